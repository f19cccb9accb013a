"""ISA: instantaneous-screw-axis invariants (De Schutter 2010), analytic version
(docs/algorithms/descriptors.md).

Pipeline (reference ``calculate_ISA_descriptor.m``): reparameterize with angle or screw progress
(docs/algorithms/progress.md), Kalman/RTS-smooth (docs/algorithms/smoothing.md), form the spatial
screw twist ``(Ω, V)`` and its first two derivatives with the smoothed positions
(docs/algorithms/smoothing.md); add 1e-12 to every entry of the twist and of its first derivative;
then per sample

* ``ω₁ = |Ω|``, ``e_x = Ω/ω₁``, ``e_y = (Ω × Ω̇)/|Ω × Ω̇|``, ``e_z = e_x × e_y``;
* ``c = -Ω̇·e_z`` (= ω₁ω₂), ``ω₂ = c/ω₁``, ``ω₃ = (Ω̈·e_y)/c``;
* ISA-frame origin ``p_z = -(V·e_y)/ω₁``, ``p_y = (V·e_z)/ω₁``,
  ``p_x = -(p_z(Ω̇·e_x) + V̇·e_y)/c``;
* ``v₁ = V·e_x``; ``v₂ = (p_y(Ω̇·e_x) - V̇·e_z - ω₂v₁)/ω₁``;
* ``v₃ = (p_z(Ω̈·e_x) - p_x(Ω̈·e_z) + V̈·e_y)/c - ω₃(v₂/ω₂ + v₁/ω₁)``.

Columns ``[ω₁, ω₂, ω₃, v₁, v₂, v₃]`` weighted by ``(L, λL, λL, 1, λ, λ)`` (rows 5–6 without L).
Bi-invariant, but singular for pure translations (ω₁ → 0) and fixed-axis motions
(Ω × Ω̇ → 0); there the values are huge, or undefined (then :class:`DegenerateMotionError`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.kalman import PoseKinematics
from .base import register
from .families import KalmanDescriptor

__all__ = ["ISA", "isa_representation"]

#: Constant added to every entry of the twist and its first derivative (reference value).
ISA_OFFSET = 1e-12


@njit(cache=True)
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, error_model="numpy")
def isa_kernel(st, offset):
    """Unweighted ISA invariants (N, 6) from spatial twist derivatives ``st`` (N, 3, 6)."""
    n = st.shape[0]
    out = np.empty((n, 6))
    W = np.empty(3)
    Wd = np.empty(3)
    Wdd = np.empty(3)
    V = np.empty(3)
    Vd = np.empty(3)
    Vdd = np.empty(3)
    ex = np.empty(3)
    ey = np.empty(3)
    ez = np.empty(3)
    for k in range(n):
        for r in range(3):
            W[r] = st[k, 0, r] + offset
            V[r] = st[k, 0, 3 + r] + offset
            Wd[r] = st[k, 1, r] + offset
            Vd[r] = st[k, 1, 3 + r] + offset
            Wdd[r] = st[k, 2, r]
            Vdd[r] = st[k, 2, 3 + r]
        w1 = math.sqrt(_dot(W, W))
        cx = W[1] * Wd[2] - W[2] * Wd[1]
        cy = W[2] * Wd[0] - W[0] * Wd[2]
        cz = W[0] * Wd[1] - W[1] * Wd[0]
        nc = math.sqrt(cx * cx + cy * cy + cz * cz)
        for r in range(3):
            ex[r] = W[r] / w1
        ey[0] = cx / nc
        ey[1] = cy / nc
        ey[2] = cz / nc
        ez[0] = ex[1] * ey[2] - ex[2] * ey[1]
        ez[1] = ex[2] * ey[0] - ex[0] * ey[2]
        ez[2] = ex[0] * ey[1] - ex[1] * ey[0]
        c = -_dot(Wd, ez)
        w2 = c / w1
        w3 = _dot(Wdd, ey) / c
        pz = -_dot(V, ey) / w1
        py = _dot(V, ez) / w1
        px = -(pz * _dot(Wd, ex) + _dot(Vd, ey)) / c
        v1 = _dot(V, ex)
        v2 = (py * _dot(Wd, ex) - _dot(Vd, ez) - w2 * v1) / w1
        v3 = (pz * _dot(Wdd, ex) - px * _dot(Wdd, ez) + _dot(Vdd, ey)) / c - w3 * (
            v2 / w2 + v1 / w1
        )
        out[k, 0] = w1
        out[k, 1] = w2
        out[k, 2] = w3
        out[k, 3] = v1
        out[k, 4] = v2
        out[k, 5] = v3
    return out


def isa_representation(spatial_twists: np.ndarray, offset: float = ISA_OFFSET) -> np.ndarray:
    """Unweighted ISA invariants.

    Parameters
    ----------
    spatial_twists : ndarray, shape (N, 3, 6)
        ``[:, d, :]`` = d-th progress derivative of the spatial screw twist ``(Ω, V)``
        (V referred to the world origin).
    offset : float
        Constant added to the twist and its first derivative (1e-12 in the reference).

    Returns
    -------
    ndarray, shape (N, 6)
        ``[ω₁, ω₂, ω₃, v₁, v₂, v₃]`` per unit progress (may be non-finite at singular motions).
    """
    st = np.ascontiguousarray(spatial_twists, dtype=np.float64)
    if st.ndim != 3 or st.shape[1:] != (3, 6):
        raise ValueError(f"spatial_twists must have shape (N, 3, 6), got {st.shape}")
    return isa_kernel(st, float(offset))


@register
class ISA(KalmanDescriptor):
    """Analytic ISA invariants (docs/algorithms/descriptors.md), Euclidean DTW distance
    (docs/algorithms/dtw.md).

    Parameters
    ----------
    progress : {"angle", "screw"}
        Progress type (default "screw").
    L : float
        Scale length [m] (default 0.5, the middle of the grid 0.1..0.9).
    lam : float
        Weight λ of the higher-order rows (default 0.01, the middle of the grid 0.0001..1).
    n_samples : int
        Number of progress samples (50).

    Notes
    -----
    Output columns ``[Lω₁, λLω₂, λLω₃, v₁, λv₂, λv₃]``, shape (n_samples, 6).
    """

    name = "isa"
    display_name = "ISA"
    progress_types = ("angle", "screw")
    default_lam = 0.01
    lam_grid = (0.0001, 0.001, 0.01, 0.1, 1.0)

    @staticmethod
    def row_weights_for(L: float, lam: float) -> np.ndarray:
        """``(L, λL, λL, 1, λ, λ)``."""
        return np.array([L, lam * L, lam * L, 1.0, lam, lam])

    @staticmethod
    def representation_from_kinematics(kin: PoseKinematics) -> np.ndarray:
        """Unweighted ISA (N, 6) of the smoothed spatial screw twist and its derivatives."""
        return isa_kernel(kin.spatial_twists(), ISA_OFFSET)
