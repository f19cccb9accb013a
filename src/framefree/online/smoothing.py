"""Smoothing a noisy sensor's poses: a centred Gaussian on the uniform grid, for the takes and
the stream alike (``RecognizerConfig.smoothing``; by default decided from the takes' noise).

A skeleton tracker's wrist joint jitters by a centimetre or more. That noise raises the learned
rest level (the motion speed over 0.1 s of a hand at rest is then mostly noise) and roughens the
descriptor; on the Machete right controller at 30 Hz with 1 cm of noise per axis F1 falls from
68 to 53 %, and a centred Gaussian of 67 ms on takes and sessions gives it back
(docs/online-history.md, *Session 28*).

Each pose ``T_c`` of the grid becomes ``T_c · exp(Σ_i w_i log(T_c⁻¹ T_i))`` over its neighbours
``T_i`` within three standard deviations, with Gaussian weights ``w_i`` renormalized where the
window is cut by the start or end of the poses. The average is taken in the pose's own frame, so
smoothing commutes with any change of world frame and of body frame: it keeps framefree's
invariances exactly. For positions only (a constant orientation) it is the weighted mean of the
positions. Live, a pose can be smoothed only once the poses after it have arrived: the stream
reaches the recognizer three standard deviations late.

Not :mod:`framefree.core.smoothing`, the reference descriptors' pre-smoothing of positions and
quaternion components by a window of samples, which is not exact for a change of body frame.

By default (``smoothing=None``) the recognizer decides from its takes (:func:`sensor_smoothing`):
it measures the white noise on their positions (:func:`position_noise`) and smooths only when
that noise alone would make a still hand appear to move. v32 counted the orientations' noise too
(:func:`rotation_noise` times the scale length ``L``); since v34 drops an orientation noisy enough
to matter, v36 counts the positions only: a hand tracker's palm turns more noisily in motion
than at rest, and on examples cut without rests (SFINGE3D's dictionary cut at 5 % of its peak
speed) the turns alone put the reading over the limit, and the smoothing cost 4 swipes and 8
false positives (docs/online-history.md, *v36*).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory

__all__ = ["GridSmoother", "grid_gaussian", "noise_limit", "position_noise",
           "rotation_noise", "sensor_smoothing", "smooth_in_own_frame", "smoothed_take"]

#: Order of the differences that :func:`position_noise` measures noise on. White noise of σ
#: gives third differences of σ √20; a hand's smooth motion gives little at tracking rates
#: (the Machete controllers at 90 Hz read 0.1 mm, resampled to 30 Hz 0.3 mm; SFINGE3D's palm at
#: 20 Hz 0.3 mm; the same controllers with 1 cm of noise added 10.6 mm).
NOISE_ORDER = 3

#: Quantile of the third differences' norms that :func:`position_noise` reads: the stillest
#: tenth, as the speed's noise floor is its 10th percentile. A fast stroke sampled at 20 Hz adds
#: its jerk to the differences and only raises their norms, so a low quantile reads the noise
#: where the motion adds least (session 30: SFINGE3D's swipes cut at 5 % of their peak read 1.4
#: mm at the median, over the 1.3 mm limit, and 1.1 mm here; injected noise reads the same).
NOISE_QUANTILE = 0.1

#: That quantile of a χ distribution of three degrees of freedom (the norm of a standard normal
#: vector of three dimensions): √0.58437, the 10th percentile of χ² with three.
CHI3_QUANTILE = 0.76444


def position_noise(traj: Trajectory) -> float:
    """Standard deviation [m] of white noise on ``traj``'s positions, per axis and sample.

    A robust estimate from the third differences of the positions as recorded (no resampling):
    white noise of σ per axis makes each third difference a Gaussian vector of σ √20 per axis,
    whose norm has the 10th percentile 0.764 σ √20 (a χ of three degrees of freedom). The motion
    itself contributes little: a third difference of a smooth motion is its jerk times the
    sample period cubed, and the stillest tenth of the differences (:data:`NOISE_QUANTILE`) is
    where it adds least. The norm makes the estimate independent of the world frame. ``nan`` for
    a take of fewer than eight samples.
    """
    if traj.p.shape[0] < 2 * NOISE_ORDER + 2:
        return float("nan")
    d = np.linalg.norm(np.diff(traj.p, n=NOISE_ORDER, axis=0), axis=1)
    scale = CHI3_QUANTILE * math.sqrt(math.comb(2 * NOISE_ORDER, NOISE_ORDER))
    return float(np.quantile(d, NOISE_QUANTILE)) / scale


def rotation_noise(traj: Trajectory) -> float:
    """Standard deviation [rad] of white noise on ``traj``'s orientations, per axis and sample.

    :func:`position_noise` for the orientation: the second differences of the turns from one
    sample to the next, ``log(R_kᵀ R_{k+1})`` in the tracker's frame, are third differences of
    the noise, read at their stillest tenth. The turns are taken in the tracker's own frame and
    only their norms are read, so the estimate depends neither on the world frame nor on how
    the tracker sits in the hand. 0 for a sensor of positions only (a constant orientation);
    ``nan`` for a take of fewer than eight samples.
    """
    if traj.q.shape[0] < 2 * NOISE_ORDER + 2:
        return float("nan")
    R = se3.matrix_from_quaternion(traj.q)
    turns = se3.vector_from_rotation(np.einsum("nji,njk->nik", R[:-1], R[1:]))
    d = np.linalg.norm(np.diff(turns, n=NOISE_ORDER - 1, axis=0), axis=1)
    scale = CHI3_QUANTILE * math.sqrt(math.comb(2 * NOISE_ORDER, NOISE_ORDER))
    return float(np.quantile(d, NOISE_QUANTILE)) / scale


def noise_limit(still_speed: float, lag: float) -> float:
    """Position noise [m per axis] at which a still hand appears to move at ``still_speed``
    [m/s] when its speed is taken over ``lag`` [s]: the displacement between two noisy
    positions has a per-axis deviation of σ √2, and the norm of three such axes a mean of
    √(8/π) times that."""
    return still_speed * lag / (math.sqrt(2.0) * math.sqrt(8.0 / math.pi))


def sensor_smoothing(trajectories: Sequence[Trajectory], still_speed: float, lag: float,
                     smoothing: float) -> tuple[float, float]:
    """The smoothing [s] a recognizer built on ``trajectories`` applies, and the noise [m]
    that decided it.

    ``smoothing`` when the takes' median :func:`position_noise` exceeds :func:`noise_limit`
    (``still_speed``, ``lag``): the noise alone would make a still hand appear to move; else 0.
    The orientations' noise takes no part (v36): one noisy enough to matter is dropped
    (:mod:`~framefree.online.noisy_orientation`).
    """
    noise = [position_noise(tr) for tr in trajectories]
    noise = [x for x in noise if math.isfinite(x)]
    if not noise:
        return 0.0, float("nan")
    level = float(np.median(noise))
    return (smoothing if level > noise_limit(still_speed, lag) else 0.0), level


def grid_gaussian(std: float, dt: float) -> np.ndarray:
    """Weights (2h+1,) of a centred Gaussian of standard deviation ``std`` [s] on a grid of step
    ``dt`` [s], ``h = ceil(3 std / dt)``, summing to 1; ``[1.0]`` for ``std`` 0."""
    if not std >= 0:
        raise ValueError(f"smoothing must not be negative, got {std}")
    h = math.ceil(3.0 * std / dt - 1e-9)
    if h == 0:
        return np.ones(1)
    w = np.exp(-0.5 * (np.arange(-h, h + 1) * dt / std) ** 2)
    return w / w.sum()


def _smoothed_one(poses: np.ndarray, centre: int, weights: np.ndarray) -> np.ndarray:
    """Pose ``centre`` of ``poses`` (n, 4, 4) averaged with its neighbours in its own frame."""
    h = (weights.size - 1) // 2
    lo, hi = max(0, centre - h), min(poses.shape[0], centre + h + 1)
    w = weights[lo - centre + h:hi - centre + h]
    T_c = poses[centre]
    relative = se3.transform_inverse(T_c) @ poses[lo:hi]
    mean_twist = (w[:, None] * se3.twist_from_pose(relative)).sum(axis=0) / w.sum()
    return T_c @ se3.pose_from_twist(mean_twist)


def smooth_in_own_frame(poses: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Every pose of ``poses`` (n, 4, 4) smoothed with ``weights`` (:func:`grid_gaussian`),
    the windows cut at both ends. Returns a new array (n, 4, 4)."""
    poses = np.asarray(poses, dtype=np.float64)
    if weights.size == 1:
        return poses.copy()
    return np.stack([_smoothed_one(poses, c, weights) for c in range(poses.shape[0])])


def smoothed_take(traj: Trajectory, std: float, dt: float) -> Trajectory:
    """A take on the uniform grid of step ``dt`` [s] (:meth:`Trajectory.uniform_poses`),
    smoothed by a centred Gaussian of ``std`` [s]: what the live recognizer sees of the same
    motion, apart from the delay. ``std`` 0 returns ``traj`` itself."""
    if std == 0:
        return traj
    times, poses = traj.uniform_poses(dt)
    return Trajectory.from_poses(traj.t[0] + times,
                                 smooth_in_own_frame(poses, grid_gaussian(std, dt)), source=traj.source)


class GridSmoother:
    """The live side of :func:`smooth_in_own_frame`: grid poses in, the same poses smoothed out, each
    as soon as the poses of its window after it have arrived (``delay`` [s] late).

    Parameters
    ----------
    std : float
        Standard deviation [s] of the Gaussian (> 0).
    dt : float
        Grid step [s].
    """

    def __init__(self, std: float, dt: float) -> None:
        self.weights = grid_gaussian(std, dt)
        self.half = (self.weights.size - 1) // 2
        self.delay = self.half * dt
        self._times: deque[float] = deque(maxlen=2 * self.half + 1)
        self._poses: deque[np.ndarray] = deque(maxlen=2 * self.half + 1)
        self._seen = 0  # poses pushed since the last reset

    def reset(self) -> None:
        """Forget the poses held (a new stream, or a restart after a long dropout)."""
        self._times.clear()
        self._poses.clear()
        self._seen = 0

    def push(self, times: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Grid times (k,) [s] and poses (k, 4, 4) in; the smoothed poses now complete out
        (their times (m,) and poses (m, 4, 4), m <= k once the first ``half`` are held)."""
        out_t, out_p = [], []
        for t, T in zip(times, poses, strict=True):
            self._times.append(float(t))
            self._poses.append(np.array(T, dtype=np.float64))
            self._seen += 1
            centre = self._seen - 1 - self.half  # index of the pose now complete
            if centre < 0:
                continue
            window = np.stack(self._poses)
            c = min(centre, self.half)  # its place in the window (cut at the stream's start)
            out_t.append(self._times[c])
            out_p.append(_smoothed_one(window, c, self.weights))
        if not out_t:
            return np.zeros(0), np.zeros((0, 4, 4))
        return np.array(out_t), np.stack(out_p)
