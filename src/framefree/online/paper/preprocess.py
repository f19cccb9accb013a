"""Streaming preprocessing: online screw-path reparameterization and online BILTS+.

See docs/online-paper.md, *Streaming preprocessing*.

One routine serves model building and live recognition: :class:`StreamingBILTSPlus` receives raw
pose samples one at a time, keeps the geometric samples of Algorithm 1
(docs/algorithms/progress.md, reusing :class:`framefree.core.progress.StreamingReparameterizer`), and
emits one BILTS+ descriptor sample (18 numbers: ``Lω'₋, v'₋, Lω'₀, v'₀, Lω'₊, v'₊``) as soon as
its window is complete:

* geometric sample ``j`` is Gaussian-smoothed (window 10, offsets -5..+4, σ = 2) once the 4 samples
  after it exist; at the start of a sequence the window is truncated and renormalized, exactly as
  offline (docs/algorithms/smoothing.md, *Gaussian moving average*);
* the central spatial twist ``i`` needs smoothed poses ``i-1`` and ``i+1`` (the first one is the
  reference's one-sided quirk, docs/algorithms/se3.md, *Twists*), divided by ``2 Δs_res``;
* descriptor sample ``k`` needs twists ``k-m, k, k+m``; it is computed by
  :func:`framefree.descriptors.bilts.bilts_sample` (eQR with the L-clamp around the smoothed position).

A descriptor sample therefore lags ``m + 5`` geometric samples behind the newest one, and a sequence
of ``n`` geometric samples yields ``n - 5 - 2m`` descriptor samples (the end is never truncated,
because a live stream has no end). :func:`descriptor_from_samples` is the offline path of the same
routine (all samples at once, same kernels); :func:`replay` pushes a recording through the
streaming path, which is how gesture models are built.
"""

from __future__ import annotations

from collections import deque

import numpy as np
from numba import njit

from ...core import se3, se3_kernels
from ...core.progress import StreamingReparameterizer
from ...core.smoothing import gaussian_offsets, gaussian_weights
from ...core.trajectory import Trajectory
from ...descriptors.bilts import bilts_sample, window_spacing

__all__ = [
    "N_DESCRIPTOR",
    "CausalPoseFilter",
    "StreamingBILTSPlus",
    "densify_poses",
    "descriptor_from_samples",
    "geometric_samples",
    "replay",
]

#: Columns of an online descriptor sample (the 18 twist entries of BILTS+; no singular values).
N_DESCRIPTOR = 18
#: Rows of the deterministic unit-normal table for the twist perturbation.
_NOISE_ROWS = 101
_NOISE_TABLE = np.random.default_rng(20250314).standard_normal((_NOISE_ROWS, 6))


@njit(cache=True)
def pose_from_pq(p, q):
    """4×4 pose from a position (3,) [m] and a quaternion (4,) ``(w, x, y, z)`` (normalized)."""
    T = np.eye(4)
    T[:3, :3] = se3_kernels.matrix_from_quaternion_one(q)
    T[0, 3] = p[0]
    T[1, 3] = p[1]
    T[2, 3] = p[2]
    return T


@njit(cache=True)
def smooth_window(y, g):
    """Gaussian-weighted mean of the rows of ``y`` (n, 7) with weights ``g`` (n,) → pose (4, 4).

    Columns of ``y``: position (3) and sign-continuous quaternion (4); the mean quaternion is
    renormalized. Summation in row order (the same in the streaming and the offline path).
    """
    acc = np.zeros(7)
    wsum = 0.0
    for r in range(y.shape[0]):
        wsum += g[r]
        for c in range(7):
            acc[c] += g[r] * y[r, c]
    for c in range(7):
        acc[c] /= wsum
    return pose_from_pq(acc[:3], acc[3:])


@njit(cache=True)
def central_twist(T_hi, T_lo, ds, noise):
    """Spatial twist ``vee(log(T_hi T_lo⁻¹)) / (2 ds) + noise`` (6,), rotation first."""
    xi = se3_kernels.twist_from_pose_one(se3_kernels.compose_one(T_hi, se3_kernels.inverse_one(T_lo)))
    out = np.empty(6)
    for c in range(6):
        out[c] = xi[c] / (2.0 * ds) + noise[c]
    return out


@njit(cache=True)
def _offline_kernel(y, g, before, after, ds, m, L, noise):
    n = y.shape[0]
    n_sm = max(n - after, 0)
    sm = np.empty((n_sm, 4, 4))
    for j in range(n_sm):
        lo = max(0, j - before)
        sm[j] = smooth_window(y[lo : j + after + 1], g[lo - (j - before) :])
    n_tw = max(n_sm - 1, 0)
    tw = np.empty((n_tw, 6))
    for i in range(n_tw):
        tw[i] = central_twist(sm[i + 1], sm[max(i - 1, 0)], ds, noise[i % noise.shape[0]])
    n_d = max(n_tw - 2 * m, 0)
    out = np.empty((n_d, 18))
    for j in range(n_d):
        k = j + m
        s = bilts_sample(tw[k - m], tw[k], tw[k + m], sm[k, :3, 3].copy(), L, True, 0.0)
        out[j] = s[:18]
    return out


class CausalPoseFilter:
    """Causal moving average of the last ``n`` raw poses (position mean, normalized quaternion mean).

    Parameters
    ----------
    n : int
        Window length in pose samples (1: pass through). The output lags the input by
        ``(n - 1) / 2`` sample periods (40 ms for n = 5 at 50 Hz).
    """

    def __init__(self, n: int = 1) -> None:
        self.n = int(n)
        self.reset()

    def reset(self) -> None:
        """Forget the past samples (a new sequence starts)."""
        self._buf: deque[np.ndarray] = deque(maxlen=self.n)

    def push(self, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Add a sample (position (3,) [m], unit quaternion (4,)); return the filtered (p, q)."""
        if self.n <= 1:
            return p, q
        if self._buf:
            q = se3.align_quaternion_sign(q, self._buf[-1][3:])
        self._buf.append(np.concatenate([p, q]))
        m = np.mean(np.array(self._buf), axis=0)
        return m[:3], m[3:] / np.linalg.norm(m[3:])


def densify_poses(poses: np.ndarray, interpolate: int) -> np.ndarray:
    """``interpolate - 1`` poses put by ScLERP between every two consecutive poses.

    Parameters
    ----------
    poses : ndarray, shape (N, 4, 4)
        Poses [m] in time order.
    interpolate : int
        Poses per original step (1: the poses unchanged).

    Returns
    -------
    ndarray, shape ((N - 1) * interpolate + 1, 4, 4)
        The first pose, then for every step the poses at fractions ``1/k, 2/k, ..., 1`` of it
        (the last one the original pose), as :meth:`StreamingBILTSPlus.push_all` offers them to
        Algorithm 1.
    """
    k = int(interpolate)
    if k <= 1 or len(poses) < 2:
        return poses
    out = np.empty(((len(poses) - 1) * k + 1, 4, 4))
    out[0] = poses[0]
    for i in range(1, len(poses)):
        for j in range(1, k):
            out[(i - 1) * k + j] = se3_kernels.sclerp_one(poses[i - 1], poses[i], j / k)
        out[i * k] = poses[i]
    return out


def filtered_poses(traj: Trajectory, presmooth: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Positions (N, 3) and quaternions (N, 4) of a recording after :class:`CausalPoseFilter`."""
    if presmooth <= 1:
        return traj.p, traj.q
    f = CausalPoseFilter(presmooth)
    out = [f.push(traj.p[k], traj.q[k]) for k in range(len(traj))]
    return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def geometric_samples(traj: Trajectory, resolution: float, L: float, presmooth: int = 1) -> np.ndarray:
    """Algorithm 1 on a whole recording: the kept samples as rows ``x, y, z, qw, qx, qy, qz`` (n, 7).

    Quaternions are made sign-continuous along the kept samples. ``presmooth`` applies
    :class:`CausalPoseFilter` first (as the streaming path does).
    """
    rep = StreamingReparameterizer(resolution, L)
    P, Q = filtered_poses(traj, presmooth)
    idx = rep.run(traj.poses() if presmooth <= 1 else se3.poses_from_pq(P, Q))
    y = np.column_stack([P[idx], Q[idx]])
    y[:, 3:] = se3.quaternion_continuity(y[:, 3:], se3.NEAREST_SIGN)
    return y


def descriptor_from_samples(
    samples: np.ndarray,
    resolution: float,
    L: float,
    ds_scale: float,
    window: int = 10,
    twist_noise: float = 1e-12,
) -> np.ndarray:
    """Offline path of the streaming routine: descriptor of a whole geometric sequence.

    Parameters
    ----------
    samples : ndarray, shape (n, 7)
        Geometric samples ``x, y, z [m], qw, qx, qy, qz`` (sign-continuous), as kept by Algorithm 1.
    resolution : float
        Δs_res [m], the nominal progress step.
    L, ds_scale : float
        BILTS+ scale length and window scale [m].
    window : int
        Gaussian window (samples).
    twist_noise : float
        Standard deviation of the deterministic twist perturbation.

    Returns
    -------
    ndarray, shape (max(n - 5 - 2m, 0), 18)
        Identical (bit for bit) to what :class:`StreamingBILTSPlus` emits for the same samples.
    """
    before, after = gaussian_offsets(window)
    m = window_spacing(ds_scale, resolution)
    y = np.ascontiguousarray(samples, dtype=np.float64)
    return _offline_kernel(
        y, gaussian_weights(window), before, after, float(resolution), m, float(L),
        _NOISE_TABLE * twist_noise,
    )


class StreamingBILTSPlus:
    """Online reparameterizer + online BILTS+ calculator; one per stream (docs/online-paper.md).

    Parameters
    ----------
    resolution : float
        Screw-path resolution Δs_res [m] (also the nominal progress step).
    L : float
        Scale length [m].
    ds_scale : float
        BILTS+ window scale [m]; the window spacing is ``m = window_spacing(ds_scale, resolution)``.
    window : int
        Gaussian smoothing window in geometric samples (10).
    twist_noise : float
        Standard deviation of the deterministic twist perturbation (1e-12).
    presmooth : int
        Causal moving average over this many raw poses before Algorithm 1 (1: off).
    interpolate : int
        Poses offered to Algorithm 1 per raw step: ``interpolate - 1`` poses put by ScLERP between
        the previous (filtered) pose and the new one, then the new one (1: off; for recordings
        too sparse for Algorithm 1, see :func:`~framefree.online.paper.models.auto_interpolation`).

    Attributes
    ----------
    m : int
        Window spacing in geometric samples.
    delay : int
        Geometric samples between the newest one and the centre of the newest descriptor sample.
    n_geometric : int
        Geometric samples kept since the last reset.
    n_descriptors : int
        Descriptor samples emitted since the last reset.

    Notes
    -----
    Memory is bounded: only the last ``window`` raw geometric samples, ``m + 2`` smoothed poses and
    ``2m + 1`` twists are kept.
    """

    def __init__(
        self,
        resolution: float,
        L: float,
        ds_scale: float,
        window: int = 10,
        twist_noise: float = 1e-12,
        presmooth: int = 1,
        interpolate: int = 1,
    ) -> None:
        if int(interpolate) < 1:
            raise ValueError(f"interpolate must be at least 1, got {interpolate}")
        self.interpolate = int(interpolate)
        self.resolution = float(resolution)
        self._filter = CausalPoseFilter(presmooth)
        self.L = float(L)
        self.ds_scale = float(ds_scale)
        self.window = int(window)
        self.m = window_spacing(ds_scale, resolution)
        self._before, self._after = gaussian_offsets(window)
        self._g = gaussian_weights(window)
        self._noise = _NOISE_TABLE * float(twist_noise)
        self.delay = self.m + self._after + 1
        self._rep = StreamingReparameterizer(resolution, L)
        self.reset()

    def reset(self) -> None:
        """Start a new geometric sequence (after a gap or a jump)."""
        self._rep.reset()
        self._filter.reset()
        self._raw: deque[np.ndarray] = deque(maxlen=self._before + self._after + 1)
        self._smoothed: deque[np.ndarray] = deque(maxlen=self.m + 2)
        self._twists: deque[np.ndarray] = deque(maxlen=2 * self.m + 1)
        self._q_last: np.ndarray | None = None
        self._T_prev: np.ndarray | None = None
        self.n_geometric = 0
        self.n_smoothed = 0
        self.n_twists = 0
        self.n_descriptors = 0

    def push(self, p: np.ndarray, q: np.ndarray) -> np.ndarray | None:
        """Offer one pose sample; return the new descriptor sample (18,) or None.

        Parameters
        ----------
        p : ndarray, shape (3,)
            Position [m].
        q : ndarray, shape (4,)
            Unit quaternion ``(w, x, y, z)``.
        """
        if self.interpolate > 1:
            raise RuntimeError("push() offers one pose; with interpolate > 1 use push_all()")
        p = np.asarray(p, dtype=np.float64)
        q = np.asarray(q, dtype=np.float64)
        p, q = self._filter.push(p, q)
        if not self._rep.push(pose_from_pq(p, q)):
            return None
        return self._accept(p, q)

    def push_all(self, p: np.ndarray, q: np.ndarray) -> list[np.ndarray]:
        """Offer one pose sample with the poses interpolated before it; return every new
        descriptor sample (18,) (none, one, or with ``interpolate > 1`` possibly several).

        Parameters
        ----------
        p : ndarray, shape (3,)
            Position [m].
        q : ndarray, shape (4,)
            Unit quaternion ``(w, x, y, z)``.
        """
        p = np.asarray(p, dtype=np.float64)
        q = np.asarray(q, dtype=np.float64)
        p, q = self._filter.push(p, q)
        T = pose_from_pq(p, q)
        out: list[np.ndarray] = []
        k, prev = self.interpolate, self._T_prev
        if k > 1 and prev is not None:
            for j in range(1, k):
                Tj = se3_kernels.sclerp_one(prev, T, j / k)
                if self._rep.push(Tj):
                    qj = se3_kernels.quaternion_from_matrix_one(np.ascontiguousarray(Tj[:3, :3]))
                    d = self._accept(Tj[:3, 3].copy(), qj)
                    if d is not None:
                        out.append(d)
        self._T_prev = T if k > 1 else None
        if self._rep.push(T):
            d = self._accept(p, q)
            if d is not None:
                out.append(d)
        return out

    def _accept(self, p: np.ndarray, q: np.ndarray) -> np.ndarray | None:
        if self._q_last is not None:
            q = se3.align_quaternion_sign(q, self._q_last)
        self._q_last = q
        self._raw.append(np.concatenate([p, q]))
        self.n_geometric += 1
        j = self.n_geometric - 1 - self._after  # smoothed sample that just became final
        if j < 0:
            return None
        lo = max(0, j - self._before)
        y = np.array(self._raw)[len(self._raw) - (j + self._after + 1 - lo) :]
        self._smoothed.append(smooth_window(y, self._g[lo - (j - self._before) :]))
        self.n_smoothed += 1
        i = j - 1  # twist that just became final
        if i < 0:
            return None
        sm = self._smoothed
        T_lo = sm[-3] if i >= 1 else sm[-2]
        self._twists.append(central_twist(sm[-1], T_lo, self.resolution, self._noise[i % _NOISE_ROWS]))
        self.n_twists += 1
        k = i - self.m  # descriptor centre that just became computable
        if k < self.m:
            return None
        tw = self._twists
        p_k = np.ascontiguousarray(sm[-(i + 1 - k) - 1][:3, 3])
        d = bilts_sample(tw[0], tw[self.m], tw[2 * self.m], p_k, self.L, True, 0.0)[:N_DESCRIPTOR]
        self.n_descriptors += 1
        return d


def replay(
    traj: Trajectory,
    resolution: float,
    L: float,
    ds_scale: float,
    window: int = 10,
    twist_noise: float = 1e-12,
    presmooth: int = 1,
    interpolate: int = 1,
) -> tuple[np.ndarray, np.ndarray]:
    """Push a recording through :class:`StreamingBILTSPlus` as if it were live (``interpolate``:
    see there).

    Returns
    -------
    descriptors : ndarray, shape (K, 18)
    times : ndarray, shape (K,)
        Time stamp [s] of the pose sample at which each descriptor sample was emitted.
    """
    calc = StreamingBILTSPlus(resolution, L, ds_scale, window, twist_noise, presmooth, interpolate)
    out: list[np.ndarray] = []
    times: list[float] = []
    for k in range(len(traj)):
        for d in calc.push_all(traj.p[k], traj.q[k]):
            out.append(d)
            times.append(float(traj.t[k]))
    desc = np.array(out).reshape(-1, N_DESCRIPTOR)
    return desc, np.array(times)
