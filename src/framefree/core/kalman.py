"""Kalman / Rauch–Tung–Striebel smoother of the Kalman-based descriptors (docs/algorithms/smoothing.md).

DHB, eFS and ISA smooth the 50-sample reparameterized trajectory with a forward Kalman filter and a
backward RTS pass, applied independently to each of 7 scalar signals: the 3 position coordinates
and the 4 components of the sign-continuous quaternion. The model is a Taylor expansion up to the
jerk, driven by white noise on the derivative of the jerk:

* state ``x = (y, y', y'', y''')`` (derivatives with respect to progress, step ``h = Δs``);
* transition ``F`` = upper-triangular Taylor matrix, process noise ``Q = q² g gᵀ`` with
  ``g = (h⁴/24, h³/6, h²/2, h)`` and ``q = 50``;
* measurement ``z = (y, 0)``: the sample plus a virtual zero-velocity measurement, covariance
  ``diag(σ², 10⁶ σ²/h²)``, ``σ = 0.002`` (positions, metres) or ``π/180`` (quaternion components);
* prior ``x₀ = (y₁, 0, 0, 0)``, ``P₀ = diag(1, 10², 10⁴, 10⁶)``; a prediction precedes the first
  update.

The covariances and gains do not depend on the data, only on ``h`` and ``σ``: they are computed once
per distinct ``σ`` (twice for a pose: positions, quaternions) and applied to every signal of that
group. Gains come from linear solves (no explicit inverse, docs/algorithms/smoothing.md).

:func:`smooth_pose_kinematics` turns the smoothed signals into the pose twist ``(ω, ṗ)`` and its
first two derivatives (docs/algorithms/smoothing.md), from which the spatial screw twist and its
derivatives follow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..errors import DegenerateMotionError
from .smoothing import pose_signals

__all__ = [
    "KALMAN_Q",
    "P0_DIAGONAL",
    "SIGMA_POSITION",
    "SIGMA_ROTATION",
    "VIRTUAL_VELOCITY_FACTOR",
    "PoseKinematics",
    "rts_smooth",
    "rts_smooth_with_covariance",
    "smooth_pose_kinematics",
    "spatial_from_pose_twists",
]

#: Intensity q of the white noise on the derivative of the jerk (reference "Q" = 50).
KALMAN_Q = 50.0
#: Measurement standard deviation of position coordinates [m].
SIGMA_POSITION = 0.002
#: Measurement standard deviation of quaternion components (1°, used as-is) [-].
SIGMA_ROTATION = math.pi / 180.0
#: Variance of the virtual zero-velocity measurement is this factor × σ² / h².
VIRTUAL_VELOCITY_FACTOR = 1e6
#: Diagonal of the prior covariance of (y, y', y'', y''').
P0_DIAGONAL = (1.0, 1e2, 1e4, 1e6)


# --------------------------------------------------------------------------------------------------
# small dense linear algebra
# --------------------------------------------------------------------------------------------------


@njit(cache=True)
def _solve_into(A, B, a, x):
    """Solve ``A X = B`` (A (n, n), B (n, m)) by Gaussian elimination with partial pivoting.

    ``a`` (n, n) and ``x`` (n, m) are work arrays; the solution is left in ``x``.
    """
    n = A.shape[0]
    m = B.shape[1]
    for r in range(n):
        for c in range(n):
            a[r, c] = A[r, c]
        for c in range(m):
            x[r, c] = B[r, c]
    for col in range(n):
        piv = col
        best = abs(a[col, col])
        for r in range(col + 1, n):
            if abs(a[r, col]) > best:
                best = abs(a[r, col])
                piv = r
        if piv != col:
            for c in range(n):
                tmp = a[col, c]
                a[col, c] = a[piv, c]
                a[piv, c] = tmp
            for c in range(m):
                tmp = x[col, c]
                x[col, c] = x[piv, c]
                x[piv, c] = tmp
        d = a[col, col]
        for r in range(col + 1, n):
            f = a[r, col] / d
            if f != 0.0:
                for c in range(col, n):
                    a[r, c] -= f * a[col, c]
                for c in range(m):
                    x[r, c] -= f * x[col, c]
    for r in range(n - 1, -1, -1):
        for c in range(m):
            s = x[r, c]
            for k in range(r + 1, n):
                s -= a[r, k] * x[k, c]
            x[r, c] = s / a[r, r]


@njit(cache=True)
def _model(h, q):
    """Transition F (4, 4) and process noise Q (4, 4) of the jerk-derivative white-noise model."""
    F = np.eye(4)
    F[0, 1] = h
    F[0, 2] = h * h / 2.0
    F[0, 3] = h * h * h / 6.0
    F[1, 2] = h
    F[1, 3] = h * h / 2.0
    F[2, 3] = h
    g = np.array([h**4 / 24.0, h**3 / 6.0, h * h / 2.0, h])
    Q = np.empty((4, 4))
    for i in range(4):
        for j in range(4):
            Q[i, j] = q * q * g[i] * g[j]
    return F, Q


@njit(cache=True)
def _mm(A, B, out):
    """out = A @ B for 4×4 matrices (no allocation)."""
    for i in range(4):
        for j in range(4):
            s = 0.0
            for k in range(4):
                s += A[i, k] * B[k, j]
            out[i, j] = s


@njit(cache=True)
def _mmt(A, B, out):
    """out = A @ Bᵀ for 4×4 matrices (no allocation)."""
    for i in range(4):
        for j in range(4):
            s = 0.0
            for k in range(4):
                s += A[i, k] * B[j, k]
            out[i, j] = s


# Kept as one compiled function (about 60 lines of code): the forward filter and the backward
# smoother share their state arrays in one numba frame; the steps are marked inside.
@njit(cache=True)
def rts_gains(n, h, sigma, q, with_covariance=True):
    """Data-independent part of the smoother for one signal group.

    Parameters
    ----------
    n : int
        Number of samples.
    h : float
        Sample step (progress units).
    sigma : float
        Measurement standard deviation of the signal.
    q : float
        Process noise intensity.

    Returns
    -------
    K : ndarray, shape (n, 4, 2)
        Kalman gains of the forward pass.
    J : ndarray, shape (n, 4, 4)
        RTS smoother gains (``J[n-1]`` unused, zero).
    Ps : ndarray, shape (n, 4, 4)
        Smoothed state covariances (only the last one unless ``with_covariance``).
    """
    F, Q = _model(h, q)
    r0 = sigma * sigma
    r1 = VIRTUAL_VELOCITY_FACTOR * sigma * sigma / (h * h)
    P = np.zeros((4, 4))
    for i in range(4):
        P[i, i] = P0_DIAGONAL[i]
    K = np.empty((n, 4, 2))
    Pm = np.empty((n, 4, 4))
    Pf = np.empty((n, 4, 4))
    FP = np.empty((4, 4))
    Pp = np.empty((4, 4))
    for j in range(n):
        # predicted covariance P⁻ = F P Fᵀ + Q
        _mm(F, P, FP)
        _mmt(FP, F, Pp)
        for a in range(4):
            for b in range(4):
                Pp[a, b] += Q[a, b]
        # innovation covariance S = H P⁻ Hᵀ + R (2×2); K = P⁻ Hᵀ S⁻¹ by a 2×2 linear solve
        # (Cramer's rule on Sᵀ Kᵀ = (P⁻ Hᵀ)ᵀ)
        s00 = Pp[0, 0] + r0
        s01 = Pp[0, 1]
        s10 = Pp[1, 0]
        s11 = Pp[1, 1] + r1
        det = s00 * s11 - s01 * s10
        for a in range(4):
            c0 = Pp[a, 0]
            c1 = Pp[a, 1]
            # row a of K solves [k0, k1] S = [c0, c1]
            K[j, a, 0] = (c0 * s11 - c1 * s10) / det
            K[j, a, 1] = (c1 * s00 - c0 * s01) / det
        # P = (I - K H) P⁻
        for a in range(4):
            for b in range(4):
                P[a, b] = Pp[a, b] - K[j, a, 0] * Pp[0, b] - K[j, a, 1] * Pp[1, b]
        Pm[j] = Pp
        Pf[j] = P
    J = np.zeros((n, 4, 4))
    Ps = np.empty((n if with_covariance else 1, 4, 4))
    Ps[-1] = Pf[n - 1]
    FPt = np.empty((4, 4))
    work = np.empty((4, 4))
    Jt = np.empty((4, 4))
    D = np.empty((4, 4))
    JD = np.empty((4, 4))
    for j in range(n - 2, -1, -1):
        # J = P_j Fᵀ (P⁻_{j+1})⁻¹  <=>  (P⁻_{j+1})ᵀ Jᵀ = F P_jᵀ
        _mmt(F, Pf[j], FPt)
        _solve_into(Pm[j + 1].T, FPt, work, Jt)
        for a in range(4):
            for b in range(4):
                J[j, a, b] = Jt[b, a]
        if with_covariance:
            # P^s_j = P_j + J (P^s_{j+1} - P⁻_{j+1}) Jᵀ
            for a in range(4):
                for b in range(4):
                    D[a, b] = Ps[j + 1, a, b] - Pm[j + 1, a, b]
            _mm(J[j], D, JD)
            _mmt(JD, J[j], FP)
            for a in range(4):
                for b in range(4):
                    Ps[j, a, b] = Pf[j, a, b] + FP[a, b]
    return K, J, Ps


@njit(cache=True)
def _smooth_signal(y, F, K, J, out, c):
    """Forward filter and RTS pass of one signal ``y`` (n,) with given gains → ``out[:, c, :]``."""
    n = y.shape[0]
    xm = np.empty((n, 4))
    xf = np.empty((n, 4))
    x = np.zeros(4)
    x[0] = y[0]
    pred = np.empty(4)
    for j in range(n):
        for a in range(4):
            s = 0.0
            for b in range(a, 4):
                s += F[a, b] * x[b]
            pred[a] = s
        e0 = y[j] - pred[0]
        e1 = -pred[1]
        for a in range(4):
            x[a] = pred[a] + K[j, a, 0] * e0 + K[j, a, 1] * e1
            xm[j, a] = pred[a]
            xf[j, a] = x[a]
    for a in range(4):
        out[n - 1, c, a] = xf[n - 1, a]
    d = np.empty(4)
    for j in range(n - 2, -1, -1):
        for a in range(4):
            d[a] = out[j + 1, c, a] - xm[j + 1, a]
        for a in range(4):
            s = xf[j, a]
            for b in range(4):
                s += J[j, a, b] * d[b]
            out[j, c, a] = s


@njit(cache=True)
def rts_smooth_kernel(y, h, sigma, q):
    """Smoothed value and first three derivatives of every column of ``y``.

    Parameters
    ----------
    y : ndarray, shape (n, C)
        Signals sampled with step ``h``.
    h : float
        Sample step.
    sigma : ndarray, shape (C,)
        Measurement standard deviation per signal; gains are shared between consecutive signals
        with equal σ.
    q : float
        Process noise intensity.

    Returns
    -------
    ndarray, shape (n, C, 4)
        ``[..., d]`` = d-th derivative (d = 0..3) with respect to the sample variable.
    """
    n, C = y.shape
    F, _ = _model(h, q)
    out = np.empty((n, C, 4))
    K, J, _ = rts_gains(n, h, sigma[0], q, False)
    last = sigma[0]
    for c in range(C):
        if sigma[c] != last:
            K, J, _ = rts_gains(n, h, sigma[c], q, False)
            last = sigma[c]
        _smooth_signal(y[:, c], F, K, J, out, c)
    return out


def _check_step(h: float) -> float:
    h = float(h)
    if not (h > 0 and math.isfinite(h)):
        raise DegenerateMotionError(
            f"Kalman smoother needs a positive progress step, got {h:g} "
            "(a motion without progress of the chosen kind)"
        )
    return h


def rts_smooth(
    y: np.ndarray, h: float, sigma: float | np.ndarray, q: float = KALMAN_Q
) -> np.ndarray:
    """Kalman filter + RTS smoother of docs/algorithms/smoothing.md applied to each column of ``y``.

    Parameters
    ----------
    y : ndarray, shape (n,) or (n, C)
        Signals sampled with step ``h``.
    h : float
        Sample step (the progress step Δs of the reparameterized trajectory).
    sigma : float or ndarray, shape (C,)
        Measurement standard deviation (same unit as ``y``).
    q : float
        Process noise intensity (default 50).

    Returns
    -------
    ndarray, shape (n, 4) or (n, C, 4)
        Smoothed value and first, second, third derivatives with respect to the sample variable.

    Raises
    ------
    DegenerateMotionError
        If ``h`` is not positive and finite.
    """
    h = _check_step(h)
    y = np.asarray(y, dtype=np.float64)
    one = y.ndim == 1
    y2 = y[:, None] if one else y
    if y2.ndim != 2 or y2.shape[0] < 1:
        raise ValueError(f"y must have shape (n,) or (n, C), got {y.shape}")
    sig = np.broadcast_to(np.asarray(sigma, dtype=np.float64), (y2.shape[1],)).copy()
    out = rts_smooth_kernel(np.ascontiguousarray(y2), h, sig, float(q))
    return out[:, 0, :] if one else out


def rts_smooth_with_covariance(
    y: np.ndarray, h: float, sigma: float, q: float = KALMAN_Q
) -> tuple[np.ndarray, np.ndarray]:
    """Smoothed states (n, 4) and smoothed covariances (n, 4, 4) of one signal ``y`` (n,)."""
    h = _check_step(h)
    y = np.ascontiguousarray(y, dtype=np.float64)
    if y.ndim != 1:
        raise ValueError(f"y must have shape (n,), got {y.shape}")
    _, _, Ps = rts_gains(y.shape[0], h, float(sigma), float(q), True)
    return rts_smooth(y, h, sigma, q), Ps


# --------------------------------------------------------------------------------------------------
# smoothed pose kinematics (docs/algorithms/smoothing.md)
# --------------------------------------------------------------------------------------------------


@njit(cache=True)
def _qmul_vec_acc(a, b, c, out, scale):
    """``out += scale · vec(a ⊗ b*)`` for quaternions ``a``, ``b`` (scalar first) given as
    rows ``a`` and ``b`` of ``c`` (n, 4): the vector part of a Hamilton product with a conjugate."""
    a0, a1, a2, a3 = c[a, 0], c[a, 1], c[a, 2], c[a, 3]
    b0, b1, b2, b3 = c[b, 0], -c[b, 1], -c[b, 2], -c[b, 3]
    out[0] += scale * (a0 * b1 + b0 * a1 + a2 * b3 - a3 * b2)
    out[1] += scale * (a0 * b2 + b0 * a2 + a3 * b1 - a1 * b3)
    out[2] += scale * (a0 * b3 + b0 * a3 + a1 * b2 - a2 * b1)


@njit(cache=True)
def pose_kinematics_kernel(poses, h, q):
    """Smoothed positions (n, 3) and pose twist derivatives (n, 3, 6) of poses (n, 4, 4)."""
    n = poses.shape[0]
    y = pose_signals(poses)
    sig = np.empty(7)
    for r in range(3):
        sig[r] = SIGMA_POSITION
    for r in range(3, 7):
        sig[r] = SIGMA_ROTATION
    xs = rts_smooth_kernel(y, h, sig, q)
    pos = np.empty((n, 3))
    tw = np.zeros((n, 3, 6))
    # rows: 0 = normalized q, 1..3 = raw derivatives q̇, q̈, q⃛
    c = np.empty((4, 4))
    for k in range(n):
        nq = 0.0
        for r in range(4):
            nq += xs[k, 3 + r, 0] * xs[k, 3 + r, 0]
        nq = math.sqrt(nq)
        for r in range(4):
            c[0, r] = xs[k, 3 + r, 0] / nq
            c[1, r] = xs[k, 3 + r, 1]
            c[2, r] = xs[k, 3 + r, 2]
            c[3, r] = xs[k, 3 + r, 3]
        # ω = 2 q̇⊗q*;  ω̇ = 2 q̈⊗q* + 2 q̇⊗q̇*;  ω̈ = 2 q⃛⊗q* + 4 q̈⊗q̇* + 2 q̇⊗q̈*
        _qmul_vec_acc(1, 0, c, tw[k, 0], 2.0)
        _qmul_vec_acc(2, 0, c, tw[k, 1], 2.0)
        _qmul_vec_acc(1, 1, c, tw[k, 1], 2.0)
        _qmul_vec_acc(3, 0, c, tw[k, 2], 2.0)
        _qmul_vec_acc(2, 1, c, tw[k, 2], 4.0)
        _qmul_vec_acc(1, 2, c, tw[k, 2], 2.0)
        for r in range(3):
            pos[k, r] = xs[k, r, 0]
            tw[k, 0, 3 + r] = xs[k, r, 1]
            tw[k, 1, 3 + r] = xs[k, r, 2]
            tw[k, 2, 3 + r] = xs[k, r, 3]
    return pos, tw


@njit(cache=True)
def _cross_acc(a, b, out, scale):
    """``out[3:] += scale · (a × b)`` for 3-vectors."""
    out[3] += scale * (a[1] * b[2] - a[2] * b[1])
    out[4] += scale * (a[2] * b[0] - a[0] * b[2])
    out[5] += scale * (a[0] * b[1] - a[1] * b[0])


@njit(cache=True)
def spatial_twists_kernel(pos, tw):
    """Spatial screw twist and derivatives (n, 3, 6) from pose twists (n, 3, 6) and positions."""
    n = pos.shape[0]
    out = tw.copy()
    for k in range(n):
        p = pos[k]
        w0 = tw[k, 0, :3]
        w1 = tw[k, 1, :3]
        w2 = tw[k, 2, :3]
        pd = tw[k, 0, 3:]
        pdd = tw[k, 1, 3:]
        # V = ṗ + p×ω;  V̇ = p̈ + p×ω̇ + ṗ×ω;  V̈ = p⃛ + p×ω̈ + 2 ṗ×ω̇ + p̈×ω
        _cross_acc(p, w0, out[k, 0], 1.0)
        _cross_acc(p, w1, out[k, 1], 1.0)
        _cross_acc(pd, w0, out[k, 1], 1.0)
        _cross_acc(p, w2, out[k, 2], 1.0)
        _cross_acc(pd, w1, out[k, 2], 2.0)
        _cross_acc(pdd, w0, out[k, 2], 1.0)
    return out


@dataclass(frozen=True)
class PoseKinematics:
    """Kalman-smoothed kinematics of a reparameterized trajectory (docs/algorithms/smoothing.md).

    Attributes
    ----------
    positions : ndarray, shape (n, 3)
        Smoothed body-origin positions [m].
    pose_twists : ndarray, shape (n, 3, 6)
        ``[:, d, :]`` = d-th progress derivative (d = 0, 1, 2) of the pose twist ``(ω, ṗ)``:
        ``(ω, ṗ)``, ``(ω̇, p̈)``, ``(ω̈, p⃛)``; world coordinates, per unit progress.
    ds : float
        Progress step used as the Kalman step ``h``.
    """

    positions: np.ndarray
    pose_twists: np.ndarray
    ds: float

    def spatial_twists(self) -> np.ndarray:
        """Spatial screw twist ``(Ω, V)`` and its first two derivatives, shape (n, 3, 6)."""
        return spatial_from_pose_twists(self.pose_twists, self.positions)


def spatial_from_pose_twists(pose_twists: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """Spatial screw twists and derivatives (n, 3, 6) from pose twists (n, 3, 6), positions (n, 3)."""
    return spatial_twists_kernel(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(pose_twists, dtype=np.float64),
    )


def smooth_pose_kinematics(poses: np.ndarray, ds: float, q: float = KALMAN_Q) -> PoseKinematics:
    """Kalman-smooth a reparameterized pose sequence and derive its twists (docs/algorithms/smoothing.md).

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4)
        Poses at equidistant progress.
    ds : float
        Progress step (metres for arclength/screw progress, radians for angle progress).
    q : float
        Process noise intensity (default 50).

    Returns
    -------
    PoseKinematics

    Raises
    ------
    DegenerateMotionError
        If ``ds`` is not positive and finite.
    """
    h = _check_step(ds)
    poses = np.ascontiguousarray(poses, dtype=np.float64)
    if poses.ndim != 3 or poses.shape[1:] != (4, 4):
        raise ValueError(f"poses must have shape (n, 4, 4), got {poses.shape}")
    pos, tw = pose_kinematics_kernel(poses, h, float(q))
    return PoseKinematics(pos, tw, h)
