"""Incremental dissimilarity calculators, one per gesture model, packed into one bank.

See docs/online-paper.md, *Matchers: the latency search and running sums*.

For model ``j`` with descriptor samples ``a_0..a_{N-1}`` and live samples ``b_0..b_t`` the average
pointwise BILTS+ dissimilarity at latency ``ℓ`` compares the first ``N - ℓ`` model samples with the
last ``N - ℓ`` live samples:

    d_{j,ℓ}(t) = 1/(N-ℓ) Σ_{i=0}^{N-ℓ-1} δ(a_i, b_{t-N+ℓ+1+i}),   δ(A, B) = min_R ||R A - B||_F²,

and the matcher outputs ``d_j(t) = min_ℓ d_{j,ℓ}(t)`` over ``ℓ = ℓ_min..round(0.2 N)``.

Every term lies on a diagonal ``r - i = const`` of the (model × live) table, so each model keeps
one vector ``S`` of ``N`` running diagonal sums: after live sample ``t``, ``S[i]`` is the sum along
the diagonal that ends at ``(i, t)``. A new live sample ``b`` costs ``N`` Kabsch residuals,

    S_new[i] = S_old[i-1] + δ(a_i, b),   S_new[0] = δ(a_0, b),

and ``d_{j,ℓ}(t) = S[N-ℓ-1] / (N-ℓ)``, valid once ``t + 1 ≥ N - ℓ`` live samples exist. No live
sample is stored: the state is ``Σ_j N_j`` numbers. All models are packed into one array and updated
by one numba kernel (optionally multi-threaded over models).

The Kabsch residual is :func:`framefree.core.kabsch.residual_with_norms` (Horn/Theobald QCP, the one
implementation in the package) with the model norms precomputed once per model sample.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit, prange

from ...core.kabsch import residual_columns, residual_with_norms

__all__ = [
    "MatcherBank",
    "brute_force_dissimilarity",
    "latency_bounds",
    "residual18",
]


@njit(cache=True)
def residual18(a, a2, b, b2):
    """``min_{R∈SO(3)} ||R A - B||_F²`` for six 3-vectors stored flat in ``a``, ``b`` (18,).

    A thin wrapper of :func:`framefree.core.kabsch.residual_with_norms` (the one Kabsch implementation).

    Parameters
    ----------
    a, b : ndarray, shape (18,)
        Column-major 3×6 matrices.
    a2, b2 : float
        ``||a||²`` and ``||b||²``.
    """
    return residual_with_norms(a, a2, b, b2, 6)


@njit(cache=True)
def _update_model(j, A, A2, An, offsets, b, b2, bn, S, count, lat_lo, lat_hi, cut, out_d, out_l):
    o = offsets[j]
    n = offsets[j + 1] - o
    # a diagonal whose partial sum reaches bound can never give d_j < cut[j] (later terms are
    # >= 0 and the divisor is at most n - lat_lo): it is marked dead (inf) and not computed further
    bound = cut[j] * (n - lat_lo[j])
    prune = bound < np.inf
    for i in range(n - 1, -1, -1):
        prev = S[o + i - 1] if i > 0 else 0.0
        if prune:
            if prev >= bound:
                S[o + i] = np.inf
                continue
            # Kabsch residual >= sum over the 6 columns of (|a_c| - |b_c|)^2 (rotations keep norms)
            lb = prev
            for c in range(6):
                e = An[o + i, c] - bn[c]
                lb += e * e
            if lb >= bound:
                S[o + i] = np.inf
                continue
        v = prev + residual_with_norms(A[o + i], A2[o + i], b, b2, 6)
        S[o + i] = v if not (prune and v >= bound) else np.inf
    best = np.inf
    best_l = -1
    for lat in range(lat_lo[j], lat_hi[j] + 1):
        k = n - lat
        if k < 1 or count < k:
            continue
        v = S[o + k - 1] / k
        if v < best:
            best = v
            best_l = lat
    out_d[j] = best
    out_l[j] = best_l


@njit(cache=True)
def _column_norms(b):
    bn = np.empty(6)
    b2 = 0.0
    for c in range(6):
        x = b[3 * c] * b[3 * c] + b[3 * c + 1] * b[3 * c + 1] + b[3 * c + 2] * b[3 * c + 2]
        b2 += x
        bn[c] = math.sqrt(x)
    return b2, bn


@njit(cache=True)
def _update_serial(A, A2, An, offsets, b, S, count, lat_lo, lat_hi, cut, out_d, out_l):
    b2, bn = _column_norms(b)
    for j in range(offsets.shape[0] - 1):
        _update_model(j, A, A2, An, offsets, b, b2, bn, S, count, lat_lo, lat_hi, cut, out_d, out_l)


@njit(cache=True, parallel=True)
def _update_parallel(A, A2, An, offsets, b, S, count, lat_lo, lat_hi, cut, out_d, out_l):
    b2, bn = _column_norms(b)
    for j in prange(offsets.shape[0] - 1):
        _update_model(j, A, A2, An, offsets, b, b2, bn, S, count, lat_lo, lat_hi, cut, out_d, out_l)


def latency_bounds(length: int, fraction: float = 0.2, latency_min: int = 1) -> tuple[int, int]:
    """Latencies searched for a model of ``length`` samples: ``latency_min..round(fraction·length)``.

    MATLAB rounding (halves away from zero); the upper bound is at least ``latency_min`` and at most
    ``length - 1`` (at least one sample is compared).
    """
    hi = math.floor(fraction * length + 0.5)
    hi = min(max(hi, latency_min), length - 1)
    return latency_min, hi


class MatcherBank:
    """All gesture matchers in one packed state (docs/online-paper.md, *Matchers*).

    Parameters
    ----------
    descriptors : sequence of ndarray, shape (N_j, 18)
        The model descriptor sequences (``N_j ≥ 2``).
    latency_fraction : float
        Largest latency as a fraction of the model length (0.2).
    latency_min : int
        Smallest latency (1, or 0 to include the fully aligned case).
    parallel_models : int
        Use the multi-threaded kernel when there are at least this many models.
    cutoffs : array_like, shape (M,), optional
        Exact pruning: model ``j`` only needs ``d_j`` exactly when it is below ``cutoffs[j]``;
        running sums that can no longer get below it are dropped (reported ``d_j`` is then
        ``inf``), and Kabsch residuals whose column-norm lower bound already exceeds it are not
        computed. Default ``inf``: every ``d_j`` exact.

    Attributes
    ----------
    lengths : ndarray of int, shape (M,)
    count : int
        Live descriptor samples since the last reset.
    """

    def __init__(
        self,
        descriptors: Sequence[np.ndarray],
        latency_fraction: float = 0.2,
        latency_min: int = 1,
        parallel_models: int = 1000,
        cutoffs: np.ndarray | Sequence[float] | None = None,
    ) -> None:
        if len(descriptors) == 0:
            raise ValueError("at least one model is needed")
        seqs = [np.ascontiguousarray(d, dtype=np.float64) for d in descriptors]
        for j, d in enumerate(seqs):
            if d.ndim != 2 or d.shape[1] != 18 or d.shape[0] < 2:
                raise ValueError(f"model {j}: expected a (N >= 2, 18) descriptor, got {d.shape}")
        self.lengths = np.array([d.shape[0] for d in seqs], dtype=np.int64)
        self.offsets = np.concatenate([[0], np.cumsum(self.lengths)]).astype(np.int64)
        self.A = np.ascontiguousarray(np.concatenate(seqs))
        self.A2 = np.einsum("ij,ij->i", self.A, self.A)
        self.An = np.ascontiguousarray(np.linalg.norm(self.A.reshape(-1, 6, 3), axis=2))
        self.cutoffs = np.full(len(seqs), np.inf)
        if cutoffs is not None:
            self.set_cutoffs(cutoffs)
        bounds = [latency_bounds(int(n), latency_fraction, latency_min) for n in self.lengths]
        self.lat_lo = np.array([b[0] for b in bounds], dtype=np.int64)
        self.lat_hi = np.array([b[1] for b in bounds], dtype=np.int64)
        self.parallel = len(seqs) >= parallel_models
        self.S = np.zeros(self.A.shape[0])
        self.d = np.full(len(seqs), np.inf)
        self.latency = np.full(len(seqs), -1, dtype=np.int64)
        self.count = 0

    @property
    def n_models(self) -> int:
        """Number of models M."""
        return int(self.lengths.shape[0])

    def set_cutoffs(self, cutoffs: np.ndarray | Sequence[float]) -> None:
        """Per-model pruning cutoffs (M,) (``inf``: exact); takes effect for new live samples."""
        c = np.asarray(cutoffs, dtype=np.float64).reshape(-1)
        if c.shape[0] != self.n_models:
            raise ValueError(f"{c.shape[0]} cutoffs for {self.n_models} models")
        self.cutoffs = np.ascontiguousarray(c)

    def reset(self) -> None:
        """Clear all live windows and cached dissimilarities (refractory reset)."""
        self.S[:] = 0.0
        self.d[:] = np.inf
        self.latency[:] = -1
        self.count = 0

    def update(self, b: np.ndarray) -> np.ndarray:
        """Feed one live descriptor sample (18,); return ``d_j`` for every model (M,).

        ``inf`` where a matcher has not yet seen ``N_j - round(0.2 N_j)`` live samples. The best
        latency of each model is in :attr:`latency` afterwards.
        """
        b = np.ascontiguousarray(b, dtype=np.float64)
        self.count += 1
        kern = _update_parallel if self.parallel else _update_serial
        kern(self.A, self.A2, self.An, self.offsets, b, self.S, self.count, self.lat_lo, self.lat_hi,
             self.cutoffs, self.d, self.latency)
        return self.d


def brute_force_dissimilarity(
    model: np.ndarray, live: np.ndarray, latency_min: int = 1, latency_fraction: float = 0.2
) -> float:
    """``d_j(t)`` recomputed from scratch with :func:`framefree.core.kabsch.residual_columns`.

    Parameters
    ----------
    model : ndarray, shape (N, 18)
    live : ndarray, shape (t, 18)
        All live samples since the last reset, newest last.

    Returns
    -------
    float
        ``inf`` if no latency has enough live samples.
    """
    n = model.shape[0]
    lo, hi = latency_bounds(n, latency_fraction, latency_min)
    best = np.inf
    t = live.shape[0]
    for lat in range(lo, hi + 1):
        k = n - lat
        if k < 1 or t < k:
            continue
        s = sum(residual_columns(model[i], live[t - k + i], 6) for i in range(k))
        best = min(best, s / k)
    return best
