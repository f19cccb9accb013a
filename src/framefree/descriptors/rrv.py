"""RRV: Rotation and Relative Velocity, a global descriptor (docs/algorithms/descriptors.md), and
the front end it shares with DSRF: the normalization by the total arclength
(docs/algorithms/progress.md), Gaussian smoothing (window 3) and the finite-difference rates.

Normalization (docs/algorithms/progress.md). ℓ is the total arclength of the 50 Hz trajectory. The
reference divides the positions by ℓ before (arclength, angle progress) or after (screw progress)
reparameterizing. Scaling all translations by 1/ℓ is an automorphism of SE(3) that commutes with
ScLERP and scales arclength progress by 1/ℓ while leaving angle progress unchanged, so all three
cases are obtained from the *unnormalized* reparameterization (the cached one of the benchmark):
divide the resampled positions by ℓ and use the step

* arclength: ``Δs = 1/(N-1)``;
* angle: ``Δs`` = the angle step of the reparameterization;
* screw: ``Δs`` = the screw step divided by ℓ.

RRV pipeline (reference ``calculate_RRV_descriptor.m``), after normalization and smoothing, for
k = 1..N-1:

* ``ω_k = log(R_{k+1} R_kᵀ)^∨ / Δs``, ``u_k = (p_{k+1} - p_k)/Δs``, ``β_k = |ω_k|`` (a rate, as in
  the reference, docs/algorithms/descriptors.md), ``a_k = ω_k/(β_k + 1e-10)``;
* global frame U: left singular vectors of ``[a_1 … a_{N-1}]``; ``U₁``, ``U₂`` negated when their
  dot product with the mean of the ``a_k`` is negative, ``U₃ = U₁ × U₂``;
* ``S_k = (cos(β_k/2), sin(β_k/2) Uᵀa_k)``; ``u^loc_k = R(S_k)ᵀ Uᵀ u_k``;
  ``ν_k = u^loc_k / sqrt(|u^loc_k| + 1e-10)``.

Output (N-1, 7): ``[S_k, ν_k]``. Distance: Euclidean DTW over all 7 columns (docs/algorithms/dtw.md).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from ..core import se3_kernels
from .base import register
from .families import RATE_OFFSET, GlobalDescriptor, euclidean_distance_matrix

__all__ = ["RRV", "rrv_from_rates"]


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
        Rl = se3_kernels.matrix_from_quaternion_one(S)
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
    """RRV descriptor (K, 7) from angular rates (K, 3) and velocities (K, 3)
    (docs/algorithms/descriptors.md)."""
    return rrv_kernel(
        np.ascontiguousarray(omega, dtype=np.float64), np.ascontiguousarray(u, dtype=np.float64)
    )


@register
class RRV(GlobalDescriptor):
    """Rotation and Relative Velocity (docs/algorithms/descriptors.md), generic Euclidean DTW
    distance (docs/algorithms/dtw.md).

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
    display_name = "RRV"
    n_features = 7

    def from_rates(self, omega: np.ndarray, u: np.ndarray) -> np.ndarray:
        """RRV (K, 7) from normalized rates."""
        return rrv_from_rates(omega, u)

    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """Euclidean DTW over all 7 columns divided by ``n_q + n_m - 1`` (docs/algorithms/dtw.md).

        Returns
        -------
        ndarray, shape (n_queries, n_models)
        """
        return euclidean_distance_matrix(queries, models, 7)
