"""Geometric progress along a rigid-body trajectory and reparameterization by it
(docs/algorithms/progress.md).

Three progress measures are offered:

``"arclength"``
    distance travelled by the body origin [m];
``"angle"``
    rotation angle [rad];
``"screw"``
    screw path [m]: the combined rotation (weighted by the scale length ``L``) and translation along
    the instantaneous screw axis, whose reference point is kept within ``L`` of the body origin
    (segmentation paper, docs/algorithms/progress.md).

Offline, a trajectory is resampled at 50 Hz, its cumulative progress computed, and poses are
interpolated (ScLERP) at N equidistant progress values (docs/algorithms/progress.md). Online,
:class:`StreamingReparameterizer` keeps an incoming pose only once the screw path since the last
kept pose exceeds a resolution (Algorithm 1 of the paper, docs/algorithms/progress.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..errors import DegenerateMotionError
from . import se3_kernels
from .smoothing import smooth_poses
from .trajectory import Trajectory

__all__ = [
    "PROGRESS_TYPES",
    "Reparameterized",
    "StreamingReparameterizer",
    "cumulative_progress",
    "progress_increments",
    "reparameterize",
    "screw_path_increment",
]

#: Total progress [m or rad] at or below which a motion has none: far below any tracker's
#: resolution, far above the rounding noise (1e-13) that pre-smoothing a motionless recording leaves
MIN_TOTAL_PROGRESS = 1e-9

PROGRESS_TYPES = ("arclength", "angle", "screw")
_PROGRESS_CODES = {"arclength": 0, "angle": 1, "screw": 2}

#: Nominal time step of the reference's uniform resampling [s] (50 Hz).
DEFAULT_DT = 0.02
#: Number of progress samples of every offline descriptor.
DEFAULT_SAMPLES = 50


@njit(cache=True)
def screw_increment_from_twist(xi, L):
    """Screw path of one displacement twist ``(phi, rho)`` in body coordinates
    (docs/algorithms/progress.md)."""
    phi = xi[:3]
    rho = xi[3:]
    nphi2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]
    if nphi2 == 0.0:
        d1 = math.sqrt(rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2])
    else:
        p0 = (phi[1] * rho[2] - phi[2] * rho[1]) / nphi2
        p1 = (phi[2] * rho[0] - phi[0] * rho[2]) / nphi2
        p2 = (phi[0] * rho[1] - phi[1] * rho[0]) / nphi2
        npp = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
        if npp > L:
            shrink = L / npp
            b0, b1, b2 = p0 * shrink, p1 * shrink, p2 * shrink
            m0 = rho[0] + (phi[1] * b2 - phi[2] * b1)
            m1 = rho[1] + (phi[2] * b0 - phi[0] * b2)
            m2 = rho[2] + (phi[0] * b1 - phi[1] * b0)
            d1 = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
        else:
            d1 = abs(phi[0] * rho[0] + phi[1] * rho[1] + phi[2] * rho[2]) / math.sqrt(nphi2)
    return math.sqrt(L * L * nphi2 + d1 * d1)


@njit(cache=True)
def screw_path_increment(A, B, L):
    """Screw path [m] of the relative displacement from pose ``A`` to pose ``B`` (4×4 each)."""
    return screw_path_increment_into(A, B, L, np.empty((4, 4)), np.empty(6))


@njit(cache=True)
def screw_path_increment_into(A, B, L, work, xi):
    """:func:`screw_path_increment` with scratch arrays ``work`` (4×4) and ``xi`` (6,): no
    allocation."""
    se3_kernels.relative_into(A, B, work)
    se3_kernels.twist_from_pose_into(work, xi)
    return screw_increment_from_twist(xi, L)


@njit(cache=True)
def _increments_kernel(T, code, L):
    n = T.shape[0]
    out = np.empty(n - 1)
    work = np.empty((4, 4))
    xi = np.empty(6)
    for k in range(n - 1):
        if code == 0:
            d = 0.0
            for r in range(3):
                diff = T[k + 1, r, 3] - T[k, r, 3]
                d += diff * diff
            out[k] = math.sqrt(d)
        elif code == 1:
            phi = se3_kernels.rotation_increment_one(T[k], T[k + 1])  # rotation of R_{k+1} R_kᵀ
            out[k] = math.sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2])
        else:
            out[k] = screw_path_increment_into(T[k], T[k + 1], L, work, xi)
    return out


def _check_progress(progress: str) -> int:
    try:
        return _PROGRESS_CODES[progress]
    except KeyError:
        raise ValueError(
            f"unknown progress type {progress!r}; choose one of {PROGRESS_TYPES}"
        ) from None


def progress_increments(poses: np.ndarray, progress: str = "screw", L: float = 0.3) -> np.ndarray:
    """Progress increments between consecutive poses.

    Parameters
    ----------
    poses : ndarray, shape (N, 4, 4)
    progress : {"arclength", "angle", "screw"}
    L : float
        Scale length [m] (screw progress only).

    Returns
    -------
    ndarray, shape (N - 1,)
        In metres (arclength, screw) or radians (angle).
    """
    code = _check_progress(progress)
    if progress == "screw" and not L > 0:
        raise ValueError(f"L must be positive, got {L}")
    return _increments_kernel(np.ascontiguousarray(poses, dtype=np.float64), code, float(L))


def cumulative_progress(poses: np.ndarray, progress: str = "screw", L: float = 0.3) -> np.ndarray:
    """Cumulative progress ``s`` (N,) with ``s[0] = 0``."""
    inc = progress_increments(poses, progress, L)
    return np.concatenate([[0.0], np.cumsum(inc)])


@dataclass(frozen=True)
class Reparameterized:
    """A trajectory resampled at equidistant progress.

    Attributes
    ----------
    poses : ndarray, shape (n, 4, 4)
    ds : float
        Progress step between consecutive samples (``total / (n - 1)``).
    total : float
        Total progress of the trajectory.
    """

    poses: np.ndarray
    ds: float
    total: float


def uniform_time_poses(
    traj: Trajectory, dt: float = DEFAULT_DT, presmooth: int | None = None
) -> np.ndarray:
    """Poses (M, 4, 4) of ``traj`` resampled on the reference's uniform time grid
    (docs/algorithms/progress.md).

    Parameters
    ----------
    presmooth : int, optional
        framefree extension (not in the reference): Gaussian-smooth the uniform poses with this
        window [samples] before any progress is computed. See :func:`reparameterize`.
    """
    poses = traj.uniform_poses(dt)[1]
    if presmooth:
        poses = smooth_poses(poses, presmooth)
    return poses


def reparameterize_poses(
    poses: np.ndarray,
    progress: str = "screw",
    L: float = 0.3,
    n: int = DEFAULT_SAMPLES,
    source: str | None = None,
) -> Reparameterized:
    """Resample a pose sequence at ``n`` equidistant values of its cumulative progress
    (docs/algorithms/progress.md).

    Raises
    ------
    DegenerateMotionError
        If the total progress is zero (no motion of the kind the progress measures): at most
        :data:`MIN_TOTAL_PROGRESS`, the rounding noise that smoothing a motionless recording
        leaves.
    """
    if n < 2:
        raise ValueError(f"n must be at least 2, got {n}")
    poses = np.ascontiguousarray(poses, dtype=np.float64)
    s = cumulative_progress(poses, progress, L)
    total = float(s[-1])
    if not total > MIN_TOTAL_PROGRESS or not math.isfinite(total):
        unit = "rad" if progress == "angle" else "m"
        raise DegenerateMotionError(
            f"the motion has no {progress} progress (total {total:g} {unit}): "
            "a motionless recording, or a motion this progress type cannot measure",
            source,
        )
    sq = np.linspace(0.0, total, n)
    sq[-1] = total
    out = se3_kernels.interpolate_poses_kernel(s, poses, sq)
    return Reparameterized(out, total / (n - 1), total)


def reparameterize(
    traj: Trajectory,
    progress: str = "screw",
    L: float = 0.3,
    n: int = DEFAULT_SAMPLES,
    dt: float = DEFAULT_DT,
    presmooth: int | None = None,
) -> Reparameterized:
    """Resample ``traj`` at 50 Hz (ScLERP), then at ``n`` equidistant progress values
    (docs/algorithms/progress.md).

    Parameters
    ----------
    traj : Trajectory
    progress : {"arclength", "angle", "screw"}
    L : float
        Scale length [m] of the screw path.
    n : int
        Number of progress samples (50 in the reference).
    dt : float
        Step of the uniform time grid [s].
    presmooth : int, optional
        **framefree extension, off by default.** The reference computes progress from the raw
        50 Hz poses, so sensor noise adds progress in proportion to the number of samples (1° of
        orientation noise per sample adds about L·0.04 m of screw path per sample) and can outweigh
        the gesture itself. With ``presmooth=w`` the uniform poses are first smoothed with the
        Gaussian of :func:`~framefree.core.smoothing.smooth_poses` (window ``w`` samples; ``w = 10`` at
        50 Hz passes voluntary hand motion below about 3 Hz and removes tremor and jitter). Exactly
        invariant to world-frame changes, like every other step.
    """
    poses = uniform_time_poses(traj, dt, presmooth)
    return reparameterize_poses(poses, progress, L, n, traj.source)


class StreamingReparameterizer:
    """Online reparameterization by screw path (Algorithm 1 of the paper, docs/algorithms/progress.md).

    The first pose is kept. Every later pose is kept when the screw path from the last kept pose
    to it exceeds ``resolution``; otherwise it is discarded. No interpolation is done.

    Parameters
    ----------
    resolution : float
        Screw-path resolution Δs_res [m].
    L : float
        Scale length of the screw path [m].

    Examples
    --------
    >>> rep = StreamingReparameterizer(resolution=0.01, L=0.3)
    >>> kept = [T for T in poses if rep.push(T)]  # doctest: +SKIP
    """

    def __init__(self, resolution: float, L: float) -> None:
        if not resolution > 0:
            raise ValueError(f"resolution must be positive, got {resolution}")
        if not L > 0:
            raise ValueError(f"L must be positive, got {L}")
        self.resolution = float(resolution)
        self.L = float(L)
        self.last_kept: np.ndarray | None = None
        self.n_kept = 0
        self.n_seen = 0

    def reset(self) -> None:
        """Forget the last kept pose: the next pose starts a new geometric sequence."""
        self.last_kept = None

    def push(self, pose: np.ndarray) -> bool:
        """Offer a pose (4, 4); return True if it becomes the next geometric sample."""
        self.n_seen += 1
        if self.last_kept is None:
            self.last_kept = np.array(pose, dtype=np.float64)
            self.n_kept += 1
            return True
        ds = screw_path_increment(
            self.last_kept, np.ascontiguousarray(pose, dtype=np.float64), self.L
        )
        if ds > self.resolution:
            self.last_kept = np.array(pose, dtype=np.float64)
            self.n_kept += 1
            return True
        return False

    def run(self, poses: np.ndarray) -> np.ndarray:
        """Push a whole pose sequence (N, 4, 4); return the indices of the kept poses."""
        poses = np.ascontiguousarray(poses, dtype=np.float64)
        start = self.last_kept
        idx = _stream_reparam_kernel(
            poses, self.resolution, self.L, np.eye(4) if start is None else start, start is None
        )
        self.n_seen += poses.shape[0]
        if idx.size:
            self.last_kept = poses[idx[-1]].copy()
            self.n_kept += idx.size
        return idx


@njit(cache=True)
def _stream_reparam_kernel(poses, resolution, L, start, fresh):
    keep = np.empty(poses.shape[0], dtype=np.int64)
    nk = 0
    last = start
    for k in range(poses.shape[0]):
        if fresh and nk == 0:
            keep[nk] = k
            nk += 1
            last = poses[k]
            continue
        if screw_path_increment(last, poses[k], L) > resolution:
            keep[nk] = k
            nk += 1
            last = poses[k]
    return keep[:nk]
