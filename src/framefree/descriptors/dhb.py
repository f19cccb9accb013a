"""DHB: Denavit–Hartenberg-inspired Bidirectional invariants (docs/algorithms/descriptors.md), and
the machinery shared by the three Kalman-based local descriptors DHB, eFS and ISA.

Pipeline (reference ``calculate_DHB_descriptor.m``):

1. reparameterize to N = 50 equidistant progress samples, step Δs (docs/algorithms/progress.md);
2. Kalman/RTS-smooth positions and quaternions with step Δs (docs/algorithms/smoothing.md) and form
   the pose twist ``(ω, ṗ)`` (docs/algorithms/smoothing.md);
3. map each block (x = ω, then x = ṗ) to a magnitude and two angles between successive vectors:
   ``a_k = |x_k|``; ``θ¹_k = arctan(|x_k × x_{k+1}| / (x_k·x_{k+1}))`` (0 if the denominator is at
   most 1e-10 in magnitude; last sample 0); ``θ²_k = arctan(|x_{k+1}| x_{k+1}·(x_k × x_{k+2}) /
   ((x_{k+1} × x_k)·(x_{k+1} × x_{k+2})))`` (same guard; last two samples 0). The arctangent is the
   single-argument one, as in the reference (docs/algorithms/descriptors.md);
4. columns ``[a^ω, θ¹^ω, θ²^ω, a^v, θ¹^v, θ²^v]`` weighted by ``(L, λL, λL, 1, λL, λL)``.

The unweighted (N, 6) *representation* depends on the trajectory, the progress type and, for screw
progress only, on L; the weights are a cheap final step (see :meth:`KalmanDescriptor.weight`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.kalman import PoseKinematics
from .base import register
from .families import KalmanDescriptor

__all__ = ["DHB", "dhb_block", "dhb_representation"]

#: Guard on the denominators of the DHB angles (reference value).
ANGLE_GUARD = 1e-10


@njit(cache=True)
def dhb_block(x, out, col):
    """DHB magnitude and angles of a vector sequence ``x`` (N, 3) into ``out[:, col:col+3]``."""
    n = x.shape[0]
    for k in range(n):
        out[k, col] = math.sqrt(x[k, 0] ** 2 + x[k, 1] ** 2 + x[k, 2] ** 2)
        out[k, col + 1] = 0.0
        out[k, col + 2] = 0.0
    for k in range(n - 1):
        a = x[k]
        b = x[k + 1]
        c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
        if abs(c) > ANGLE_GUARD:
            cx = a[1] * b[2] - a[2] * b[1]
            cy = a[2] * b[0] - a[0] * b[2]
            cz = a[0] * b[1] - a[1] * b[0]
            out[k, col + 1] = math.atan(math.sqrt(cx * cx + cy * cy + cz * cz) / c)
    for k in range(n - 2):
        a = x[k]
        b = x[k + 1]
        d = x[k + 2]
        # u = b × a, w = b × d
        ux = b[1] * a[2] - b[2] * a[1]
        uy = b[2] * a[0] - b[0] * a[2]
        uz = b[0] * a[1] - b[1] * a[0]
        wx = b[1] * d[2] - b[2] * d[1]
        wy = b[2] * d[0] - b[0] * d[2]
        wz = b[0] * d[1] - b[1] * d[0]
        c = ux * wx + uy * wy + uz * wz
        if abs(c) > ANGLE_GUARD:
            # a × d
            ex = a[1] * d[2] - a[2] * d[1]
            ey = a[2] * d[0] - a[0] * d[2]
            ez = a[0] * d[1] - a[1] * d[0]
            nb = math.sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2])
            out[k, col + 2] = math.atan(nb * (b[0] * ex + b[1] * ey + b[2] * ez) / c)


@njit(cache=True)
def dhb_kernel(twists):
    """Unweighted DHB representation (N, 6) of pose twists (N, 6) ``(ω, ṗ)``."""
    n = twists.shape[0]
    out = np.empty((n, 6))
    dhb_block(np.ascontiguousarray(twists[:, :3]), out, 0)
    dhb_block(np.ascontiguousarray(twists[:, 3:]), out, 3)
    return out


def dhb_representation(twists: np.ndarray) -> np.ndarray:
    """Unweighted DHB representation of a twist sequence.

    Parameters
    ----------
    twists : ndarray, shape (N, 6)
        ``(ω, ṗ)`` per sample (rotation first).

    Returns
    -------
    ndarray, shape (N, 6)
        ``[|ω|, θ¹_ω, θ²_ω, |ṗ|, θ¹_v, θ²_v]`` (angles in radians, in (-π/2, π/2)).
    """
    twists = np.ascontiguousarray(twists, dtype=np.float64)
    if twists.ndim != 2 or twists.shape[1] != 6:
        raise ValueError(f"twists must have shape (N, 6), got {twists.shape}")
    return dhb_kernel(twists)


@register
class DHB(KalmanDescriptor):
    """DHB invariants of the Kalman-smoothed pose twist (docs/algorithms/descriptors.md), Euclidean
    DTW distance (docs/algorithms/dtw.md).

    Parameters
    ----------
    progress : {"arclength", "angle", "screw"}
        Progress type (default "screw").
    L : float
        Scale length [m] (default 0.5, the middle of the grid 0.1..0.9).
    lam : float
        Weight λ of the angle rows (default 1, the middle of the grid 0.01..100).
    n_samples : int
        Number of progress samples (50).

    Notes
    -----
    Output columns ``[L|ω|, λLθ¹_ω, λLθ²_ω, |ṗ|, λLθ¹_v, λLθ²_v]``, shape (n_samples, 6).
    World-frame invariant; not body-frame invariant (the pose twist depends on the body origin).
    """

    name = "dhb"
    display_name = "DHB"
    default_lam = 1.0
    lam_grid = (0.01, 0.1, 1.0, 10.0, 100.0)

    @staticmethod
    def row_weights_for(L: float, lam: float) -> np.ndarray:
        """``(L, λL, λL, 1, λL, λL)``."""
        return np.array([L, lam * L, lam * L, 1.0, lam * L, lam * L])

    @staticmethod
    def representation_from_kinematics(kin: PoseKinematics) -> np.ndarray:
        """Unweighted DHB (N, 6) of the smoothed pose twist ``kin.pose_twists[:, 0]``."""
        return dhb_kernel(np.ascontiguousarray(kin.pose_twists[:, 0, :]))
