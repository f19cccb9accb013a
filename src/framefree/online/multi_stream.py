"""The stream side of live recognition with several trackers moving together.

A two-handed gesture is one motion of both hands, so the trackers are cut into movement units
together: the **combined motion speed** is the sum of every tracker's own motion speed (the
screw-path rate of :mod:`~framefree.online.segmentation`, frame-free for each tracker), and a
unit starts and ends where that sum crosses the move and rest levels. A hand that rests while the
other moves keeps the unit going; both must rest for it to end.

* :class:`MultiPoseBuffer`: the ring buffer of the latest uniform poses of every tracker;
* :class:`MultiMotionSegmenter`: the single-tracker segmenter on the combined speed;
* :class:`GridJoiner`: each tracker's samples pass its own acceptance gate and uniform grid; the
  joiner hands on a grid time only once every tracker has a pose there;
* :class:`StopGroup`: one stop detector per tracker; a stop signal of either hand is a stop.

The levels and candidate limits come from the model recordings (:func:`combined_speed`,
:func:`multi_speed_levels`, :func:`multi_candidate_limits`). See ``docs/online.md``.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.progress import screw_path_increment
from ..core.trajectory import Trajectory
from .limits import limits_of_units
from .rest_levels import rest_level
from .segmentation import (
    MotionSegmenter,
    PoseBuffer,
    SpeedLevels,
    Unit,
    motion_speed,
)
from .stop import StopDetector

__all__ = [
    "GridJoiner",
    "MultiMotionSegmenter",
    "MultiPoseBuffer",
    "StopGroup",
    "combined_speed",
    "grid_poses",
    "live_cut",
    "multi_candidate_limits",
    "multi_speed_levels",
    "recording_units",
]


class MultiPoseBuffer(PoseBuffer):
    """:class:`~framefree.online.segmentation.PoseBuffer` of several trackers: a pose is an
    array (n_trackers, 4, 4), a slice's poses are (n, n_trackers, 4, 4).

    Parameters
    ----------
    capacity : int
        Grid times kept.
    n_trackers : int
    """

    def __init__(self, capacity: int, n_trackers: int) -> None:
        super().__init__(capacity)
        self.n_trackers = int(n_trackers)
        self._poses = np.zeros((self.capacity, self.n_trackers, 4, 4))

    def _empty(self, capacity: int) -> MultiPoseBuffer:
        return MultiPoseBuffer(capacity, self.n_trackers)


class MultiMotionSegmenter(MotionSegmenter):
    """Movement units of several trackers on the sum of their motion speeds [m/s].

    Same parameters as :class:`~framefree.online.segmentation.MotionSegmenter` but ``settle``
    (several trackers never settle: not measured on them), and ``n_trackers``. Units carry no
    headings (corners and turns are single-tracker rules).
    """

    def __init__(self, levels: SpeedLevels, L: float, dt: float = 0.02, lag: int = 5,
                 valley_ratio: float = 0.5, capacity: int = 1500, n_trackers: int = 2) -> None:
        super().__init__(levels, L, dt, lag, valley_ratio, capacity)
        self.buffer = MultiPoseBuffer(capacity, n_trackers)
        self.reset()

    def _speed(self, k: int) -> float:
        A, B = self.buffer.pose(k - self.lag), self.buffer.pose(k)
        total = sum(screw_path_increment(np.ascontiguousarray(A[j]), np.ascontiguousarray(B[j]),
                                         self.L) for j in range(A.shape[0]))
        return total / (self.lag * self.dt)

    def _close(self, end: int, rest_after: bool, settled: bool = False) -> Unit:
        buf = self.buffer
        unit = Unit(self._start, end, buf.time(self._start), buf.time(end), self._peak, rest_after,
                    settled=settled)
        self.units.append(unit)
        return unit


def grid_poses(sample: MultiTrajectory, dt: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    """Every tracker on one uniform grid: times (n,) [s] and poses (n, n_trackers, 4, 4)."""
    grids = [tr.uniform_poses(dt) for tr in sample.trackers]
    n = min(g[0].size for g in grids)
    return grids[0][0][:n], np.stack([g[1][:n] for g in grids], axis=1)


def combined_motion(sample: MultiTrajectory, L: float, dt: float = 0.02, lag: int = 5
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The combined motion speed (n - lag,) [m/s] of a recording on the uniform grid, the sum of
    its trackers' :func:`~framefree.online.segmentation.motion_speed`, and their positions
    (n, n_trackers, 3) [m] on that grid."""
    _, poses = grid_poses(sample, dt)
    v = sum(motion_speed(poses[:, j], dt, L, lag)[lag:] for j in range(poses.shape[1]))
    return v, poses[:, :, :3, 3]


def combined_speed(sample: MultiTrajectory, L: float, dt: float = 0.02, lag: int = 5) -> np.ndarray:
    """The combined motion speed (n - lag,) [m/s] of a recording (:func:`combined_motion`)."""
    return combined_motion(sample, L, dt, lag)[0]


def multi_speed_levels(samples: Sequence[MultiTrajectory], L: float, dt: float = 0.02,
                       lag: int = 5, noise_factor: float = 3.0, peak_fraction: float = 0.05,
                       move_factor: float = 1.5, rest_before: float = 0.2) -> SpeedLevels:
    """Rest and move levels [m/s] of the combined speed from model recordings.

    As :func:`~framefree.online.rest_levels.speed_levels`, with the **median** noise floor (10th
    percentile of a recording's speed) instead of the largest: whole-body recordings such as the
    Machete Vive set often start or end in motion, and the largest floor of the six people's 330
    recordings (0.95 m/s) lies above many of their strokes' valleys; the median (0.15 m/s)
    is a rest. The median floor counts at most ``peak_fraction`` × the median peak, and where most
    recordings hold no rest the level is at most the speed at which they start or end or, where
    that is faster, the slowest the hand moves for ``rest_before`` seconds inside them, as there
    (:func:`~framefree.online.rest_levels.rest_level`; the trackers' positions tell whether an
    end heads one way).
    """
    motions = [m for m in (combined_motion(s, L, dt, lag) for s in samples) if m[0].size]
    if not motions:
        raise ValueError("no model recording is long enough to measure its motion speed")
    rest = rest_level(motions, lag, noise_factor, peak_fraction, max(1, round(rest_before / dt)))
    return SpeedLevels(rest=rest, move=move_factor * rest)


def _padded(sample: MultiTrajectory, dt: float, pad: float = 0.5
            ) -> tuple[np.ndarray, np.ndarray]:
    """Grid times (n,) [s] and poses (n, n_trackers, 4, 4) of a recording with its first and
    last pose held ``pad`` seconds before and after it."""
    times, poses = grid_poses(sample, dt)
    k = round(pad / dt)
    poses = np.concatenate([np.repeat(poses[:1], k, 0), poses, np.repeat(poses[-1:], k, 0)])
    return times[0] + (np.arange(poses.shape[0]) - k) * dt, poses


def recording_units(sample: MultiTrajectory, levels: SpeedLevels, L: float, dt: float = 0.02,
                    lag: int = 5, valley_ratio: float = 0.5) -> list[Unit]:
    """The movement units the live segmenter cuts a recording into (with the recording's first
    and last pose held for 0.5 s around it, so that a recording that starts or ends in motion
    still has its strokes closed); running indices into :func:`_padded`'s poses."""
    times, poses = _padded(sample, dt)
    seg = MultiMotionSegmenter(levels, L, dt, lag, valley_ratio, poses.shape[0] + 1,
                               poses.shape[1])
    units = []
    for k in range(poses.shape[0]):
        unit = seg.push(float(times[k]), poses[k])
        if unit is not None:
            units.append(unit)
    return units


def live_cut(sample: MultiTrajectory, levels: SpeedLevels, L: float, dt: float = 0.02,
             lag: int = 5, valley_ratio: float = 0.5, margin: int = 5) -> MultiTrajectory | None:
    """A recording as the live spotter cuts the whole gesture out of a stream: from its first
    movement unit's start to its last one's end, with ``margin`` grid samples on each side, on the
    50 Hz grid (None without a unit)."""
    units = recording_units(sample, levels, L, dt, lag, valley_ratio)
    if not units:
        return None
    times, poses = _padded(sample, dt)
    a, b = max(units[0].start - margin, 0), min(units[-1].end + margin, times.size - 1)
    if b - a < 5:
        return None
    trackers = tuple(Trajectory.from_poses(times[a:b + 1], poses[a:b + 1, j],
                                           source=f"{sample.source} (cut)")
                     for j in range(poses.shape[1]))
    return MultiTrajectory(trackers, sample.names, sample.up, f"{sample.source} (cut)")


def multi_candidate_limits(samples: Sequence[MultiTrajectory], levels: SpeedLevels, L: float,
                           span_factor: float, pause_factor: float, dt: float = 0.02,
                           labels: Sequence[str] | None = None, min_pause: float = 0.5,
                           ) -> tuple[int, float, float, float]:
    """``(max_units, max_duration [s], max_pause [s], pause_ratio)`` from the model recordings, by
    the single-tracker rule (:func:`~framefree.online.limits.candidate_limits`, a recording that
    rests far longer than any other left out with ``labels``) on the units of the combined
    speed."""
    return limits_of_units([recording_units(s, levels, L, dt) for s in samples], span_factor,
                           pause_factor, labels, min_pause)


class GridJoiner:
    """Joins the trackers' uniform grids: a grid time is handed on once every tracker has a pose
    there.

    Each tracker has its own grid (its resampler starts at its first accepted sample, and again
    after a restart); a grid pose is filed under the index ``round((t - origin) / dt)`` of the
    first time seen since the last :meth:`reset`, so grids that start a fraction of a step apart
    still meet. An index that some tracker skipped is dropped.

    Parameters
    ----------
    n_trackers : int
    dt : float
        Grid step [s].
    """

    def __init__(self, n_trackers: int, dt: float) -> None:
        self.n_trackers = int(n_trackers)
        self.dt = float(dt)
        self.reset()

    def reset(self) -> None:
        """Forget the poses waiting for the other trackers and the grid's origin (a restart)."""
        self.origin: float | None = None
        self._queues: list[deque[tuple[int, float, np.ndarray]]] = [
            deque() for _ in range(self.n_trackers)]
        self._last = -1

    def add(self, tracker: int, times: np.ndarray, poses: np.ndarray) -> None:
        """File a tracker's new grid poses: times (k,) [s], poses (k, 4, 4)."""
        for t, T in zip(times, poses, strict=True):
            if self.origin is None:
                self.origin = float(t)
            k = round((float(t) - self.origin) / self.dt)
            if k > self._last:
                self._queues[tracker].append((k, float(t), T))

    def ready(self) -> list[tuple[float, np.ndarray]]:
        """The grid times every tracker has reached: ``(t [s], poses (n_trackers, 4, 4))`` each,
        in time order; ``t`` is the first tracker's grid time."""
        out = []
        queues = self._queues
        while all(queues):
            head = max(q[0][0] for q in queues)
            for q in queues:
                while q and q[0][0] < head:
                    q.popleft()
            if not all(queues):
                break
            items = [q.popleft() for q in queues]
            self._last = head
            out.append((items[0][1], np.stack([it[2] for it in items])))
        return out


class StopGroup:
    """One :class:`~framefree.online.stop.StopDetector` per tracker: a stop signal of either hand
    is the stop. Another tracker's detector firing while the group is not re-armed (the same
    signal made with both hands) gives no second stop.

    Parameters
    ----------
    detectors : sequence of StopDetector
    """

    def __init__(self, detectors: Sequence[StopDetector]) -> None:
        self.detectors = list(detectors)
        self.threshold = self.detectors[0].threshold

    @property
    def armed(self) -> bool:
        """False from a stop until every tracker's rotation has slowed down again."""
        return all(d.armed for d in self.detectors)

    @property
    def angular_speed(self) -> float:
        """The fastest tracker's windowed angular speed [rad/s] (NaN before any)."""
        speeds = [d.angular_speed for d in self.detectors if not math.isnan(d.angular_speed)]
        return max(speeds) if speeds else math.nan

    def update(self, tracker: int, t: float, q: np.ndarray) -> bool:
        """One accepted sample of ``tracker`` at ``t`` [s] with orientation ``q`` (4,); True when
        it fires the group's stop."""
        armed = self.armed
        fired = self.detectors[tracker].update(t, q)
        return fired and armed

    def reset(self) -> None:
        for d in self.detectors:
            d.reset()

    def rearm_now(self) -> None:
        for d in self.detectors:
            d.rearm_now()
