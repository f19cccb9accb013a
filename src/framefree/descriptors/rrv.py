"""RRV: Rotation and Relative Velocity, a global descriptor (§5.5), and the front end it shares
with DSRF: the normalization by the total arclength (§4.7), Gaussian smoothing (window 3) and the
finite-difference rates.

Normalization (§4.7). ℓ is the total arclength of the 50 Hz trajectory. The reference divides the
positions by ℓ before (arclength, angle progress) or after (screw progress) reparameterizing.
Scaling all translations by 1/ℓ is an automorphism of SE(3) that commutes with ScLERP and scales
arclength progress by 1/ℓ while leaving angle progress unchanged, so all three cases are obtained
from the *unnormalized* reparameterization (the cached one of the benchmark): divide the resampled
positions by ℓ and use the step

* arclength: ``Δs = 1/(N-1)``;
* angle: ``Δs`` = the angle step of the reparameterization;
* screw: ``Δs`` = the screw step divided by ℓ.

RRV pipeline (reference ``calculate_RRV_descriptor.m``), after normalization and smoothing, for
k = 1..N-1:

* ``ω_k = log(R_{k+1} R_kᵀ)^∨ / Δs``, ``u_k = (p_{k+1} - p_k)/Δs``, ``β_k = |ω_k|`` (a rate, as in
  the reference, Ambiguity 5.5), ``a_k = ω_k/(β_k + 1e-10)``;
* global frame U: left singular vectors of ``[a_1 … a_{N-1}]``; ``U₁``, ``U₂`` negated when their
  dot product with the mean of the ``a_k`` is negative, ``U₃ = U₁ × U₂``;
* ``S_k = (cos(β_k/2), sin(β_k/2) Uᵀa_k)``; ``u^loc_k = R(S_k)ᵀ Uᵀ u_k``;
  ``ν_k = u^loc_k / sqrt(|u^loc_k| + 1e-10)``.

Output (N-1, 7): ``[S_k, ν_k]``. Distance: Euclidean DTW over all 7 columns (§6.3, Ambiguity 6.3).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from .. import se3
from ..errors import DegenerateMotionError
from ..progress import (
    DEFAULT_SAMPLES,
    cumulative_progress,
    reparameterize_poses,
    uniform_time_poses,
)
from ..smoothing import smooth_poses
from ..trajectory import Trajectory
from .base import Descriptor, register
from .dhb import check_finite, euclidean_distance_matrix

__all__ = [
    "RRV",
    "GlobalDescriptor",
    "global_rates",
    "normalized_poses",
    "normalized_step",
    "rrv_from_rates",
    "total_arclength",
]

#: Gaussian smoothing window of RRV and DSRF (samples).
GLOBAL_SMOOTHING_WINDOW = 3
#: Offset in the denominators of RRV and DSRF (reference value).
RATE_OFFSET = 1e-10


def total_arclength(poses: np.ndarray) -> float:
    """Total distance ℓ [m] travelled by the body origin along poses (M, 4, 4)."""
    return float(cumulative_progress(poses, "arclength")[-1])


def normalized_step(progress: str, ds: float, arclength: float, n: int) -> float:
    """Progress step of the normalized trajectory (§4.7).

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
        phi = se3.rotation_increment_one(T[k], T[k + 1])
        for r in range(3):
            w[k, r] = phi[r] / ds
            u[k, r] = (T[k + 1, r, 3] - T[k, r, 3]) / ds
    return w, u


def global_rates(
    poses: np.ndarray, ds: float, arclength: float, progress: str
) -> tuple[np.ndarray, np.ndarray]:
    """Normalize (§4.7), smooth (window 3) and differentiate a reparameterized trajectory.

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


@njit(cache=True, error_model="numpy")
def rrv_kernel(w, u):
    """RRV (N-1, 7) from angular rates ``w`` (N-1, 3) and velocities ``u`` (N-1, 3)."""
    n = w.shape[0]
    A = np.empty((3, n))
    beta = np.empty(n)
    mean = np.zeros(3)
    for k in range(n):
        b = math.sqrt(w[k, 0] ** 2 + w[k, 1] ** 2 + w[k, 2] ** 2)
        beta[k] = b
        for r in range(3):
            A[r, k] = w[k, r] / (b + RATE_OFFSET)
            mean[r] += A[r, k]
    mean /= n
    U, _, _ = np.linalg.svd(A, full_matrices=False)
    G = np.empty((3, 3))
    for c in range(2):
        d = mean[0] * U[0, c] + mean[1] * U[1, c] + mean[2] * U[2, c]
        s = -1.0 if d < 0.0 else 1.0
        for r in range(3):
            G[r, c] = s * U[r, c]
    G[0, 2] = G[1, 0] * G[2, 1] - G[2, 0] * G[1, 1]
    G[1, 2] = G[2, 0] * G[0, 1] - G[0, 0] * G[2, 1]
    G[2, 2] = G[0, 0] * G[1, 1] - G[1, 0] * G[0, 1]
    out = np.empty((n, 7))
    S = np.empty(4)
    ug = np.empty(3)
    for k in range(n):
        half = 0.5 * beta[k]
        sh = math.sin(half)
        S[0] = math.cos(half)
        for c in range(3):
            S[1 + c] = sh * (G[0, c] * A[0, k] + G[1, c] * A[1, k] + G[2, c] * A[2, k])
            ug[c] = G[0, c] * u[k, 0] + G[1, c] * u[k, 1] + G[2, c] * u[k, 2]
        Rl = se3.matrix_from_quaternion_one(S)
        nl = 0.0
        loc = np.empty(3)
        for c in range(3):
            loc[c] = Rl[0, c] * ug[0] + Rl[1, c] * ug[1] + Rl[2, c] * ug[2]
            nl += loc[c] * loc[c]
        den = math.sqrt(math.sqrt(nl) + RATE_OFFSET)
        for c in range(4):
            out[k, c] = S[c]
        for c in range(3):
            out[k, 4 + c] = loc[c] / den
    return out


def rrv_from_rates(omega: np.ndarray, u: np.ndarray) -> np.ndarray:
    """RRV descriptor (K, 7) from angular rates (K, 3) and velocities (K, 3) (§5.5 steps 3–7)."""
    return rrv_kernel(
        np.ascontiguousarray(omega, dtype=np.float64), np.ascontiguousarray(u, dtype=np.float64)
    )


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
    n_features: int = 0

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

    def from_reparameterized(self, poses: np.ndarray, ds: float, arclength: float) -> np.ndarray:
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
        """
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


@register
class RRV(GlobalDescriptor):
    """Rotation and Relative Velocity (§5.5), generic Euclidean DTW distance (§6.3).

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
    Output (n_samples - 1, 7): quaternion-like ``S_k`` (scalar first) and the square-root velocity
    ``ν_k`` in the global invariant frame. World-frame invariant through that frame; not
    body-frame invariant (positions of the body origin, arclength normalization).
    """

    name = "rrv"
    n_features = 7

    def from_rates(self, omega: np.ndarray, u: np.ndarray) -> np.ndarray:
        """RRV (K, 7) from normalized rates."""
        return rrv_from_rates(omega, u)

    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """Euclidean DTW over all 7 columns divided by ``n_q + n_m - 1`` (§6.3).

        Returns
        -------
        ndarray, shape (n_queries, n_models)
        """
        return euclidean_distance_matrix(queries, models, 7)
