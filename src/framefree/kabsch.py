"""Optimal rotation alignment of two sets of 3-vectors (the Kabsch problem), as a residual.

BILTS+ compares two descriptor samples after rotating one onto the other (§6.6):
``δ(A, B) = min_{R ∈ SO(3)} ||R A - B||_F²`` for 3×k matrices A, B. Only the residual is needed, so
instead of a 3×3 SVD per pair we use Horn's quaternion formulation: the maximum of ``tr(R A Bᵀ)`` over
rotations is the largest eigenvalue λ of a symmetric, traceless 4×4 matrix built from ``M = A Bᵀ``, and

    δ = ||A||² + ||B||² − 2 λ.

λ is found by Newton's method on the characteristic quartic, started from the upper bound
``(||A||² + ||B||²)/2`` (Theobald's QCP method). This equals the SVD solution with the determinant fix
(``σ₁ + σ₂ + sign(det M) σ₃``) and costs a few dozen flops.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["kabsch_residual", "kabsch_rotation", "max_rotation_trace"]


@njit(cache=True)
def _det3(a00, a01, a02, a10, a11, a12, a20, a21, a22):
    return a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20)


@njit(cache=True)
def max_rotation_trace_from_m(M, e0):
    """``max_R tr(R M)`` over proper rotations, for a 3×3 correlation ``M``; ``e0`` bounds it by 2×."""
    sxx, sxy, sxz = M[0, 0], M[0, 1], M[0, 2]
    syx, syy, syz = M[1, 0], M[1, 1], M[1, 2]
    szx, szy, szz = M[2, 0], M[2, 1], M[2, 2]
    N = np.empty((4, 4))
    N[0, 0] = sxx + syy + szz
    N[0, 1] = syz - szy
    N[0, 2] = szx - sxz
    N[0, 3] = sxy - syx
    N[1, 1] = sxx - syy - szz
    N[1, 2] = sxy + syx
    N[1, 3] = szx + sxz
    N[2, 2] = -sxx + syy - szz
    N[2, 3] = syz + szy
    N[3, 3] = -sxx - syy + szz
    for i in range(4):
        for j in range(i):
            N[i, j] = N[j, i]
    # characteristic polynomial λ⁴ + c2 λ² + c1 λ + c0 of the traceless symmetric N
    p2 = 0.0
    for i in range(4):
        for j in range(4):
            p2 += N[i, j] * N[i, j]
    N2 = N @ N
    p3 = 0.0
    for i in range(4):
        for j in range(4):
            p3 += N2[i, j] * N[j, i]
    c2 = -0.5 * p2
    c1 = -p3 / 3.0
    # det(N) by expansion along the first row
    c0 = (
        N[0, 0] * _det3(N[1, 1], N[1, 2], N[1, 3], N[2, 1], N[2, 2], N[2, 3], N[3, 1], N[3, 2], N[3, 3])
        - N[0, 1] * _det3(N[1, 0], N[1, 2], N[1, 3], N[2, 0], N[2, 2], N[2, 3], N[3, 0], N[3, 2], N[3, 3])
        + N[0, 2] * _det3(N[1, 0], N[1, 1], N[1, 3], N[2, 0], N[2, 1], N[2, 3], N[3, 0], N[3, 1], N[3, 3])
        - N[0, 3] * _det3(N[1, 0], N[1, 1], N[1, 2], N[2, 0], N[2, 1], N[2, 2], N[3, 0], N[3, 1], N[3, 2])
    )
    lam = 0.5 * e0
    if lam <= 0.0:
        return 0.0
    for _ in range(60):
        lam2 = lam * lam
        f = (lam2 + c2) * lam2 + c1 * lam + c0
        df = 4.0 * lam2 * lam + 2.0 * c2 * lam + c1
        if df <= 0.0:
            break
        lam_new = lam - f / df
        if not lam_new < lam:  # Newton decreases monotonically from above; stop when it stalls
            break
        done = lam - lam_new <= 1e-15 * abs(lam_new)
        lam = lam_new
        if done:
            break
    return lam


@njit(cache=True)
def residual_columns(a, b, ncols):
    """δ for two flat vectors holding ``ncols`` consecutive 3-vectors each (column-major 3×ncols)."""
    M = np.zeros((3, 3))
    e0 = 0.0
    for c in range(ncols):
        for r in range(3):
            ar = a[3 * c + r]
            e0 += ar * ar + b[3 * c + r] * b[3 * c + r]
            for s in range(3):
                M[r, s] += ar * b[3 * c + s]
    lam = max_rotation_trace_from_m(M, e0)
    res = e0 - 2.0 * lam
    return res if res > 0.0 else 0.0


@njit(cache=True)
def _residual_batch(a, b, ncols):
    out = np.empty(a.shape[0])
    for i in range(a.shape[0]):
        out[i] = residual_columns(a[i], b[i], ncols)
    return out


def kabsch_residual(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``min_{R ∈ SO(3)} ||R A − B||_F²`` for stacks of 3×k matrices.

    Parameters
    ----------
    A, B : ndarray, shape (..., 3, k)

    Returns
    -------
    ndarray, shape (...)
    """
    A = np.asarray(A, dtype=np.float64)
    B = np.asarray(B, dtype=np.float64)
    A, B = np.broadcast_arrays(A, B)
    if A.shape[-2] != 3:
        raise ValueError(f"expected matrices of shape (..., 3, k), got {A.shape}")
    k = A.shape[-1]
    lead = A.shape[:-2]
    fa = np.ascontiguousarray(np.swapaxes(A, -1, -2)).reshape(-1, 3 * k)
    fb = np.ascontiguousarray(np.swapaxes(B, -1, -2)).reshape(-1, 3 * k)
    return _residual_batch(fa, fb, k).reshape(lead)


def max_rotation_trace(M: np.ndarray) -> float:
    """``max_{R ∈ SO(3)} tr(R M)`` for one 3×3 matrix (the signed sum of its singular values)."""
    M = np.ascontiguousarray(M, dtype=np.float64)
    # λ_max(N) <= ||N||_F = 2 ||M||_F, and the kernel starts Newton at e0 / 2
    return float(max_rotation_trace_from_m(M, 4.0 * float(np.linalg.norm(M))))


def kabsch_rotation(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """The rotation R (3, 3) minimizing ``||R A − B||_F`` (SVD with the determinant fix, §6.4)."""
    C = np.asarray(A, dtype=np.float64) @ np.asarray(B, dtype=np.float64).T
    U, _, Vt = np.linalg.svd(C)
    R = Vt.T @ U.T
    if np.linalg.det(R) < 0:
        U[:, -1] *= -1
        R = Vt.T @ U.T
    return R

