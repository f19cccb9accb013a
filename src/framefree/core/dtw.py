"""Dynamic time warping as the reference uses it (MATLAB ``dtw(X, Y)``, docs/algorithms/dtw.md), in numba.

* local cost: Euclidean distance between feature vectors (not squared);
* steps (1,1), (1,0), (0,1), all of weight 1, no window;
* traceback from the last cell with the reference's tie rule: the diagonal wins unless it is worse
  than both alternatives; between a pure model step and a pure query step an exact tie prefers the
  model step.

Sequences are arrays with **time leading**: shape (n, features). The model is the first argument.

The BILTS distances (docs/algorithms/dtw.md) align with DTW on the singular-value features (columns 18–23)
and then sum another pointwise quantity along the warping path; those kernels live here too so
that one path traversal does both.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .kabsch import residual_columns

__all__ = [
    "accumulated_cost",
    "dtw_distance",
    "pack_sequences",
    "warping_path",
]


@njit(cache=True)
def accumulated_cost_kernel(X, Y, lo, hi):
    """Accumulated DTW cost matrix (n, m) with Euclidean local cost over feature columns lo..hi-1.

    The columns are copied out first, and six of them (what every framefree descriptor aligns on)
    take a loop of a length the compiler knows: 1.6 times faster, the same sums in the same order.
    """
    n = X.shape[0]
    m = Y.shape[0]
    C = np.empty((n, m))
    A = np.ascontiguousarray(X[:, lo:hi])
    B = np.ascontiguousarray(Y[:, lo:hi])
    width = hi - lo
    six = width == 6
    for i in range(n):
        for j in range(m):
            d = 0.0
            if six:
                for f in range(6):
                    diff = A[i, f] - B[j, f]
                    d += diff * diff
            else:
                for f in range(width):
                    diff = A[i, f] - B[j, f]
                    d += diff * diff
            d = math.sqrt(d)
            if i == 0 and j == 0:
                C[i, j] = d
            elif i == 0:
                C[i, j] = d + C[i, j - 1]
            elif j == 0:
                C[i, j] = d + C[i - 1, j]
            else:
                best = C[i - 1, j - 1]
                if C[i - 1, j] < best:
                    best = C[i - 1, j]
                if C[i, j - 1] < best:
                    best = C[i, j - 1]
                C[i, j] = d + best
    return C


@njit(cache=True)
def traceback_step(C, i, j):
    """One step back from cell (i, j) of the accumulated cost ``C`` with the reference tie rule."""
    if j == 0:
        return i - 1, j
    if i == 0:
        return i, j - 1
    cd = C[i - 1, j - 1]
    ci = C[i - 1, j]
    cj = C[i, j - 1]
    step_i = ci <= cj or cd <= cj
    step_j = cj < ci or cd <= ci
    return (i - 1 if step_i else i), (j - 1 if step_j else j)


@njit(cache=True)
def warping_path_kernel(C):
    """Traceback of an accumulated cost matrix with the reference tie rule; (L, 2) from start to end."""
    n, m = C.shape
    path = np.empty((n + m - 1, 2), dtype=np.int64)
    i = n - 1
    j = m - 1
    k = 0
    path[k, 0] = i
    path[k, 1] = j
    while i > 0 or j > 0:
        i, j = traceback_step(C, i, j)
        k += 1
        path[k, 0] = i
        path[k, 1] = j
    return path[k::-1].copy()


def _as_seq(x: np.ndarray, name: str) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[0] == 0:
        raise ValueError(f"{name} must be a non-empty (n, features) array, got shape {x.shape}")
    return np.ascontiguousarray(x)


def accumulated_cost(model: np.ndarray, query: np.ndarray) -> np.ndarray:
    """DTW accumulated cost matrix (n_model, n_query), Euclidean local cost."""
    X = _as_seq(model, "model")
    Y = _as_seq(query, "query")
    if X.shape[1] != Y.shape[1]:
        raise ValueError(f"feature counts differ: {X.shape[1]} vs {Y.shape[1]}")
    return accumulated_cost_kernel(X, Y, 0, X.shape[1])


def warping_path(model: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Optimal warping path (L, 2) of (model index, query index) pairs, from (0, 0) to the end."""
    return warping_path_kernel(accumulated_cost(model, query))


def dtw_distance(model: np.ndarray, query: np.ndarray) -> float:
    """DTW distance: the accumulated Euclidean cost of the optimal path (not normalized)."""
    return float(accumulated_cost(model, query)[-1, -1])


# --------------------------------------------------------------------------------------------------
# Path distances of the descriptors (one traversal: align, then sum another pointwise quantity)
# --------------------------------------------------------------------------------------------------

#: pointwise quantities summed along the path
POINTWISE_EUCLIDEAN = 0  # DTW cost itself (DHB, eFS, ISA, RRV, DSRF)
POINTWISE_SQUARED = 1  # squared Euclidean over columns 0..17 (BILTS)
POINTWISE_KABSCH = 2  # Kabsch residual over the six 3-vectors in columns 0..17 (BILTS+)


@njit(cache=True)
def open_end_row(C):
    """Model row where an open-end alignment stops: ``argmin_i C[i, m-1] / (i + m)``.

    ``C`` is an accumulated cost (n_model, m_query). The query must be used up (last column) but
    may end at any model sample ``i``; dividing by ``i + m`` (the largest number of cells a path
    from (0, 0) to (i, m-1) can visit, minus one) makes the cost an average per step, so a short
    prefix is neither favoured (fewer terms) nor punished (more terms) for its length.
    """
    n, m = C.shape
    best = 0
    best_cost = C[0, m - 1] / m
    for i in range(1, n):
        c = C[i, m - 1] / (i + m)
        if c < best_cost:
            best = i
            best_cost = c
    return best


@njit(cache=True)
def path_distance_kernel(X, Y, align_lo, align_hi, mode, open_end):
    """Normalized path distance between model X (n, F) and query Y (m, F).

    DTW on columns ``align_lo..align_hi-1``; then, depending on ``mode``, either the accumulated cost
    itself, or the sum along the path of a pointwise quantity on columns 0..17; divided by
    ``n + m - 1``. With ``open_end`` the path ends at the model sample chosen by
    :func:`open_end_row` (``i_end``) instead of the last one, and the divisor is ``i_end + m``.
    """
    C = accumulated_cost_kernel(X, Y, align_lo, align_hi)
    m = Y.shape[0]
    n = open_end_row(C) + 1 if open_end else X.shape[0]
    if mode == POINTWISE_EUCLIDEAN:
        return C[n - 1, m - 1] / (n + m - 1)
    total = 0.0
    i = n - 1
    j = m - 1
    while True:
        total += path_cell_cost(X, Y, i, j, mode)
        if i == 0 and j == 0:
            break
        i, j = traceback_step(C, i, j)
    return total / (n + m - 1)


@njit(cache=True)
def path_cell_cost(X, Y, i, j, mode):
    """Cost of cell (i, j) on the path of :func:`path_distance_kernel` (``POINTWISE_SQUARED`` or
    ``POINTWISE_KABSCH``): the squared difference of columns 0..17, or their Kabsch residual."""
    if mode == POINTWISE_SQUARED:
        d = 0.0
        for f in range(18):
            diff = X[i, f] - Y[j, f]
            d += diff * diff
        return d
    return residual_columns(X[i], Y[j], 6)


@njit(cache=True, parallel=True, nogil=True)
def path_distance_matrix_kernel(qdata, qoff, mdata, moff, align_lo, align_hi, mode, open_end):
    """Distances between every packed query and every packed model, shape (n_queries, n_models)."""
    nq = qoff.shape[0] - 1
    nm = moff.shape[0] - 1
    out = np.empty((nq, nm))
    for t in prange(nq * nm):
        a = t // nm
        b = t % nm
        out[a, b] = path_distance_kernel(
            mdata[moff[b] : moff[b + 1]],
            qdata[qoff[a] : qoff[a + 1]],
            align_lo,
            align_hi,
            mode,
            open_end,
        )
    return out


def pack_sequences(seqs: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate sequences (n_i, F) into one array (Σn_i, F) with offsets (len+1,)."""
    if not seqs:
        raise ValueError("no sequences to pack")
    arrs = [np.asarray(s, dtype=np.float64) for s in seqs]
    width = arrs[0].shape[1]
    for a in arrs:
        if a.ndim != 2 or a.shape[1] != width or a.shape[0] == 0:
            raise ValueError(f"all sequences must be non-empty (n, {width}) arrays, got {a.shape}")
    offsets = np.zeros(len(arrs) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([a.shape[0] for a in arrs])
    return np.ascontiguousarray(np.concatenate(arrs, axis=0)), offsets
