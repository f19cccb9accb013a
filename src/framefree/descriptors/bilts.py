"""BILTS and BILTS+: bi-invariant local trajectory-shape descriptors (docs/algorithms/bilts.md).

Pipeline per trajectory (docs/algorithms/bilts.md):

1. resample at 50 Hz, reparameterize to N = 50 equidistant progress samples, step Δs;
2. window spacing ``m = min(23, max(1, round(ds_scale / Δs)))``;
3. Gaussian smoothing (window 20 for BILTS, 10 for BILTS+) of positions and quaternions;
4. central spatial twists (with the reference's boundary quirk) plus 1e-12 noise (seeded);
5. for each centre k: the window ``[ξ_{k-m}, ξ_k, ξ_{k+m}]`` is re-expressed in a moving frame
   {Q, p} found by an extended QR decomposition (eQR); BILTS+ keeps p within L of the body origin;
6. row layout per sample (24 columns): ``Lω'₋, v'₋, Lω'₀, v'₀, Lω'₊, v'₊`` (18 numbers), then the
   ascending singular values of the rotational and translational 3×3 blocks (6 numbers).

Distances: DTW path on the singular values, then the sum along the path of the squared Euclidean
difference of the 18 twist entries (BILTS) or of the Kabsch residual of the six 3-vectors (BILTS+),
divided by ``n_query + n_model - 1``. framefree's ``align="gram"`` (off by default) aligns on the
21 distinct dot products of the six vectors instead (docs/algorithms/bilts.md#gram-alignment).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
from numba import njit

from ..core import se3
from ..core.dtw import (
    POINTWISE_KABSCH,
    POINTWISE_SQUARED,
    pack_sequences,
    path_distance_kernel,
    path_distance_matrix_kernel,
)
from ..core.progress import DEFAULT_SAMPLES, reparameterize
from ..core.pruning import DistanceSpec
from ..core.smoothing import smooth_poses
from ..core.trajectory import Trajectory
from .base import Descriptor, register

__all__ = [
    "BILTS",
    "MAX_WINDOW_SPACING",
    "BILTSPlus",
    "bilts_sample",
    "bilts_windows",
    "window_spacing",
]

#: Largest window spacing m (leaves at least 4 of 50 samples).
MAX_WINDOW_SPACING = 23
#: Standard deviation of the perturbation added to every twist entry (reference, docs/algorithms/bilts.md).
TWIST_NOISE = 1e-12
#: Number of columns of a BILTS sample.
N_FEATURES = 24
#: Column names: the three window twists in the moving frame, then the ascending singular values.
_TWIST_NAMES = tuple(
    f"{part}_{where}_{axis}"
    for where in ("prev", "centre", "next")
    for part in ("Lw", "v")
    for axis in "xyz"
)
FEATURE_NAMES = (*_TWIST_NAMES, "sigma_Lw_1", "sigma_Lw_2", "sigma_Lw_3")
FEATURE_NAMES = (*FEATURE_NAMES, "sigma_v_1", "sigma_v_2", "sigma_v_3")
#: Upper triangle (row-major) of the 6 × 6 Gram matrix of a sample's six 3-vectors
_UPPER = np.triu_indices(6)
#: Columns added by ``align="gram"``: the distinct dot products of the six window vectors
GRAM_NAMES = tuple(f"gram_{i}{j}" for i, j in zip(*_UPPER, strict=True))
#: Alignments: ``"singular"`` (the reference: DTW on the six singular values) or ``"gram"``
ALIGNMENTS = ("singular", "gram")


def gram_columns(samples: np.ndarray) -> np.ndarray:
    """The 21 distinct dot products of each sample's six 3-vectors (columns 0–17), shape (K, 21).

    A rotation of the moving frame leaves them unchanged, as it leaves the singular values; unlike
    those, they keep the angles between the window's twists, which tell a straight stroke from a
    corner and one stroke from the next (docs/algorithms/bilts.md#gram-alignment).
    """
    V = np.ascontiguousarray(samples[:, :18]).reshape(len(samples), 6, 3)
    G = np.einsum("kia,kja->kij", V, V)
    return np.ascontiguousarray(G[:, _UPPER[0], _UPPER[1]])


def window_spacing(ds_scale: float, ds: float, cap: int = MAX_WINDOW_SPACING) -> int:
    """``m = min(cap, max(1, round(ds_scale / ds)))`` with MATLAB rounding (halves away from zero)."""
    if not (ds > 0 and math.isfinite(ds)):
        return 1
    ratio = ds_scale / ds
    m = math.floor(ratio + 0.5) if math.isfinite(ratio) else 1
    return min(cap, max(1, m))


@njit(cache=True)
def _root_eigvals_into(a, out, at):
    """``out[at:at+3]``: square roots of the eigenvalues of the symmetric 3×3 ``a`` (a Gram
    matrix, overwritten), ascending, negative rounding clipped at 0 (no allocation)."""
    _sym3_diagonalize(a)
    e0, e1, e2 = a[0, 0], a[1, 1], a[2, 2]
    if e0 > e1:
        e0, e1 = e1, e0
    if e1 > e2:
        e1, e2 = e2, e1
    if e0 > e1:
        e0, e1 = e1, e0
    out[at] = math.sqrt(max(e0, 0.0))
    out[at + 1] = math.sqrt(max(e1, 0.0))
    out[at + 2] = math.sqrt(max(e2, 0.0))


@njit(cache=True)
def _sym3_diagonalize(a):
    """Cyclic Jacobi rotations of a symmetric 3×3 matrix in place, until it is diagonal."""
    for _ in range(50):
        off = a[0, 1] * a[0, 1] + a[0, 2] * a[0, 2] + a[1, 2] * a[1, 2]
        diag = a[0, 0] * a[0, 0] + a[1, 1] * a[1, 1] + a[2, 2] * a[2, 2]
        if off <= 1e-36 * diag or off == 0.0:
            break
        for p in range(2):
            for q in range(p + 1, 3):
                apq = a[p, q]
                if apq == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * apq)
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(3):
                    akp = a[k, p]
                    akq = a[k, q]
                    a[k, p] = c * akp - s * akq
                    a[k, q] = s * akp + c * akq
                for k in range(3):
                    apk = a[p, k]
                    aqk = a[q, k]
                    a[p, k] = c * apk - s * aqk
                    a[q, k] = s * apk + c * aqk


@njit(cache=True)
def _gram(F):
    """``F Fᵀ`` of a 3×3 matrix, written out."""
    G = np.empty((3, 3))
    _gram_into(F, G)
    return G


@njit(cache=True)
def _gram_into(F, G):
    """:func:`_gram` written into ``G``."""
    for i in range(3):
        for j in range(i, 3):
            G[i, j] = F[i, 0] * F[j, 0] + F[i, 1] * F[j, 1] + F[i, 2] * F[j, 2]
            G[j, i] = G[i, j]


# Kept as one compiled function (about 75 lines of code): it runs once per descriptor sample in
# the hot loop, and its numbered steps follow docs/algorithms/bilts.md one to one.
@njit(cache=True)
def bilts_sample(xm, x0, xp, p_obj, L, regularized, axis_prior):
    """One BILTS(+) sample (24,) from the window twists ``ξ_{k-m}, ξ_k, ξ_{k+m}`` (6,) each.

    Parameters
    ----------
    xm, x0, xp : ndarray, shape (6,)
        Spatial twists (ω; v), v referred to the world origin.
    p_obj : ndarray, shape (3,)
        Body origin at the window centre (world), the centre of the BILTS+ clamp.
    L : float
        Scale length [m]: weight of the rotational rows and clamp radius.
    regularized : bool
        BILTS+ (clamp the frame origin within L of ``p_obj``) or BILTS.
    axis_prior : float
        κ ≥ 0. 0: the reference's frame origin. κ > 0 (framefree extension, BILTS+ only): the
        origin's position along the centre screw axis is a regularized least-squares solution pulled
        towards the foot of the perpendicular from ``p_obj`` with weight κ‖ω_k‖, so that a rotation
        about a nearly fixed axis no longer places it by noise (docs/algorithms/bilts.md#axis-prior).
    """
    # X = W A = [ξ_k, ξ_{k+m} - ξ_{k-m}, ξ_{k-m}]
    X = np.empty((6, 3))
    for r in range(6):
        X[r, 0] = x0[r]
        X[r, 1] = xp[r] - xm[r]
        X[r, 2] = xm[r]
    # Gram-Schmidt on the first two rotational columns
    Q = np.empty((3, 3))
    n1 = math.sqrt(X[0, 0] ** 2 + X[1, 0] ** 2 + X[2, 0] ** 2)
    for r in range(3):
        Q[r, 0] = X[r, 0] / n1
    d = X[0, 1] * Q[0, 0] + X[1, 1] * Q[1, 0] + X[2, 1] * Q[2, 0]
    u = np.empty(3)
    for r in range(3):
        u[r] = X[r, 1] - d * Q[r, 0]
    nu = math.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
    for r in range(3):
        Q[r, 1] = u[r] / nu
    Q[0, 2] = Q[1, 0] * Q[2, 1] - Q[2, 0] * Q[1, 1]
    Q[1, 2] = Q[2, 0] * Q[0, 1] - Q[0, 0] * Q[2, 1]
    Q[2, 2] = Q[0, 0] * Q[1, 1] - Q[1, 0] * Q[0, 1]
    # R1 = Q^T X1, Y = Q^T X2
    R1 = np.empty((3, 3))
    Y = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            R1[i, j] = Q[0, i] * X[0, j] + Q[1, i] * X[1, j] + Q[2, i] * X[2, j]
            Y[i, j] = Q[0, i] * X[3, j] + Q[1, i] * X[4, j] + Q[2, i] * X[5, j]
    # frame origin in Q coordinates: on the ISA of the centre twist, with Y(3,2) made zero
    ps = np.empty(3)
    ps[2] = Y[1, 0] / R1[0, 0]
    ps[1] = -Y[2, 0] / R1[0, 0]
    # along the axis: R1[1, 1] * x = b (entry (3, 2) of the translational block made zero)
    b = Y[2, 1] + R1[0, 1] * ps[1]
    ps[0] = b / R1[1, 1]
    if regularized:
        qo = np.empty(3)
        for i in range(3):
            qo[i] = Q[0, i] * p_obj[0] + Q[1, i] * p_obj[1] + Q[2, i] * p_obj[2]
        if axis_prior > 0.0:  # regularized least squares, pulled towards the body's foot point
            w2 = (axis_prior * R1[0, 0]) ** 2
            ps[0] = (R1[1, 1] * b + w2 * qo[0]) / (R1[1, 1] ** 2 + w2)
        d0, d1, d2 = ps[0] - qo[0], ps[1] - qo[1], ps[2] - qo[2]
        nd = math.sqrt(d0 ** 2 + d1 ** 2 + d2 ** 2)
        if nd > L:
            shrink = L / nd
            d0, d1, d2 = d0 * shrink, d1 * shrink, d2 * shrink
        ps[0], ps[1], ps[2] = qo[0] + d0, qo[1] + d1, qo[2] + d2
    # R2 = Y - [p*]x R1
    R2 = np.empty((3, 3))
    for j in range(3):
        c0 = ps[1] * R1[2, j] - ps[2] * R1[1, j]
        c1 = ps[2] * R1[0, j] - ps[0] * R1[2, j]
        c2 = ps[0] * R1[1, j] - ps[1] * R1[0, j]
        R2[0, j] = Y[0, j] - c0
        R2[1, j] = Y[1, j] - c1
        R2[2, j] = Y[2, j] - c2
    # undo the mixing: F = [R1; R2] A^-1 -> columns ξ'_{k-m}, ξ'_k, ξ'_{k+m}
    out = np.empty(24)
    Fw = np.empty((3, 3))
    Fv = np.empty((3, 3))
    for r in range(3):
        Fw[r, 0] = L * R1[r, 2]
        Fw[r, 1] = L * R1[r, 0]
        Fw[r, 2] = L * (R1[r, 1] + R1[r, 2])
        Fv[r, 0] = R2[r, 2]
        Fv[r, 1] = R2[r, 0]
        Fv[r, 2] = R2[r, 1] + R2[r, 2]
    for c in range(3):
        for r in range(3):
            out[6 * c + r] = Fw[r, c]
            out[6 * c + 3 + r] = Fv[r, c]
    _gram_into(Fw, R1)  # R1 and Y are no longer needed: scratch for the Gram matrices
    _root_eigvals_into(R1, out, 18)
    _gram_into(Fv, Y)
    _root_eigvals_into(Y, out, 21)
    return out


@njit(cache=True)
def bilts_windows(twists, positions, m, L, regularized, axis_prior=0.0):
    """BILTS(+) samples for every centre k = m .. N-1-m (0-based): shape (N - 2m, 24).

    Parameters
    ----------
    twists : ndarray, shape (N, 6)
        Spatial twists of the smoothed trajectory.
    positions : ndarray, shape (N, 3)
        Smoothed body-origin positions (clamp centres).
    m : int
        Window spacing in samples.
    axis_prior : float
        κ of :func:`bilts_sample` (0: the reference).
    """
    n = twists.shape[0]
    k_count = n - 2 * m
    out = np.empty((k_count, 24))
    for j in range(k_count):
        k = j + m
        out[j] = bilts_sample(twists[k - m], twists[k], twists[k + m], positions[k], L, regularized,
                              axis_prior)
    return out


@functools.lru_cache(maxsize=64)
def _seeded_perturbation(seed: int, shape: tuple[int, int]) -> np.ndarray:
    noise = np.random.default_rng(seed).normal(0.0, TWIST_NOISE, shape)
    noise.flags.writeable = False
    return noise


def twist_perturbation(seed: int | None, shape: tuple[int, int]) -> np.ndarray:
    """The 1e-12 twist perturbation of docs/algorithms/bilts.md: reproducible for an integer seed (cached),
    fresh for ``None`` (unseeded, as the reference)."""
    if seed is None:
        return np.random.default_rng().normal(0.0, TWIST_NOISE, shape)
    return _seeded_perturbation(int(seed), tuple(shape))


class _BILTSBase(Descriptor):
    progress_types = ("screw", "angle")
    trained_parameter = "ds_scale"
    supports_open_end = True
    param_names = (
        "progress",
        "L",
        "ds_scale",
        "window",
        "n_samples",
        "seed",
        "presmooth",
        "open_end",
        "axis_prior",
        "spacing",
        "align",
    )
    regularized: bool = False
    default_window: int = 20
    feature_names = FEATURE_NAMES

    def __init__(
        self,
        progress: str = "screw",
        L: float = 0.5,
        ds_scale: float = 0.09,
        window: int | None = None,
        n_samples: int = DEFAULT_SAMPLES,
        seed: int | None = 0,
        presmooth: int | None = None,
        open_end: bool = False,
        axis_prior: float = 0.0,
        spacing: int | None = None,
        align: str = "singular",
    ) -> None:
        self.progress = self._check_progress(progress)
        if not L > 0:
            raise ValueError(f"L must be positive, got {L}")
        if not ds_scale > 0:
            raise ValueError(f"ds_scale must be positive, got {ds_scale}")
        if n_samples < 2 * 1 + 1:
            raise ValueError(f"n_samples must be at least 3, got {n_samples}")
        self.L = float(L)
        self.ds_scale = float(ds_scale)
        self.window = self.default_window if window is None else int(window)
        self.n_samples = int(n_samples)
        self.seed = seed
        if presmooth is not None and presmooth < 1:
            raise ValueError(f"presmooth must be a window of at least 1 sample, got {presmooth}")
        self.presmooth = presmooth
        self.open_end = bool(open_end)
        if not (math.isfinite(axis_prior) and axis_prior >= 0.0):
            raise ValueError(f"axis_prior must be a finite number >= 0, got {axis_prior}")
        if axis_prior > 0.0 and not self.regularized:
            raise ValueError("axis_prior needs the body-origin clamp of BILTS+ (descriptor 'bilts+')")
        self.axis_prior = float(axis_prior)
        if spacing is not None and not (int(spacing) == spacing and spacing >= 1):
            raise ValueError(f"spacing must be a whole number of samples >= 1, got {spacing}")
        self.spacing = None if spacing is None else int(spacing)
        if align not in ALIGNMENTS:
            raise ValueError(f"align must be one of {', '.join(ALIGNMENTS)}, got {align!r}")
        self.align = align

    @classmethod
    def parameter_grid(cls, progress: str) -> tuple[float, ...]:
        """Window scales searched by the benchmark: 0.03..0.15 m (screw), 1°..40° (angle)."""
        if progress == "angle":
            return tuple(math.radians(d) for d in (1.0, 10.0, 20.0, 30.0, 40.0))
        return (0.03, 0.06, 0.09, 0.12, 0.15)

    def _max_spacing(self) -> int:
        return min(MAX_WINDOW_SPACING, (self.n_samples - 1) // 2)

    def compute(self, traj: Trajectory) -> np.ndarray:
        """BILTS(+) descriptor of a trajectory, shape (n_samples - 2m, 24).

        Raises
        ------
        DegenerateMotionError
            If the trajectory has no progress (motionless).
        """
        rep = reparameterize(traj, self.progress, self.L, self.n_samples, presmooth=self.presmooth)
        return self.from_reparameterized(rep.poses, rep.ds)

    def from_reparameterized(
        self, poses: np.ndarray, ds: float, arclength: float | None = None
    ) -> np.ndarray:
        """Descriptor from poses (N, 4, 4) already at equidistant progress with step ``ds``
        (``arclength`` is not used)."""
        m = (window_spacing(self.ds_scale, ds, self._max_spacing()) if self.spacing is None
             else min(self.spacing, self._max_spacing()))
        smoothed = smooth_poses(poses, self.window)
        twists = se3.central_spatial_twists(smoothed, ds)
        twists = twists + twist_perturbation(self.seed, twists.shape)
        positions = np.ascontiguousarray(smoothed[:, :3, 3])
        out = bilts_windows(np.ascontiguousarray(twists), positions, m, self.L, self.regularized,
                            self.axis_prior)
        return np.hstack([out, gram_columns(out)]) if self.align == "gram" else out

    @property
    def n_features(self) -> int:
        """Columns of a sample: 24, or 45 with ``align="gram"``."""
        return N_FEATURES + (len(GRAM_NAMES) if self.align == "gram" else 0)

    @property
    def _aligned(self) -> tuple[int, int]:
        return (N_FEATURES, self.n_features) if self.align == "gram" else (18, N_FEATURES)

    _pointwise: int = POINTWISE_SQUARED

    def alignment_columns(self, n_features: int) -> slice:
        """DTW aligns on the six singular values (columns 18–23), or with ``align="gram"`` on the
        21 dot products (columns 24–44)."""
        return slice(*self._aligned) if n_features == self.n_features else slice(0, n_features)

    def distance_spec(self) -> DistanceSpec:
        """DTW on the alignment columns, then the pointwise term along the path."""
        return DistanceSpec(*self._aligned, self._pointwise, bool(self.open_end))

    def _check_columns(self, *arrays: np.ndarray) -> None:
        if any(a.ndim != 2 or a.shape[1] != self.n_features for a in arrays):
            raise ValueError(f"{self.display_name} sequences (align={self.align!r}) are "
                             f"(K, {self.n_features}) arrays")

    def distance(self, model: np.ndarray, query: np.ndarray) -> float:
        """Distance between one model and one query sequence (both (K, 24), or (K, 45) with
        ``align="gram"``)."""
        X = np.ascontiguousarray(model, dtype=np.float64)
        Y = np.ascontiguousarray(query, dtype=np.float64)
        self._check_columns(X, Y)
        return float(path_distance_kernel(X, Y, *self._aligned, self._pointwise, self.open_end))

    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """DTW on the alignment columns, pointwise sum of the twist part along the path
        (docs/algorithms/dtw.md).

        Returns
        -------
        ndarray, shape (n_queries, n_models)
        """
        qd, qo = pack_sequences(list(queries))
        md, mo = pack_sequences(list(models))
        self._check_columns(qd, md)
        return path_distance_matrix_kernel(qd, qo, md, mo, *self._aligned, self._pointwise,
                                           self.open_end)


@register
class BILTS(_BILTSBase):
    """BILTS (``BILTS_discrete``): Gaussian window 20, ISA-based frame origin, squared-Euclidean
    distance along the DTW path (docs/algorithms/bilts.md, docs/algorithms/dtw.md).

    Parameters
    ----------
    progress : {"screw", "angle"}
    L : float
        Scale length [m] (screw progress, rotational weight).
    ds_scale : float
        Window scale: metres (screw progress) or radians (angle progress).
    window : int, optional
        Gaussian smoothing window in samples (default 20).
    n_samples : int
        Progress samples (50 in the reference).
    seed : int or None
        Seed of the 1e-12 twist perturbation (None: unseeded, as the reference).
    presmooth : int, optional
        framefree extension, off by default (reference behaviour): smooth the 50 Hz poses with a
        Gaussian window of this many samples before computing progress, which makes the
        reparameterization robust to sensor noise. See :func:`framefree.core.progress.reparameterize`.
    open_end : bool
        framefree extension: open-end alignment, an unfinished query may match the beginning of a
        model (docs/algorithms/dtw.md).
    axis_prior : float
        framefree extension, BILTS+ only, 0 (reference behaviour) by default: weight κ of the prior
        that places the moving-frame origin, along the screw axis, near the body origin when the
        motion does not determine it (a rotation about a nearly fixed axis, such as an elbow
        flexion). See docs/algorithms/bilts.md#axis-prior.
    spacing : int, optional
        framefree extension: a fixed window spacing ``m`` [samples] instead of
        ``round(ds_scale / Δs)`` (the reference, ``None``). With it, the windows cover the same
        fraction of every trajectory, however large it is (docs/algorithms/bilts.md#fixed-spacing).
    """

    name = "bilts"
    display_name = "BILTS"
    regularized = False
    default_window = 20
    _pointwise = POINTWISE_SQUARED


@register
class BILTSPlus(_BILTSBase):
    """BILTS+ (``BILTS_discrete_reg``): Gaussian window 10, frame origin clamped within L of the
    body origin, per-pair Kabsch-aligned distance along the DTW path (docs/algorithms/bilts.md,
    docs/algorithms/dtw.md).

    Parameters are those of :class:`BILTS` (default window 10).
    """

    name = "bilts+"
    display_name = "BILTS+"
    regularized = True
    default_window = 10
    _pointwise = POINTWISE_KABSCH
