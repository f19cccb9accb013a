"""Exact pruning of nearest-neighbour search under framefree's DTW distances.

A distance between a model ``X`` (n, F) and a query ``Y`` (m, F) (:func:`~framefree.core.dtw.
path_distance_kernel`) sums a non-negative cell cost ``r(i, j)`` along a monotone warping path
from ``(0, 0)``: to ``(n−1, m−1)``, or, open-ended, to ``(i_end, m−1)`` for some ``i_end``; and
divides by ``n + m − 1`` (or ``i_end + m ≤ n + m − 1``). Every such path visits every query
sample ``j``, and a closed path also every model sample ``i``, so for any cell lower bound
``c(i, j) ≤ r(i, j)``::

    distance ≥ max(Σ_i min_j c(i, j), Σ_j min_i c(i, j)) / (n + m − 1)     (closed end)
    distance ≥ Σ_j min_i c(i, j) / (n + m − 1)                              (open end)

The cell bounds come from per-sample *bound features* ``b`` with ``c(i, j) ≥ Σ_f (b_if − b'_jf)²``
(squared costs) or ``≥ ‖b_i − b'_j‖`` (Euclidean costs), and ``min_j`` of a sum is at least the
sum of the per-feature minima, each found by a binary search in the sorted feature — an
``O((n + m) · F · log)`` bound in place of an ``O(n · m)`` alignment (the LB_Keogh idea without a
warping window, per feature).

Bound features per distance (``mode`` of :mod:`framefree.core.dtw`):

``POINTWISE_KABSCH`` (BILTS+) and ``POINTWISE_SQUARED`` (BILTS)
    the singular values of the rotational and of the translational 3×3 block of the six twist
    vectors. By von Neumann's trace inequality ``max_R tr(R M) ≤ Σ_k σ_k(A) σ_k(B)`` for ``M = Bᵀ A``,
    so the Kabsch residual ``min_R ‖R A − B‖²`` of each block, and so of both blocks under one
    rotation, is at least ``Σ_k (σ_k(A) − σ_k(B))²``; the plain squared difference is at least the
    Kabsch residual (``R = I``).
``POINTWISE_EUCLIDEAN``
    the aligned columns themselves (the cell cost is their Euclidean distance).

Search (:func:`pruned_nearest`): bounds of all models, then exact distances in the order of the
bounds until the next bound exceeds the best distance so far. The nearest model, its exact
distance and therefore every 1-NN decision are those of the full search (ties: the first model in
order, as ``numpy.argmin``); pruned models report their bound, which exceeds the nearest distance.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from .dtw import (
    POINTWISE_EUCLIDEAN,
    POINTWISE_KABSCH,
    POINTWISE_SQUARED,
    pack_sequences,
    path_distance_kernel,
)

__all__ = [
    "DistanceSpec",
    "ModelBank",
    "SearchResult",
    "bound_features",
    "envelope_bounds",
    "lower_bounds",
    "pruned_nearest",
]

#: relative slack on a bound, so that rounding in its float arithmetic never makes it exceed the
#: exact distance
_SLACK = 1e-9


@dataclass(frozen=True)
class DistanceSpec:
    """How a descriptor's distance is computed (:func:`~framefree.core.dtw.path_distance_kernel`).

    Attributes
    ----------
    align_lo, align_hi : int
        Feature columns DTW aligns on (``align_hi`` 0: up to the last column).
    mode : int
        ``POINTWISE_EUCLIDEAN``, ``POINTWISE_SQUARED`` or ``POINTWISE_KABSCH``.
    open_end : bool
        Open-end alignment.
    """

    align_lo: int
    align_hi: int
    mode: int
    open_end: bool

    @property
    def squared(self) -> bool:
        return self.mode != POINTWISE_EUCLIDEAN

    def resolved(self, n_features: int) -> DistanceSpec:
        """The same with ``align_hi`` set for sequences of ``n_features`` columns."""
        hi = self.align_hi if self.align_hi > 0 else n_features
        return DistanceSpec(self.align_lo, hi, self.mode, self.open_end)


def _block_singular_values(X: np.ndarray) -> np.ndarray:
    """(n, 6): ascending singular values of the rotational (twist vectors 0, 2, 4) and the
    translational (1, 3, 5) 3×3 block of each sample's six 3-vectors (columns 0–17)."""
    vectors = X[:, :18].reshape(-1, 6, 3)  # (n, vector, xyz)
    blocks = np.stack([vectors[:, 0::2], vectors[:, 1::2]], axis=1)  # (n, 2, 3 vectors, 3)
    s = np.linalg.svd(blocks, compute_uv=False)[..., ::-1]  # (n, 2, 3), ascending
    return np.ascontiguousarray(s.reshape(-1, 6))


def bound_features(seq: np.ndarray, spec: DistanceSpec) -> np.ndarray:
    """Per-sample bound features (n, k) of a descriptor sequence (n, F) (module docstring)."""
    seq = np.ascontiguousarray(seq, dtype=np.float64)
    if spec.mode in (POINTWISE_KABSCH, POINTWISE_SQUARED):
        return _block_singular_values(seq)
    return np.ascontiguousarray(seq[:, spec.align_lo:spec.align_hi])


@njit(cache=True, nogil=True)
def _sorted_columns(B):
    out = np.empty((B.shape[1], B.shape[0]))
    for f in range(B.shape[1]):
        out[f] = np.sort(B[:, f])
    return out


@njit(cache=True)
def _side_sum(SA, SB, squared):
    """Bound of ``Σ_i min_j c(i, j)`` from per-feature sorted samples ``SA`` (k, n) and ``SB``
    (k, m), by one merge per feature.

    Squared costs: ``Σ_i Σ_f min_j (a_if − b_jf)²`` (the order of the sums does not matter).
    Euclidean costs: ``Σ_i sqrt(Σ_f e_if) ≥ Σ_f Σ_i sqrt(e_if) / sqrt(k)`` (Cauchy–Schwarz).
    """
    k, n = SA.shape
    m = SB.shape[1]
    total = 0.0
    for f in range(k):
        p = 0
        for i in range(n):
            x = SA[f, i]
            while p + 1 < m and SB[f, p + 1] <= x:
                p += 1
            d = abs(x - SB[f, p])
            if p + 1 < m:
                e = abs(SB[f, p + 1] - x)
                if e < d:
                    d = e
            total += d * d if squared else d
    return total if squared else total / np.sqrt(k)


@njit(cache=True)
def _lower_bound(Sm, Sq, squared, open_end):
    n = Sm.shape[1]
    m = Sq.shape[1]
    best = _side_sum(Sq, Sm, squared)
    if not open_end:
        rows = _side_sum(Sm, Sq, squared)
        if rows > best:
            best = rows
    return best / (n + m - 1) * (1.0 - _SLACK)


@njit(cache=True)
def _envelope_sum(qS, lo, hi, squared):
    """Bound of ``Σ_j min_i c(i, j)`` from the model's per-feature range ``[lo_f, hi_f]`` (k,)
    alone: every model sample lies in it, so a query value ``v`` costs at least its squared (or
    plain) distance to the range. With the query's values sorted per feature (``qS``, (k, m)),
    only the values outside the range are visited; each term is at most the merge bound's (the
    same subtraction, of a nearer or equal number), so rounding never lifts it above."""
    k, m = qS.shape
    total = 0.0
    for f in range(k):
        row = qS[f]
        i = 0
        while i < m and row[i] < lo[f]:
            d = lo[f] - row[i]
            total += d * d if squared else d
            i += 1
        i = m - 1
        while i >= 0 and row[i] > hi[f]:
            d = row[i] - hi[f]
            total += d * d if squared else d
            i -= 1
    return total if squared else total / np.sqrt(k)


@njit(cache=True, parallel=True, nogil=True)
def _envelope_kernel(lo, hi, lengths, qS, squared):
    M = lo.shape[0]
    m = qS.shape[1]
    out = np.empty(M)
    for j in prange(M):
        out[j] = _envelope_sum(qS, lo[j], hi[j], squared) / (lengths[j] + m - 1) * (1.0 - _SLACK)
    return out


@njit(cache=True, parallel=True, nogil=True)
def _lower_bounds_kernel(sdata, soff, qS, squared, open_end):
    M = soff.shape[0] - 1
    out = np.empty(M)
    for j in prange(M):
        out[j] = _lower_bound(sdata[:, soff[j]:soff[j + 1]], qS, squared, open_end)
    return out


@njit(cache=True, parallel=True)
def _exact_chunk(qdata, qS, idx, cutoff, sdata, soff, mdata, moff, lo, hi, mode, open_end):
    """For each model of ``idx`` (in parallel): its merge bound, and, unless that exceeds
    ``cutoff``, its exact distance. Returns the values and which are exact."""
    out = np.empty(idx.shape[0])
    exact = np.zeros(idx.shape[0], dtype=np.bool_)
    squared = mode != POINTWISE_EUCLIDEAN
    for k in prange(idx.shape[0]):
        j = idx[k]
        out[k] = _lower_bound(sdata[:, soff[j]:soff[j + 1]], qS, squared, open_end)
        if out[k] <= cutoff:
            out[k] = path_distance_kernel(mdata[moff[j]:moff[j + 1]], qdata, lo, hi, mode,
                                          open_end)
            exact[k] = True
    return out, exact


@njit(cache=True, nogil=True)
def _search(qdata, qS, bounds, sdata, soff, mdata, moff, lo, hi, mode, open_end, chunk,
            accept_below):
    """Exact distances in the order of the cheap envelope ``bounds``, ``chunk`` at a time (in
    parallel), until every remaining bound exceeds the best distance so far — or, with acceptance
    thresholds, until the best so far cannot be accepted and no remaining model could be (its
    bound is at or above the largest threshold). A model the envelope does not rule out gets its
    tighter merge bound (:func:`_lower_bound`) in the parallel chunk, and its exact distance only
    if that bound does not rule it out either. Returns the values (exact, or a lower bound),
    which are exact, and the DTW cells computed."""
    M = bounds.shape[0]
    reject = accept_below.shape[0] == M
    top = accept_below.max() if reject and M > 0 else np.inf
    values = bounds.copy()
    exact = np.zeros(M, dtype=np.bool_)
    order = np.argsort(bounds, kind="mergesort")
    cells = 0
    k = 0
    todo = np.empty(chunk, dtype=np.int64)
    best = -1  # index of the nearest model so far
    while k < M:
        if reject and bounds[order[k]] >= top and (best < 0 or values[best] >= accept_below[best]):
            break  # the nearest model, whichever it is, cannot be accepted
        n_todo = 0
        while k < M and n_todo < chunk:
            j = order[k]
            if best >= 0 and bounds[j] > values[best]:
                k = M  # bounds ascend: no later model can be nearer
                break
            k += 1
            todo[n_todo] = j
            n_todo += 1
        if n_todo == 0:
            break
        cutoff = np.inf if best < 0 else values[best]
        d, computed = _exact_chunk(qdata, qS, todo[:n_todo], cutoff, sdata, soff, mdata, moff, lo,
                                   hi, mode, open_end)
        for t in range(n_todo):
            j = todo[t]
            if not computed[t]:  # ruled out by its merge bound
                values[j] = max(values[j], d[t])
                continue
            values[j] = d[t]
            exact[j] = True
            cells += (moff[j + 1] - moff[j]) * qdata.shape[0]
            if best < 0 or d[t] < values[best] or (d[t] == values[best] and j < best):
                best = j
    return values, exact, cells


class ModelBank:
    """Models packed once for pruned search: their sequences and bound features.

    Parameters
    ----------
    models : sequence of ndarray, each (n_j, F)
        Model descriptor sequences.
    spec : DistanceSpec
        How their distance is computed.
    """

    def __init__(self, models: Sequence[np.ndarray], spec: DistanceSpec) -> None:
        self.mdata, self.moff = pack_sequences(list(models))
        spec = spec.resolved(self.mdata.shape[1])
        self.spec = spec
        bounds = [bound_features(m, spec) for m in models]
        self.sdata = np.ascontiguousarray(np.concatenate([_sorted_columns(b) for b in bounds], axis=1))
        self.soff = np.concatenate([[0], np.cumsum([b.shape[0] for b in bounds])]).astype(np.int64)
        #: each model's per-feature range of bound features (M, k) and its length (M,)
        self.low = np.ascontiguousarray(self.sdata[:, self.soff[:-1]].T)
        self.high = np.ascontiguousarray(self.sdata[:, self.soff[1:] - 1].T)
        self.lengths = np.diff(self.moff)
        self.dtw_cells = sum(int(m.shape[0]) for m in models)  # times the query length

    def __len__(self) -> int:
        return self.moff.shape[0] - 1


@dataclass(frozen=True)
class SearchResult:
    """Outcome of a pruned search for one query.

    Attributes
    ----------
    values : ndarray, shape (M,)
        Exact distance of every model whose distance was computed, a lower bound of every other.
    exact : ndarray of bool, shape (M,)
        Which values are exact.
    cells : int
        DTW cells computed (model length × query length, summed over exact distances).
    full_cells : int
        DTW cells an unpruned search computes.
    """

    values: np.ndarray
    exact: np.ndarray
    cells: int
    full_cells: int

    @property
    def nearest(self) -> int:
        """Index of the nearest model (the first of equal distances, as ``numpy.argmin``)."""
        return int(np.argmin(self.values))


def lower_bounds(query: np.ndarray, bank: ModelBank) -> np.ndarray:
    """Lower bounds (M,) of the distances from ``query`` (m, F) to every model of ``bank``."""
    qS = _sorted_columns(bound_features(query, bank.spec))
    return _lower_bounds_kernel(bank.sdata, bank.soff, qS, bank.spec.squared, bank.spec.open_end)


def envelope_bounds(query: np.ndarray, bank: ModelBank) -> np.ndarray:
    """Cheaper, looser lower bounds (M,) than :func:`lower_bounds`: each model's samples are
    replaced by the range of their bound features, ``O(k · outside)`` per model instead of a merge
    of both sequences. The search orders the models by these."""
    q = np.ascontiguousarray(query, dtype=np.float64)
    return _envelope(_sorted_columns(bound_features(q, bank.spec)), bank)


def _envelope(qS: np.ndarray, bank: ModelBank) -> np.ndarray:
    return _envelope_kernel(bank.low, bank.high, bank.lengths, qS, bank.spec.squared)


def pruned_nearest(query: np.ndarray, bank: ModelBank, chunk: int = 8,
                   accept_below: np.ndarray | None = None) -> SearchResult:
    """The exact nearest model, the others pruned by their lower bounds where possible.

    Parameters
    ----------
    query : ndarray, shape (m, F)
    bank : ModelBank
    chunk : int
        Exact distances computed together (in parallel) before the bounds are compared with the
        best distances again; larger chunks use more cores and prune a little less.
    accept_below : ndarray, shape (M,), optional
        1-NN with rejection: the query is accepted only if its nearest model ``j`` is nearer than
        ``accept_below[j]``. The search then also stops once the best model so far cannot be
        accepted and every remaining bound is at or above ``max(accept_below)``: the query is
        rejected whichever model is nearest. The decision (accepted, and then the nearest model
        and its distance) is still exact; for a rejected query ``nearest`` may be a pruned model.

    Returns
    -------
    SearchResult
    """
    q = np.ascontiguousarray(query, dtype=np.float64)
    if q.ndim != 2 or q.shape[1] != bank.mdata.shape[1]:
        raise ValueError(f"query of shape {q.shape}; the models have {bank.mdata.shape[1]} columns")
    s = bank.spec
    tau = np.zeros(0) if accept_below is None else np.ascontiguousarray(accept_below, dtype=np.float64)
    if tau.size and tau.shape != (len(bank),):
        raise ValueError(f"accept_below needs one threshold per model ({len(bank)}), got {tau.shape}")
    qS = _sorted_columns(bound_features(q, s))
    values, exact, cells = _search(q, qS, _envelope(qS, bank), bank.sdata, bank.soff, bank.mdata, bank.moff,
                                   s.align_lo, s.align_hi, s.mode, s.open_end, max(1, int(chunk)),
                                   tau)
    return SearchResult(values, exact, int(cells), int(bank.dtw_cells * q.shape[0]))
