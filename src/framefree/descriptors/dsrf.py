"""DSRF: Dual Square-Root Function, a global descriptor in world coordinates
(docs/algorithms/descriptors.md), with its rotation-aligned classifier distance
(docs/algorithms/dtw.md).

Descriptor (reference ``calculate_DSRF_descriptor.m``): normalize and reparameterize
(docs/algorithms/progress.md), smooth (window 3), and for k = 1..N-1 with ``ω_k`` and ``u_k`` as for
RRV: ``σ^ω_k = ω_k/(sqrt|ω_k| + 1e-10)``, ``σ^v_k = u_k/(sqrt|u_k| + 1e-10)``; output (N-1, 6).

Distance (reference ``classify_descriptor_DSRF.m``), for a model M and a query Q of equal length:

1. ``A = [σ^ω_M  σ^v_M]`` and ``B = [σ^ω_Q  σ^v_Q]`` (3 × 2(N-1) each), ``C = A Bᵀ``;
2. Kabsch: ``C = U S Vᵀ``, ``R = V Uᵀ``; if ``det R < 0`` negate the last column of U and recompute;
3. rotate the model's two 3-vector blocks by R;
4. Euclidean DTW (model first) divided by ``n_q + n_m - 1``.

World-frame invariance holds for the distance, not the descriptor.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit, prange

from ..core.dtw import accumulated_cost_kernel, pack_sequences
from .base import register
from .families import RATE_OFFSET, GlobalDescriptor

__all__ = ["DSRF", "dsrf_alignment", "dsrf_distance", "dsrf_from_rates"]


@njit(cache=True, error_model="numpy")
def dsrf_kernel(w, u):
    """DSRF (K, 6) from angular rates ``w`` (K, 3) and velocities ``u`` (K, 3)."""
    n = w.shape[0]
    out = np.empty((n, 6))
    for k in range(n):
        nw = math.sqrt(w[k, 0] ** 2 + w[k, 1] ** 2 + w[k, 2] ** 2)
        nu = math.sqrt(u[k, 0] ** 2 + u[k, 1] ** 2 + u[k, 2] ** 2)
        dw = math.sqrt(nw) + RATE_OFFSET
        du = math.sqrt(nu) + RATE_OFFSET
        for r in range(3):
            out[k, r] = w[k, r] / dw
            out[k, 3 + r] = u[k, r] / du
    return out


def dsrf_from_rates(omega: np.ndarray, u: np.ndarray) -> np.ndarray:
    """DSRF descriptor (K, 6) from angular rates (K, 3) and velocities (K, 3)
    (docs/algorithms/descriptors.md)."""
    return dsrf_kernel(
        np.ascontiguousarray(omega, dtype=np.float64), np.ascontiguousarray(u, dtype=np.float64)
    )


@njit(cache=True)
def alignment_kernel(M, Q):
    """Kabsch rotation R (3, 3) minimizing ``||R A - B||`` for DSRF sequences M, Q (K, 6)."""
    C = np.zeros((3, 3))
    for k in range(M.shape[0]):
        for r in range(3):
            for s in range(3):
                C[r, s] += M[k, r] * Q[k, s] + M[k, 3 + r] * Q[k, 3 + s]
    U, _, Vt = np.linalg.svd(C)
    R = Vt.T @ U.T
    if np.linalg.det(R) < 0.0:
        for r in range(3):
            U[r, 2] = -U[r, 2]
        R = Vt.T @ U.T
    return R


@njit(cache=True)
def dsrf_distance_kernel(M, Q):
    """Aligned DTW distance between model M (n, 6) and query Q (n, 6), normalized."""
    R = alignment_kernel(M, Q)
    n = M.shape[0]
    Mr = np.empty((n, 6))
    for k in range(n):
        for b in range(2):
            for r in range(3):
                Mr[k, 3 * b + r] = (
                    R[r, 0] * M[k, 3 * b] + R[r, 1] * M[k, 3 * b + 1] + R[r, 2] * M[k, 3 * b + 2]
                )
    m = Q.shape[0]
    C = accumulated_cost_kernel(Mr, Q, 0, 6)
    return C[n - 1, m - 1] / (n + m - 1)


@njit(cache=True, parallel=True)
def dsrf_distance_matrix_kernel(qdata, qoff, mdata, moff):
    """Aligned distances between every packed query and model, shape (n_queries, n_models)."""
    nq = qoff.shape[0] - 1
    nm = moff.shape[0] - 1
    out = np.empty((nq, nm))
    for t in prange(nq * nm):
        a = t // nm
        b = t % nm
        out[a, b] = dsrf_distance_kernel(mdata[moff[b] : moff[b + 1]], qdata[qoff[a] : qoff[a + 1]])
    return out


def _check_pair(model: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    M = np.ascontiguousarray(model, dtype=np.float64)
    Q = np.ascontiguousarray(query, dtype=np.float64)
    if M.ndim != 2 or Q.ndim != 2 or M.shape[1] != 6 or Q.shape[1] != 6:
        raise ValueError(f"DSRF sequences must have shape (K, 6), got {M.shape} and {Q.shape}")
    if M.shape[0] != Q.shape[0]:
        raise ValueError(
            f"DSRF alignment pairs samples by index and needs equal lengths, got {M.shape[0]} "
            f"and {Q.shape[0]}"
        )
    return M, Q


def dsrf_alignment(model: np.ndarray, query: np.ndarray) -> np.ndarray:
    """The rotation R (3, 3) that best maps the model's 3-vectors onto the query's (docs/algorithms/dtw.md).

    Parameters
    ----------
    model, query : ndarray, shape (K, 6)
        DSRF sequences of equal length.
    """
    M, Q = _check_pair(model, query)
    return alignment_kernel(M, Q)


def dsrf_distance(model: np.ndarray, query: np.ndarray) -> float:
    """DSRF classifier distance (docs/algorithms/dtw.md) between a model and a query sequence (K, 6) each."""
    M, Q = _check_pair(model, query)
    return float(dsrf_distance_kernel(M, Q))


@register
class DSRF(GlobalDescriptor):
    """Dual Square-Root Function (docs/algorithms/descriptors.md) with the globally rotation-aligned
    DTW distance (docs/algorithms/dtw.md).

    Parameters
    ----------
    progress : {"arclength", "angle", "screw"}
        Progress type (default "screw").
    L : float
        Scale length [m], screw progress only (default 0.5).
    n_samples : int
        Number of progress samples (50).

    Notes
    -----
    Output (n_samples - 1, 6): ``[σ^ω, σ^v]`` in world coordinates. The descriptor itself is not
    world-frame invariant; the distance is (up to a world rotation). Not body-frame invariant.
    """

    name = "dsrf"
    display_name = "DSRF"
    n_features = 6

    def from_rates(self, omega: np.ndarray, u: np.ndarray) -> np.ndarray:
        """DSRF (K, 6) from normalized rates."""
        return dsrf_from_rates(omega, u)

    def prealign(self, model: np.ndarray, query: np.ndarray) -> np.ndarray:
        """The model rotated by the distance's global Kabsch rotation onto the query."""
        if model.shape != query.shape or model.shape[1] != 6:
            return model
        R = dsrf_alignment(model, query)
        return np.hstack([model[:, :3] @ R.T, model[:, 3:] @ R.T])

    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """Rotation-aligned Euclidean DTW distances (docs/algorithms/dtw.md).

        Returns
        -------
        ndarray, shape (n_queries, n_models)

        Raises
        ------
        ValueError
            If the sequences do not all have the same length (the alignment pairs samples by index).
        """
        qd, qo = pack_sequences(list(queries))
        md, mo = pack_sequences(list(models))
        if qd.shape[1] != 6 or md.shape[1] != 6:
            raise ValueError("DSRF sequences have 6 columns")
        lengths = set(np.diff(qo).tolist()) | set(np.diff(mo).tolist())
        if len(lengths) != 1:
            raise ValueError(
                "DSRF alignment pairs samples by index and needs equal lengths, "
                f"got {sorted(lengths)}"
            )
        return dsrf_distance_matrix_kernel(qd, qo, md, mo)
