"""Smoothing of pose sequences.

:func:`gaussian_smooth` emulates MATLAB's ``smoothdata(y, 'gaussian', w)`` exactly as the reference
relies on it (docs/algorithms/smoothing.md): σ = w/5, window offsets ``-(w-1)/2..(w-1)/2`` for odd w
and ``-w/2..w/2-1`` for even w, truncated and renormalized at the ends.

:func:`smooth_poses` applies it to positions and sign-continuous quaternion components, then
renormalizes the quaternions (RRV, DSRF, BILTS, BILTS+).

The Kalman/RTS smoother of docs/algorithms/smoothing.md used by DHB, eFS and ISA lives in
:mod:`framefree.core.kalman`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from . import se3_kernels

__all__ = [
    "gaussian_offsets",
    "gaussian_smooth",
    "gaussian_weights",
    "pose_signals",
    "smooth_poses",
]


def gaussian_offsets(window: int) -> tuple[int, int]:
    """Samples before and after the current one in a Gaussian window of length ``window``."""
    if window < 1:
        raise ValueError(f"window must be at least 1, got {window}")
    if window % 2:
        return (window - 1) // 2, (window - 1) // 2
    return window // 2, window // 2 - 1


def gaussian_weights(window: int) -> np.ndarray:
    """Unnormalized weights ``exp(-o²/(2σ²))``, σ = window/5, for offsets ``-before..after``."""
    before, after = gaussian_offsets(window)
    o = np.arange(-before, after + 1, dtype=np.float64)
    sigma = window / 5.0
    return np.exp(-0.5 * (o / sigma) ** 2)


@njit(cache=True)
def _smooth_kernel(y, g, before):
    n, c = y.shape
    nw = g.shape[0]
    out = np.empty_like(y)
    for k in range(n):
        wsum = 0.0
        acc = np.zeros(c)
        for j in range(nw):
            idx = k - before + j
            if 0 <= idx < n:
                wsum += g[j]
                for col in range(c):
                    acc[col] += g[j] * y[idx, col]
        for col in range(c):
            out[k, col] = acc[col] / wsum
    return out


def gaussian_smooth(y: np.ndarray, window: int) -> np.ndarray:
    """Gaussian moving average along axis 0 (MATLAB ``smoothdata`` 'gaussian' semantics).

    Parameters
    ----------
    y : ndarray, shape (N,) or (N, C)
    window : int
        Window length in samples.

    Returns
    -------
    ndarray, same shape as ``y``
    """
    y = np.asarray(y, dtype=np.float64)
    flat = y.reshape(y.shape[0], -1)
    before, _ = gaussian_offsets(window)
    out = _smooth_kernel(np.ascontiguousarray(flat), gaussian_weights(window), before)
    return out.reshape(y.shape)


@njit(cache=True)
def pose_signals(poses):
    """The 7 scalar signals of poses (N, 4, 4): positions and sign-continuous quaternions, (N, 7)."""
    n = poses.shape[0]
    q = np.empty((n, 4))
    for k in range(n):
        q[k] = se3_kernels.quaternion_from_matrix_one(poses[k, :3, :3])
    se3_kernels.continuity_inplace(q, 0.5)
    y = np.empty((n, 7))
    for k in range(n):
        for r in range(3):
            y[k, r] = poses[k, r, 3]
        for r in range(4):
            y[k, 3 + r] = q[k, r]
    return y


@njit(cache=True)
def smooth_poses_kernel(poses, g, before):
    """Gaussian-smooth positions and quaternions of poses (N, 4, 4); returns smoothed poses."""
    n = poses.shape[0]
    pq = pose_signals(poses)
    sm = _smooth_kernel(pq, g, before)
    out = np.empty((n, 4, 4))
    for k in range(n):
        R = se3_kernels.matrix_from_quaternion_one(sm[k, 3:])
        out[k] = 0.0
        out[k, :3, :3] = R
        for r in range(3):
            out[k, r, 3] = sm[k, r]
        out[k, 3, 3] = 1.0
    return out


def smooth_poses(poses: np.ndarray, window: int) -> np.ndarray:
    """Gaussian-smooth a pose sequence (N, 4, 4) component-wise (docs/algorithms/smoothing.md);
    quaternions renormalized."""
    before, _ = gaussian_offsets(window)
    return smooth_poses_kernel(
        np.ascontiguousarray(poses, dtype=np.float64), gaussian_weights(window), before
    )
