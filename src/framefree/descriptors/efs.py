"""eFS: extended Frenet–Serret invariants of the rotational and translational motion
(docs/algorithms/descriptors.md).

Pipeline (reference ``calculate_eFS_descriptor.m``): reparameterize (docs/algorithms/progress.md),
Kalman/RTS-smooth (docs/algorithms/smoothing.md) and take the pose twist ``(ω, ṗ)`` with its first
two progress derivatives (docs/algorithms/smoothing.md); add the constant 1e-12 to every entry of
the twist and of its first derivative; then per block (``x = ω, ẋ = ω̇, ẍ = ω̈`` and ``x = ṗ, ẋ =
p̈, ẍ = p⃛``) and per sample:

* ``r₁ = |x|``;
* ``r₂ = |x × ẋ| / |x|²`` (curvature rate);
* ``r₃ = ((x × ẋ) × (x × ẍ)) · x/|x| / |x × ẋ|²`` (torsion rate).

Columns ``[r₁^ω, r₂^ω, r₃^ω, r₁^v, r₂^v, r₃^v]`` weighted by ``(L, λL, λL, 1, λL, λL)``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.kalman import PoseKinematics
from .base import register
from .families import KalmanDescriptor

__all__ = ["EFS", "efs_representation"]

#: Constant added to every entry of the twist and its first derivative (reference value).
EFS_OFFSET = 1e-12


@njit(cache=True, error_model="numpy")
def _fs_block(x, xd, xdd, out, k, col):
    cx = x[1] * xd[2] - x[2] * xd[1]
    cy = x[2] * xd[0] - x[0] * xd[2]
    cz = x[0] * xd[1] - x[1] * xd[0]
    ex = x[1] * xdd[2] - x[2] * xdd[1]
    ey = x[2] * xdd[0] - x[0] * xdd[2]
    ez = x[0] * xdd[1] - x[1] * xdd[0]
    nx2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
    nx = math.sqrt(nx2)
    nc2 = cx * cx + cy * cy + cz * cz
    # (x × ẋ) × (x × ẍ)
    tx = cy * ez - cz * ey
    ty = cz * ex - cx * ez
    tz = cx * ey - cy * ex
    out[k, col] = nx
    out[k, col + 1] = math.sqrt(nc2) / nx2
    out[k, col + 2] = (tx * x[0] + ty * x[1] + tz * x[2]) / nx / nc2


@njit(cache=True, error_model="numpy")
def efs_kernel(tw, offset):
    """Unweighted eFS (N, 6) from pose twist derivatives ``tw`` (N, 3, 6)."""
    n = tw.shape[0]
    out = np.empty((n, 6))
    x = np.empty(3)
    xd = np.empty(3)
    xdd = np.empty(3)
    for k in range(n):
        for blk in range(2):
            for r in range(3):
                x[r] = tw[k, 0, 3 * blk + r] + offset
                xd[r] = tw[k, 1, 3 * blk + r] + offset
                xdd[r] = tw[k, 2, 3 * blk + r]
            _fs_block(x, xd, xdd, out, k, 3 * blk)
    return out


def efs_representation(pose_twists: np.ndarray, offset: float = EFS_OFFSET) -> np.ndarray:
    """Unweighted eFS invariants.

    Parameters
    ----------
    pose_twists : ndarray, shape (N, 3, 6)
        ``[:, d, :]`` = d-th progress derivative of the pose twist ``(ω, ṗ)``.
    offset : float
        Constant added to the twist and its first derivative (1e-12 in the reference).

    Returns
    -------
    ndarray, shape (N, 6)
        ``[|ω|, κ_ω, τ_ω, |ṗ|, κ_v, τ_v]`` per unit progress.
    """
    tw = np.ascontiguousarray(pose_twists, dtype=np.float64)
    if tw.ndim != 3 or tw.shape[1:] != (3, 6):
        raise ValueError(f"pose_twists must have shape (N, 3, 6), got {tw.shape}")
    return efs_kernel(tw, float(offset))


@register
class EFS(KalmanDescriptor):
    """Extended Frenet–Serret invariants (docs/algorithms/descriptors.md), Euclidean DTW distance
    (docs/algorithms/dtw.md).

    Parameters
    ----------
    progress : {"arclength", "angle", "screw"}
        Progress type (default "screw").
    L : float
        Scale length [m] (default 0.5, the middle of the grid 0.1..0.9).
    lam : float
        Weight λ of the curvature and torsion rows (default 0.1, the middle of the grid
        0.001..10).
    n_samples : int
        Number of progress samples (50).

    Notes
    -----
    Output columns ``[L|ω|, λLκ_ω, λLτ_ω, |ṗ|, λLκ_v, λLτ_v]``, shape (n_samples, 6).
    World-frame invariant (up to the 1e-12 offsets); not body-frame invariant.
    """

    name = "efs"
    display_name = "eFS"
    default_lam = 0.1
    lam_grid = (0.001, 0.01, 0.1, 1.0, 10.0)

    @staticmethod
    def row_weights_for(L: float, lam: float) -> np.ndarray:
        """``(L, λL, λL, 1, λL, λL)``."""
        return np.array([L, lam * L, lam * L, 1.0, lam * L, lam * L])

    @staticmethod
    def representation_from_kinematics(kin: PoseKinematics) -> np.ndarray:
        """Unweighted eFS (N, 6) of the smoothed pose twist and its derivatives."""
        return efs_kernel(np.ascontiguousarray(kin.pose_twists), EFS_OFFSET)
