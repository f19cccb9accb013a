"""Optimal rotation alignment of two sets of 3-vectors (the Kabsch problem), as a residual.

BILTS+ compares two descriptor samples after rotating one onto the other (docs/algorithms/dtw.md):
``δ(A, B) = min_{R ∈ SO(3)} ||R A - B||_F²`` for 3×k matrices A, B. Only the residual is needed, so
instead of a 3×3 SVD per pair we use Horn's quaternion formulation: the maximum of ``tr(R A Bᵀ)`` over
rotations is the largest eigenvalue λ of a symmetric, traceless 4×4 matrix built from ``M = A Bᵀ``, and

    δ = ||A||² + ||B||² − 2 λ.

λ is found by Newton's method on the characteristic quartic, started from the smaller of the upper
bounds ``(||A||² + ||B||²)/2`` (Theobald's QCP method) and ``√3 ||M||_F``. This equals the SVD
solution with the determinant fix (``σ₁ + σ₂ + sign(det M) σ₃``) and costs a few dozen flops; a
near-double root (rank-deficient M) falls back to a one-sided Jacobi SVD. This module is the only
implementation: the offline DTW and the online matchers (:func:`residual_with_norms`, with the
model norms precomputed) both call it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "kabsch_residual",
    "kabsch_rotation",
    "max_rotation_trace",
    "residual_columns",
    "residual_with_norms",
]


@njit(cache=True)
def _det3(a00, a01, a02, a10, a11, a12, a20, a21, a22):
    return (
        a00 * (a11 * a22 - a12 * a21)
        - a01 * (a10 * a22 - a12 * a20)
        + a02 * (a10 * a21 - a11 * a20)
    )


#: Relative size of P'(λ) below which λ is treated as a (near-)double root of the quartic.
_DOUBLE_ROOT = 1e-3
#: Newton stops once a step changes λ by less than this relative amount.
_NEWTON_TOL = 1e-14


@njit(cache=True)
def _signed_singular_value_sum(M):
    """``σ₁ + σ₂ + sign(det M) σ₃`` by one-sided Jacobi SVD (accurate to eps·σ₁ for every σ)."""
    A = M.copy()
    for _ in range(30):
        rotated = False
        for p in range(2):
            for q in range(p + 1, 3):
                alpha = A[0, p] * A[0, p] + A[1, p] * A[1, p] + A[2, p] * A[2, p]
                beta = A[0, q] * A[0, q] + A[1, q] * A[1, q] + A[2, q] * A[2, q]
                gamma = A[0, p] * A[0, q] + A[1, p] * A[1, q] + A[2, p] * A[2, q]
                if gamma == 0.0 or abs(gamma) <= 1e-16 * math.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                c = 1.0 / math.sqrt(1.0 + t * t)
                s = c * t
                for r in range(3):
                    ap = A[r, p]
                    aq = A[r, q]
                    A[r, p] = c * ap - s * aq
                    A[r, q] = s * ap + c * aq
        if not rotated:
            break
    sv = np.empty(3)
    for c in range(3):
        sv[c] = math.sqrt(A[0, c] * A[0, c] + A[1, c] * A[1, c] + A[2, c] * A[2, c])
    sv.sort()
    det = _det3(M[0, 0], M[0, 1], M[0, 2], M[1, 0], M[1, 1], M[1, 2], M[2, 0], M[2, 1], M[2, 2])
    return sv[2] + sv[1] + (sv[0] if det >= 0.0 else -sv[0])


@njit(cache=True, inline="always")
def _det2(a, b, c, d):
    return a * d - b * c


@njit(cache=True, inline="always")
def _max_trace(sxx, sxy, sxz, syx, syy, syz, szx, szy, szz, e0):
    """``max_R tr(R M)`` for ``M = [[sxx, sxy, sxz], [syx, ...], ...]``; ``e0/2`` bounds it from above."""
    # Horn's symmetric, traceless 4x4 matrix N; its largest eigenvalue is the maximum
    n00 = sxx + syy + szz
    n01 = syz - szy
    n02 = szx - sxz
    n03 = sxy - syx
    n11 = sxx - syy - szz
    n12 = sxy + syx
    n13 = szx + sxz
    n22 = -sxx + syy - szz
    n23 = syz + szy
    n33 = -sxx - syy + szz
    # characteristic polynomial λ⁴ + c2 λ² + c1 λ + c0
    m_norm2 = (
        sxx * sxx + sxy * sxy + sxz * sxz + syx * syx + syy * syy + syz * syz
        + szx * szx + szy * szy + szz * szz
    )
    c2 = -2.0 * m_norm2
    c1 = -8.0 * _det3(sxx, sxy, sxz, syx, syy, syz, szx, szy, szz)
    # det N by Laplace expansion along rows (0, 1) / (2, 3): six products of 2x2 minors
    c0 = (
        _det2(n00, n01, n01, n11) * _det2(n22, n23, n23, n33)
        - _det2(n00, n02, n01, n12) * _det2(n12, n23, n13, n33)
        + _det2(n00, n03, n01, n13) * _det2(n12, n22, n13, n23)
        + _det2(n01, n02, n11, n12) * _det2(n02, n23, n03, n33)
        - _det2(n01, n03, n11, n13) * _det2(n02, n22, n03, n23)
        + _det2(n02, n03, n12, n13) * _det2(n02, n12, n03, n13)
    )
    # two upper bounds of λ_max = σ₁ + σ₂ ± σ₃: e0/2 (Cauchy-Schwarz) and √3 ||M||_F; Newton from
    # above the largest root of a real-rooted polynomial decreases monotonically onto it
    m_norm = math.sqrt(m_norm2)
    lam = min(0.5 * e0, math.sqrt(3.0) * m_norm)
    if lam <= 0.0:
        return 0.0
    df = 0.0
    for _ in range(60):
        lam2 = lam * lam
        f = (lam2 + c2) * lam2 + c1 * lam + c0
        df = 4.0 * lam2 * lam + 2.0 * c2 * lam + c1
        if df <= 0.0:
            break
        lam_new = lam - f / df
        if not lam_new < lam:  # stop when it stalls
            break
        done = lam - lam_new <= _NEWTON_TOL * abs(lam_new)
        lam = lam_new
        if done:
            break
    if not df > _DOUBLE_ROOT * 4.0 * m_norm2 * m_norm:
        # λ is a (near-)double root (rank-deficient M, non-unique rotation), where the quartic
        # resolves it only to ~sqrt(eps): take the singular values instead (rare, exact singularities)
        M = np.empty((3, 3))
        M[0, 0], M[0, 1], M[0, 2] = sxx, sxy, sxz
        M[1, 0], M[1, 1], M[1, 2] = syx, syy, syz
        M[2, 0], M[2, 1], M[2, 2] = szx, szy, szz
        return _signed_singular_value_sum(M)
    return lam


@njit(cache=True)
def max_rotation_trace_from_m(M, e0):
    """``max_R tr(R M)`` over proper rotations for a 3×3 ``M``; ``e0 / 2`` must bound it from above."""
    return _max_trace(
        M[0, 0], M[0, 1], M[0, 2], M[1, 0], M[1, 1], M[1, 2], M[2, 0], M[2, 1], M[2, 2], e0
    )


@njit(cache=True, inline="always")
def _cross(a, b, ncols):
    """Entries of ``M = A Bᵀ`` for flat column-major 3×ncols ``a``, ``b`` (a 9-tuple, row-major)."""
    sxx = sxy = sxz = syx = syy = syz = szx = szy = szz = 0.0
    for c in range(ncols):
        ax = a[3 * c]
        ay = a[3 * c + 1]
        az = a[3 * c + 2]
        bx = b[3 * c]
        by = b[3 * c + 1]
        bz = b[3 * c + 2]
        sxx += ax * bx
        sxy += ax * by
        sxz += ax * bz
        syx += ay * bx
        syy += ay * by
        syz += ay * bz
        szx += az * bx
        szy += az * by
        szz += az * bz
    return sxx, sxy, sxz, syx, syy, syz, szx, szy, szz


@njit(cache=True, inline="always")
def residual_with_norms(a, a2, b, b2, ncols):
    """δ for flat column-major 3×ncols ``a``, ``b`` whose squared norms ``a2 = ||a||²``, ``b2 = ||b||²``
    are already known (the online matchers precompute the model side)."""
    sxx, sxy, sxz, syx, syy, syz, szx, szy, szz = _cross(a, b, ncols)
    e0 = a2 + b2
    lam = _max_trace(sxx, sxy, sxz, syx, syy, syz, szx, szy, szz, e0)
    res = e0 - 2.0 * lam
    return res if res > 0.0 else 0.0


@njit(cache=True)
def residual_columns(a, b, ncols):
    """δ for two flat vectors holding ``ncols`` consecutive 3-vectors each (column-major 3×ncols)."""
    sxx, sxy, sxz, syx, syy, syz, szx, szy, szz = _cross(a, b, ncols)
    e0 = 0.0
    for r in range(3 * ncols):
        e0 += a[r] * a[r] + b[r] * b[r]
    lam = _max_trace(sxx, sxy, sxz, syx, syy, syz, szx, szy, szz, e0)
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
    """The rotation R (3, 3) minimizing ``||R A − B||_F`` (SVD with the determinant fix,
    docs/algorithms/dtw.md)."""
    C = np.asarray(A, dtype=np.float64) @ np.asarray(B, dtype=np.float64).T
    U, _, Vt = np.linalg.svd(C)
    R = Vt.T @ U.T
    if np.linalg.det(R) < 0:
        U[:, -1] *= -1
        R = Vt.T @ U.T
    return R
