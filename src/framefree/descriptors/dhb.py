"""DHB: Denavit–Hartenberg-inspired Bidirectional invariants (§5.1), and the machinery shared by the
three Kalman-based local descriptors DHB, eFS and ISA.

Pipeline (reference ``calculate_DHB_descriptor.m``):

1. reparameterize to N = 50 equidistant progress samples, step Δs (§4.5);
2. Kalman/RTS-smooth positions and quaternions with step Δs (§3.2) and form the pose twist
   ``(ω, ṗ)`` (§3.3);
3. map each block (x = ω, then x = ṗ) to a magnitude and two angles between successive vectors:
   ``a_k = |x_k|``; ``θ¹_k = arctan(|x_k × x_{k+1}| / (x_k·x_{k+1}))`` (0 if the denominator is at
   most 1e-10 in magnitude; last sample 0); ``θ²_k = arctan(|x_{k+1}| x_{k+1}·(x_k × x_{k+2}) /
   ((x_{k+1} × x_k)·(x_{k+1} × x_{k+2})))`` (same guard; last two samples 0). The arctangent is the
   single-argument one, as in the reference (Ambiguity 5.1);
4. columns ``[a^ω, θ¹^ω, θ²^ω, a^v, θ¹^v, θ²^v]`` weighted by ``(L, λL, λL, 1, λL, λL)``.

The unweighted (N, 6) *representation* depends on the trajectory, the progress type and, for screw
progress only, on L; the weights are a cheap final step (see :meth:`KalmanDescriptor.weight`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
from numba import njit

from ..dtw import POINTWISE_EUCLIDEAN, pack_sequences, path_distance_matrix_kernel
from ..errors import DegenerateMotionError
from ..kalman import PoseKinematics, smooth_pose_kinematics
from ..progress import DEFAULT_SAMPLES, reparameterize
from ..trajectory import Trajectory
from .base import Descriptor, register

__all__ = [
    "DHB",
    "KalmanDescriptor",
    "check_finite",
    "dhb_block",
    "dhb_representation",
    "euclidean_distance_matrix",
]

#: Guard on the denominators of the DHB angles (reference value).
ANGLE_GUARD = 1e-10


def euclidean_distance_matrix(
    queries: Sequence[np.ndarray], models: Sequence[np.ndarray], n_features: int
) -> np.ndarray:
    """Generic classifier distance (§6.3) between every query and every model.

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
    return path_distance_matrix_kernel(qd, qo, md, mo, 0, n_features, POINTWISE_EUCLIDEAN)


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
    n_features: ClassVar[int] = 6
    default_lam: ClassVar[float] = 1.0

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

    def representation(self, poses: np.ndarray, ds: float) -> np.ndarray:
        """Unweighted descriptor (N, 6) of poses (N, 4, 4) at equidistant progress with step ``ds``.

        Raises
        ------
        DegenerateMotionError
            If ``ds`` is not positive or the result is not finite (singular motion).
        """
        return self.from_kinematics(smooth_pose_kinematics(poses, ds), weighted=False)

    def from_reparameterized(self, poses: np.ndarray, ds: float) -> np.ndarray:
        """Weighted descriptor (N, 6) of poses (N, 4, 4) at equidistant progress step ``ds``."""
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
        """Euclidean DTW distance over all 6 columns, divided by ``n_q + n_m - 1`` (§6.3).

        Returns
        -------
        ndarray, shape (n_queries, n_models)
        """
        return euclidean_distance_matrix(queries, models, self.n_features)


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
    """DHB invariants of the Kalman-smoothed pose twist (§5.1), Euclidean DTW distance (§6.3).

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
    default_lam = 1.0

    @staticmethod
    def row_weights_for(L: float, lam: float) -> np.ndarray:
        """``(L, λL, λL, 1, λL, λL)``."""
        return np.array([L, lam * L, lam * L, 1.0, lam * L, lam * L])

    @staticmethod
    def representation_from_kinematics(kin: PoseKinematics) -> np.ndarray:
        """Unweighted DHB (N, 6) of the smoothed pose twist ``kin.pose_twists[:, 0]``."""
        return dhb_kernel(np.ascontiguousarray(kin.pose_twists[:, 0, :]))
