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
    accumulated_cost_kernel,
    open_end_row,
    pack_sequences,
    path_cell_cost,
    path_distance_kernel,
    traceback_step,
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


@njit(cache=True, nogil=True)
def _bounded_distance(X, Y, FX, FY, lo, hi, mode, open_end, cutoff):
    """:func:`~framefree.core.dtw.path_distance_kernel`, abandoned as soon as the distance is
    known to exceed ``cutoff``: first from the bound features ``FX`` (n, k) and ``FY`` (m, k)
    summed along the alignment path (each cell's bound is at most its cost), then from the cost
    summed along the path back from its end (every cell cost is non-negative). Returns the
    distance, or a lower bound above ``cutoff``, and whether it is exact."""
    if mode == POINTWISE_EUCLIDEAN:
        return path_distance_kernel(X, Y, lo, hi, mode, open_end), True
    C = accumulated_cost_kernel(X, Y, lo, hi)
    m = Y.shape[0]
    n = open_end_row(C) + 1 if open_end else X.shape[0]
    divisor = n + m - 1
    limit = cutoff * divisor
    bound = 0.0
    i = n - 1
    j = m - 1
    while True:
        for f in range(FX.shape[1]):
            diff = FX[i, f] - FY[j, f]
            bound += diff * diff
        if i == 0 and j == 0:
            break
        i, j = traceback_step(C, i, j)
    bound *= 1.0 - _SLACK
    if bound > limit:
        return bound / divisor, False
    total = 0.0
    i = n - 1
    j = m - 1
    while True:
        total += path_cell_cost(X, Y, i, j, mode)  # as path_distance_kernel sums it
        if total > limit:
            return max(total, bound) / divisor, False
        if i == 0 and j == 0:
            break
        i, j = traceback_step(C, i, j)
    return total / divisor, True


@njit(cache=True, parallel=True)
def _exact_chunk(qdata, qF, qS, idx, cutoffs, sdata, soff, fdata, mdata, moff, lo, hi, mode,
                 open_end, merge):
    """For each model of ``idx`` (in parallel): its merge bound (if ``merge``), and, unless that
    exceeds its ``cutoffs`` entry, its distance, abandoned past the cutoff. Returns the values
    (exact, or a lower bound above the cutoff), which are exact, and which were aligned (DTW cells
    computed)."""
    out = np.empty(idx.shape[0])
    exact = np.zeros(idx.shape[0], dtype=np.bool_)
    aligned = np.zeros(idx.shape[0], dtype=np.bool_)
    squared = mode != POINTWISE_EUCLIDEAN
    for k in prange(idx.shape[0]):
        j = idx[k]
        bound = _lower_bound(sdata[:, soff[j]:soff[j + 1]], qS, squared, open_end) if merge else 0.0
        out[k] = bound
        if bound <= cutoffs[k]:
            aligned[k] = True
            value, exact[k] = _bounded_distance(mdata[moff[j]:moff[j + 1]], qdata,
                                                fdata[moff[j]:moff[j + 1]], qF, lo, hi, mode,
                                                open_end, cutoffs[k])
            out[k] = value if exact[k] else max(value, bound)
    return out, exact, aligned


@njit(cache=True, nogil=True)
def _cutoff(j, best, values, accept_below, reject):
    """Largest bound at which model ``j`` still needs its distance: the best distance so far, and,
    while that best cannot be accepted, also below ``j``'s own threshold (a model that cannot be
    accepted cannot turn a rejection into an acceptance; it is deferred, see :func:`_search`)."""
    if best < 0:
        return np.inf
    cut = values[best]
    if reject and values[best] >= accept_below[best]:
        below = np.nextafter(accept_below[j], -np.inf)
        if below < cut:
            cut = below
    return cut


@njit(cache=True, nogil=True)
def _select(queue, k, size, first_pass, best, values, accept_below, reject, todo, cutoffs,
            deferred, n_deferred):
    """The next models of ``queue`` from position ``k`` to search (up to ``size``, into ``todo``
    with their ``cutoffs``), deferring those only their own threshold rules out. Returns the new
    position (``len(queue)`` once no later model can be nearer), how many were chosen and how
    many are deferred in all."""
    Q = queue.shape[0]
    n_todo = 0
    while k < Q and n_todo < size:
        j = queue[k]
        if best >= 0 and values[j] > values[best]:
            return Q, n_todo, n_deferred  # bounds ascend: no later model can be nearer
        k += 1
        cut = _cutoff(j, best, values, accept_below, reject) if first_pass else values[best]
        if values[j] > cut:  # only possible through its threshold: defer it
            deferred[n_deferred] = j
            n_deferred += 1
            continue
        todo[n_todo] = j
        cutoffs[n_todo] = cut
        n_todo += 1
    return k, n_todo, n_deferred


@njit(cache=True, nogil=True)
def _record(todo, d, computed, aligned, first_pass, best, values, exact, deferred, n_deferred,
            moff):
    """Take a chunk's results into ``values`` and ``exact``; a model ruled out only by its
    threshold (not by the best so far) is deferred. Returns the best model so far, how many are
    deferred, and the model samples aligned (times the query length: DTW cells)."""
    samples = 0
    for t in range(todo.shape[0]):
        j = todo[t]
        values[j] = max(values[j], d[t]) if not computed[t] else d[t]
        if aligned[t]:
            samples += moff[j + 1] - moff[j]
        if not computed[t]:
            if first_pass and best >= 0 and d[t] <= values[best]:
                deferred[n_deferred] = j  # above its threshold, not the best
                n_deferred += 1
            continue
        exact[j] = True
        if best < 0 or d[t] < values[best] or (d[t] == values[best] and j < best):
            best = j
    return best, n_deferred, samples


@njit(cache=True, nogil=True)
def _search(qdata, qF, qS, bounds, sdata, soff, fdata, mdata, moff, lo, hi, mode, open_end,
            chunk, accept_below):
    """Exact distances in the order of the cheap envelope ``bounds``, in parallel chunks that
    grow from ``chunk`` (more cores busy once the best is close), until every remaining bound
    exceeds the best distance so far — or, with acceptance thresholds, until the best so far
    cannot be accepted and no remaining model could be (its bound is at or above the largest
    threshold). A model the envelope does not rule out gets its tighter merge bound
    (:func:`_lower_bound`) and its distance only if that bound does not rule it out either; the
    distance is abandoned once it exceeds the best so far.

    While the best so far cannot be accepted, a model whose bound reaches its own threshold is
    *deferred*: it cannot be accepted, so it matters only if an acceptable model turns up that it
    might be nearer than (then the query is rejected after all). Deferred models get the plain
    rule after the main pass if the best by then is acceptable. Returns the values (exact, or a
    lower bound), which are exact, and the DTW cells computed."""
    M = bounds.shape[0]
    reject = accept_below.shape[0] == M
    top = accept_below.max() if reject and M > 0 else np.inf
    values = bounds.copy()
    exact = np.zeros(M, dtype=np.bool_)
    order = np.argsort(bounds, kind="mergesort")
    deferred = np.empty(M, dtype=np.int64)
    n_deferred = 0
    cells = 0
    best = -1  # index of the nearest model so far
    todo = np.empty(M, dtype=np.int64)
    cutoffs = np.empty(M)
    size = chunk
    tried = 0  # merge bounds computed, and how many of them ruled their model out
    ruled_out = 0
    for phase in range(2):
        queue = order if phase == 0 else deferred[:n_deferred][np.argsort(values[deferred[:n_deferred]],
                                                                         kind="mergesort")]
        if phase == 1 and (best < 0 or values[best] >= accept_below[best]):
            break  # the best cannot be accepted: deferred models cannot change that
        k = 0
        while k < queue.shape[0]:
            if (phase == 0 and reject and bounds[queue[k]] >= top
                    and (best < 0 or values[best] >= accept_below[best])):
                break  # the nearest model, whichever it is, cannot be accepted
            k, n_todo, n_deferred = _select(queue, k, size, phase == 0, best, values, accept_below,
                                            reject, todo, cutoffs, deferred, n_deferred)
            if n_todo == 0:
                continue
            merge = tried < 64 or 2 * ruled_out >= tried
            d, computed, aligned = _exact_chunk(qdata, qF, qS, todo[:n_todo], cutoffs[:n_todo],
                                                sdata, soff, fdata, mdata, moff, lo, hi, mode,
                                                open_end, merge)
            if merge:
                tried += n_todo
                ruled_out += n_todo - int(aligned[:n_todo].sum())
            best, n_deferred, added = _record(todo[:n_todo], d, computed, aligned, phase == 0, best,
                                              values, exact, deferred, n_deferred, moff)
            cells += added * qdata.shape[0]
            if size < 256:
                size *= 2
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
        #: every sample's bound features, unsorted (Σn_j, k), rows as in ``mdata``
        self.fdata = np.ascontiguousarray(np.concatenate(bounds))
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
    qF = bound_features(q, s)
    qS = _sorted_columns(qF)
    values, exact, cells = _search(q, qF, qS, _envelope(qS, bank), bank.sdata, bank.soff, bank.fdata,
                                   bank.mdata, bank.moff, s.align_lo, s.align_hi, s.mode, s.open_end,
                                   max(1, int(chunk)), tau)
    return SearchResult(values, exact, int(cells), int(bank.dtw_cells * q.shape[0]))
