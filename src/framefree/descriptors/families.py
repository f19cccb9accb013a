"""Descriptor families: the machinery several descriptors share.

* :class:`KalmanDescriptor` — DHB, eFS and ISA: reparameterize, Kalman/RTS-smooth positions and
  quaternions, map the smoothed kinematics to an unweighted (N, 6) representation, weight its
  columns by (L, λ); generic Euclidean DTW distance (``docs/algorithms/descriptors.md``).
* :class:`GlobalDescriptor` — RRV and DSRF: normalize positions by the total arclength of the
  50 Hz trajectory, smooth with a window of 3 samples, forward-difference rates, then a descriptor
  in one frame fitted to the whole motion (``docs/algorithms/descriptors.md``, section *Global
  descriptors*).
* :func:`euclidean_distance_matrix` — the generic classifier distance (``docs/algorithms/dtw.md``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
from numba import njit

from ..core import se3_kernels
from ..core.dtw import POINTWISE_EUCLIDEAN, pack_sequences, path_distance_matrix_kernel
from ..core.kalman import PoseKinematics, smooth_pose_kinematics
from ..core.progress import (
    DEFAULT_SAMPLES,
    cumulative_progress,
    reparameterize,
    reparameterize_poses,
    uniform_time_poses,
)
from ..core.smoothing import smooth_poses
from ..core.trajectory import Trajectory
from ..errors import DegenerateMotionError
from .base import Descriptor

__all__ = [
    "GLOBAL_SMOOTHING_WINDOW",
    "RATE_OFFSET",
    "GlobalDescriptor",
    "KalmanDescriptor",
    "check_finite",
    "euclidean_distance_matrix",
    "global_rates",
    "normalized_poses",
    "normalized_step",
    "total_arclength",
]


def euclidean_distance_matrix(
    queries: Sequence[np.ndarray], models: Sequence[np.ndarray], n_features: int
) -> np.ndarray:
    """Generic classifier distance (docs/algorithms/dtw.md) between every query and every model.

    DTW with Euclidean local cost over all columns, model first; the accumulated cost divided by
    ``n_query + n_model - 1``.

    Parameters
    ----------
    queries, models : sequence of ndarray, shape (K_i, F)
    n_features : int
        Expected F.

    Returns
    -------
    ndarray, shape (n_queries, n_models)
    """
    qd, qo = pack_sequences(list(queries))
    md, mo = pack_sequences(list(models))
    if qd.shape[1] != n_features or md.shape[1] != n_features:
        raise ValueError(
            f"expected sequences with {n_features} columns, got {qd.shape[1]} and {md.shape[1]}"
        )
    return path_distance_matrix_kernel(qd, qo, md, mo, 0, n_features, POINTWISE_EUCLIDEAN, False)


def check_finite(desc: np.ndarray, name: str) -> np.ndarray:
    """Return ``desc`` or raise :class:`DegenerateMotionError` if it holds NaN or infinity."""
    if not np.isfinite(desc).all():
        k = int(np.argmax(~np.isfinite(desc).reshape(desc.shape[0], -1).all(axis=1)))
        raise DegenerateMotionError(
            f"{name} is undefined for this motion (non-finite value at progress sample {k + 1}): "
            "a singular motion such as a pure translation, a fixed-axis rotation or a standstill"
        )
    return desc


class KalmanDescriptor(Descriptor):
    """Common base of DHB, eFS and ISA: reparameterize, Kalman-smooth, map, weight rows.

    Parameters
    ----------
    progress : {"arclength", "angle", "screw"}
        Progress type (ISA: angle or screw only).
    L : float
        Scale length [m]: screw-progress parameter and weight of the rotational rows.
    lam : float
        Weight λ of the higher-order rows.
    n_samples : int
        Number of progress samples (50 in the reference).
    """

    param_names = ("progress", "L", "lam", "n_samples")
    scope = "local"
    trained_parameter = "lam"
    shares_representation = True
    n_features: ClassVar[int] = 6
    default_lam: ClassVar[float] = 1.0
    #: λ values searched by the benchmark (every progress type)
    lam_grid: ClassVar[tuple[float, ...]] = ()

    @classmethod
    def parameter_grid(cls, progress: str) -> tuple[float, ...]:
        """λ values searched by the benchmark (:attr:`lam_grid`, the same for every progress)."""
        return cls.lam_grid

    def __init__(
        self,
        progress: str = "screw",
        L: float = 0.5,
        lam: float | None = None,
        n_samples: int = DEFAULT_SAMPLES,
    ) -> None:
        self.progress = self._check_progress(progress)
        if not L > 0:
            raise ValueError(f"L must be positive, got {L}")
        lam = self.default_lam if lam is None else lam
        if not lam >= 0:
            raise ValueError(f"lam must be non-negative, got {lam}")
        if n_samples < 3:
            raise ValueError(f"n_samples must be at least 3, got {n_samples}")
        self.L = float(L)
        self.lam = float(lam)
        self.n_samples = int(n_samples)

    # ----------------------------------------------------------------- provided by subclasses
    @staticmethod
    def row_weights_for(L: float, lam: float) -> np.ndarray:
        """Column weights (6,) for given L and λ."""
        raise NotImplementedError

    @staticmethod
    def representation_from_kinematics(kin: PoseKinematics) -> np.ndarray:
        """Unweighted descriptor (N, 6) from Kalman-smoothed kinematics."""
        raise NotImplementedError

    # ------------------------------------------------------------------------ shared pipeline
    def row_weights(self) -> np.ndarray:
        """Column weights (6,) of this descriptor's (L, λ)."""
        return self.row_weights_for(self.L, self.lam)

    def weight(self, representation: np.ndarray) -> np.ndarray:
        """Weighted descriptor (N, 6) from an unweighted representation (N, 6)."""
        return representation * self.row_weights()

    def from_kinematics(self, kin: PoseKinematics, weighted: bool = True) -> np.ndarray:
        """Descriptor (N, 6) from Kalman-smoothed kinematics shared with other descriptors.

        DHB, eFS and ISA with the same progress type (and, for screw progress, the same L) smooth
        the same reparameterized poses: compute ``kin = smooth_pose_kinematics(poses, ds)`` once
        and pass it to each of them.

        Raises
        ------
        DegenerateMotionError
            If the result is not finite (singular motion).
        """
        raw = check_finite(self.representation_from_kinematics(kin), self.name)
        return self.weight(raw) if weighted else raw

    def representation(
        self, poses: np.ndarray, ds: float, arclength: float | None = None
    ) -> np.ndarray:
        """Unweighted descriptor (N, 6) of poses (N, 4, 4) at equidistant progress with step ``ds``
        (``arclength`` is not used).

        Raises
        ------
        DegenerateMotionError
            If ``ds`` is not positive or the result is not finite (singular motion).
        """
        return self.from_kinematics(smooth_pose_kinematics(poses, ds), weighted=False)

    def from_reparameterized(
        self, poses: np.ndarray, ds: float, arclength: float | None = None
    ) -> np.ndarray:
        """Weighted descriptor (N, 6) of poses (N, 4, 4) at equidistant progress step ``ds``
        (``arclength`` is not used)."""
        return self.weight(self.representation(poses, ds))

    def compute(self, traj: Trajectory) -> np.ndarray:
        """Descriptor of a trajectory, shape (n_samples, 6).

        Raises
        ------
        DegenerateMotionError
            If the trajectory has no progress of the chosen type, or the descriptor is undefined.
        """
        rep = reparameterize(traj, self.progress, self.L, self.n_samples)
        try:
            return self.from_reparameterized(rep.poses, rep.ds)
        except DegenerateMotionError as exc:
            if exc.source is None and traj.source is not None:
                raise DegenerateMotionError(exc.problem, traj.source) from exc
            raise

    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """Euclidean DTW distance over all 6 columns, divided by ``n_q + n_m - 1`` (docs/algorithms/dtw.md).

        Returns
        -------
        ndarray, shape (n_queries, n_models)
        """
        return euclidean_distance_matrix(queries, models, self.n_features)


#: Gaussian smoothing window of RRV and DSRF (samples).
GLOBAL_SMOOTHING_WINDOW = 3
#: Offset in the denominators of RRV and DSRF (reference value).
RATE_OFFSET = 1e-10


def total_arclength(poses: np.ndarray) -> float:
    """Total distance ℓ [m] travelled by the body origin along poses (M, 4, 4)."""
    return float(cumulative_progress(poses, "arclength")[-1])


def normalized_step(progress: str, ds: float, arclength: float, n: int) -> float:
    """Progress step of the normalized trajectory (docs/algorithms/progress.md).

    Parameters
    ----------
    progress : {"arclength", "angle", "screw"}
    ds : float
        Step of the unnormalized reparameterization (m or rad).
    arclength : float
        Total arclength ℓ of the 50 Hz trajectory [m].
    n : int
        Number of samples.
    """
    if progress == "arclength":
        return 1.0 / (n - 1)
    if progress == "angle":
        return float(ds)
    if progress == "screw":
        return float(ds) / arclength
    raise ValueError(f"unknown progress type {progress!r}")


def normalized_poses(poses: np.ndarray, arclength: float) -> np.ndarray:
    """Copy of poses (N, 4, 4) with positions divided by ``arclength``.

    Raises
    ------
    DegenerateMotionError
        If the arclength is not positive (a pure rotation or a standstill).
    """
    if not (arclength > 0 and math.isfinite(arclength)):
        raise DegenerateMotionError(
            f"the body origin does not move (total arclength {arclength:g} m): RRV and DSRF "
            "normalize positions by it"
        )
    out = np.array(poses, dtype=np.float64, copy=True)
    out[:, :3, 3] /= arclength
    return out


@njit(cache=True)
def rates_kernel(T, ds):
    """Forward-difference rates ``ω_k`` (N-1, 3) and ``u_k`` (N-1, 3) of poses (N, 4, 4)."""
    n = T.shape[0]
    w = np.empty((n - 1, 3))
    u = np.empty((n - 1, 3))
    for k in range(n - 1):
        phi = se3_kernels.rotation_increment_one(T[k], T[k + 1])
        for r in range(3):
            w[k, r] = phi[r] / ds
            u[k, r] = (T[k + 1, r, 3] - T[k, r, 3]) / ds
    return w, u


def global_rates(
    poses: np.ndarray, ds: float, arclength: float, progress: str
) -> tuple[np.ndarray, np.ndarray]:
    """Normalize (docs/algorithms/progress.md), smooth (window 3) and differentiate a
    reparameterized trajectory.

    Parameters
    ----------
    poses : ndarray, shape (N, 4, 4)
        Unnormalized poses at equidistant progress.
    ds : float
        Their progress step.
    arclength : float
        Total arclength ℓ of the 50 Hz trajectory [m].
    progress : {"arclength", "angle", "screw"}
        Progress type of the reparameterization.

    Returns
    -------
    omega, u : ndarray, shape (N-1, 3)
        Angular rate (world) and velocity of the body origin (world, in units of ℓ) per unit of
        normalized progress.
    """
    n = poses.shape[0]
    normalized = normalized_poses(poses, arclength)  # raises first if ℓ is not positive
    step = normalized_step(progress, ds, arclength, n)
    if not (step > 0 and math.isfinite(step)):
        raise DegenerateMotionError(f"the normalized progress step is {step:g}, not positive")
    return rates_kernel(smooth_poses(normalized, GLOBAL_SMOOTHING_WINDOW), step)


class GlobalDescriptor(Descriptor):
    """Common base of RRV and DSRF (normalized, window-3-smoothed finite differences).

    Parameters
    ----------
    progress : {"arclength", "angle", "screw"}
        Progress type (default "screw").
    L : float
        Scale length [m], used by screw progress only (default 0.5, the middle of 0.1..0.9).
    n_samples : int
        Number of progress samples (50); the descriptor has ``n_samples - 1`` rows.
    """

    param_names = ("progress", "L", "n_samples")
    scope = "global"
    n_features: int = 0

    @classmethod
    def trains_scale_length(cls, progress: str) -> bool:
        """L matters only through screw-path progress, so it is searched only there."""
        return progress == "screw"

    def __init__(self, progress: str = "screw", L: float = 0.5, n_samples: int = DEFAULT_SAMPLES):
        self.progress = self._check_progress(progress)
        if not L > 0:
            raise ValueError(f"L must be positive, got {L}")
        if n_samples < 3:
            raise ValueError(f"n_samples must be at least 3, got {n_samples}")
        self.L = float(L)
        self.n_samples = int(n_samples)

    def from_rates(self, omega: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Descriptor (K, F) from normalized rates (K, 3) and (K, 3)."""
        raise NotImplementedError

    def from_reparameterized(
        self, poses: np.ndarray, ds: float, arclength: float | None = None
    ) -> np.ndarray:
        """Descriptor (N-1, F) from the unnormalized reparameterization.

        Parameters
        ----------
        poses : ndarray, shape (N, 4, 4)
            Poses at equidistant progress of this descriptor's type (screw: with its L),
            positions in metres (not yet normalized).
        ds : float
            Their progress step.
        arclength : float
            Total arclength ℓ [m] of the 50 Hz trajectory they were resampled from
            (for arclength progress it is the reparameterization's ``total``).

        Raises
        ------
        DegenerateMotionError
            If ℓ is not positive or the result is not finite.
        ValueError
            If ``arclength`` is not given.
        """
        if arclength is None:
            raise ValueError(f"{self.name} needs the 50 Hz arclength to normalize positions")
        omega, u = global_rates(poses, ds, arclength, self.progress)
        return check_finite(self.from_rates(omega, u), self.name)

    def compute(self, traj: Trajectory) -> np.ndarray:
        """Descriptor of a trajectory, shape (n_samples - 1, F).

        Raises
        ------
        DegenerateMotionError
            If the trajectory has no progress of the chosen type or its body origin never moves.
        """
        T50 = uniform_time_poses(traj)
        ell = total_arclength(T50)
        rep = reparameterize_poses(T50, self.progress, self.L, self.n_samples, traj.source)
        try:
            return self.from_reparameterized(rep.poses, rep.ds, ell)
        except DegenerateMotionError as exc:
            if exc.source is None and traj.source is not None:
                raise DegenerateMotionError(exc.problem, traj.source) from exc
            raise
