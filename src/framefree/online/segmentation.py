"""Cutting a live pose stream into movement units at rests and speed minima.

A hand gesture is made of one or a few *strokes*: bell-shaped bursts of motion whose speed falls
towards zero where the hand stops or reverses (a straight out-and-back has two strokes, a circle
one). framefree finds these units in the stream with a **bi-invariant motion speed**, the screw-path
rate of the hand: the screw path (``framefree.core.progress``) of the displacement between the pose now
and the pose ``lag`` samples ago, divided by the time between them. Neither a change of the tracker's
world frame nor of its placement in the hand changes it, and measuring it over ``lag`` samples of a
uniform 50 Hz grid averages out tracker jitter and time-stamp jitter.

Three stages, each small and with its own state:

* :class:`UniformResampler`: accepted samples at any (jittered, gappy) times → poses on a uniform
  grid (ScLERP between consecutive samples), the grid the offline classifier resamples to as well;
* :class:`PoseBuffer`: a ring buffer of the latest uniform poses (bounded memory);
* :class:`MotionSegmenter`: the speed signal and the units, with hysteresis between a *rest* level
  and a *move* level, a *valley* rule for strokes that follow each other without rest (a
  local speed minimum below ``valley_ratio`` × the stroke's peak, confirmed when the speed rises
  again by the same factor), and a *settle* rule for a stroke after which the hand drifts on
  without resting (the speed stays below ``valley_ratio`` × the stroke's peak for ``settle``
  seconds).

The rest and move levels come from the model recordings
(:func:`~framefree.online.rest_levels.speed_levels`): the noise floor of their rests and the peak
speeds of their strokes.

See ``docs/online.md`` (Segment spotting).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np

from ..core import se3, se3_kernels
from ..core.progress import screw_path_increment

__all__ = [
    "HEADING_SPEED",
    "MotionSegmenter",
    "PoseBuffer",
    "SpeedLevels",
    "UniformResampler",
    "Unit",
    "heading",
    "motion_speed",
]


class UniformResampler:
    """Poses on a uniform time grid from samples at arbitrary increasing times.

    Grid times are ``t_0 + k·dt`` with ``t_0`` the first sample after a (re)start. Each new sample
    yields the grid poses in ``(t_prev, t]``, interpolated by ScLERP between the previous and the new
    sample; a sample that falls between two grid points yields nothing.

    Parameters
    ----------
    dt : float
        Grid step [s] (0.02: the 50 Hz grid of the offline classifier).
    """

    def __init__(self, dt: float = 0.02) -> None:
        if not dt > 0:
            raise ValueError(f"dt must be positive, got {dt}")
        self.dt = float(dt)
        self.reset()

    def reset(self) -> None:
        """Start a new grid at the next sample."""
        self._t0: float | None = None
        self._k = 0  # index of the next grid point
        self._t: float = 0.0
        self._T: np.ndarray | None = None

    def push(self, t: float, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Offer a sample at time ``t`` [s] with pose ``T`` (4, 4).

        Returns
        -------
        times : ndarray, shape (k,)
            Grid times [s] covered by this sample (possibly none).
        poses : ndarray, shape (k, 4, 4)
        """
        if self._T is None or self._t0 is None:
            self._t0, self._t, self._T = float(t), float(t), np.array(T, dtype=np.float64)
            self._k = 1
            return np.array([float(t)]), self._T[None].copy()
        if t <= self._t:
            return np.empty(0), np.empty((0, 4, 4))
        k_end = math.floor((t - self._t0) / self.dt + 1e-9)
        ks = np.arange(self._k, k_end + 1)
        times = self._t0 + ks * self.dt
        alpha = (times - self._t) / (t - self._t)
        B = np.asarray(T, dtype=np.float64)
        if ks.size:
            n = ks.size
            poses = se3.sclerp(np.broadcast_to(self._T, (n, 4, 4)), np.broadcast_to(B, (n, 4, 4)),
                               alpha)
        else:
            poses = np.empty((0, 4, 4))
        self._k = k_end + 1
        self._t, self._T = float(t), B.copy()
        return times, poses


class PoseBuffer:
    """Ring buffer of the latest uniform poses, addressed by a running sample index.

    Parameters
    ----------
    capacity : int
        Number of poses kept; older ones are overwritten (memory stays bounded).
    """

    def __init__(self, capacity: int) -> None:
        if capacity < 2:
            raise ValueError(f"capacity must be at least 2, got {capacity}")
        self.capacity = int(capacity)
        self._poses = np.zeros((self.capacity, 4, 4))
        self._times = np.zeros(self.capacity)
        self.count = 0  # running index of the next pose
        self.first = 0  # running index of the first pose since the last reset

    def reset(self) -> None:
        """Forget everything (indices keep running, so old units never address new poses)."""
        self.first = self.count

    @property
    def oldest(self) -> int:
        """Running index of the oldest pose still held."""
        return max(self.count - self.capacity, self.first)

    def append(self, t: float, T: np.ndarray) -> int:
        """Store a pose; return its running index."""
        i = self.count % self.capacity
        self._poses[i] = T
        self._times[i] = t
        self.count += 1
        return self.count - 1

    def pose(self, index: int) -> np.ndarray:
        """Pose (4, 4) at a running index (must still be held)."""
        return self._poses[index % self.capacity]

    def slice(self, start: int, end: int) -> tuple[np.ndarray, np.ndarray]:
        """Times (n,) and poses (n, 4, 4) of running indices ``start..end`` inclusive (clipped to
        what is held)."""
        start = max(start, self.oldest)
        end = min(end, self.count - 1)
        idx = np.arange(start, end + 1) % self.capacity
        return self._times[idx].copy(), self._poses[idx].copy()

    def time(self, index: int) -> float:
        """Time [s] at a running index."""
        return float(self._times[index % self.capacity])

    def _empty(self, capacity: int) -> PoseBuffer:
        """An empty buffer of this kind (a subclass with more per-pose data overrides it)."""
        return PoseBuffer(capacity)

    def snapshot(self, start: int) -> PoseBuffer:
        """A copy of the poses from running index ``start`` (at least :attr:`oldest`) to the
        latest, with the same running indices: it answers :meth:`slice` from ``start`` on exactly
        as this buffer does now, while this buffer goes on filling (another thread classifies
        from the copy)."""
        start = min(max(start, self.oldest), self.count)
        copy = self._empty(max(self.count - start, 2))
        times, poses = self.slice(start, self.count - 1)
        where = np.arange(start, self.count) % copy.capacity
        copy._times[where] = times
        copy._poses[where] = poses
        copy.count, copy.first = self.count, start
        return copy


@dataclass(frozen=True)
class Unit:
    """One movement unit (a stroke, or several strokes without a clear minimum between them).

    Attributes
    ----------
    start, end : int
        Running indices of the uniform poses where the unit starts and ends.
    start_t, end_t : float
        The same as times [s].
    peak : float
        Peak motion speed [m/s of screw path] within the unit.
    rest_after : bool
        True if the hand came to rest after the unit, False if the next unit followed at a speed
        minimum or after the unit settled.
    heading_in, heading_out : ndarray, shape (6,), or None
        Which way the hand moves (:func:`heading`, over the speed's lag) from where the unit
        first reaches, and up to where it last keeps, :data:`HEADING_SPEED` × its peak speed:
        the direction it leaves the previous rest or minimum in, and the one it comes into the
        next in. ``None`` when unknown.
    chord : ndarray, shape (6,), or None
        Where the unit goes as a whole: :func:`heading` from its first to its last pose. A side of
        a drawn polygon is the same however its ends were taken; the plane two chords span is
        what :func:`~framefree.online.span_shape.turn_kinds` compares. ``None`` when unknown.
    settled : bool
        True if the unit ended because it settled: its speed stayed below ``valley_ratio`` × its
        peak for the segmenter's ``settle`` time without the hand coming to rest
        (:class:`MotionSegmenter`). The unit ends where the speed fell below; the slower motion
        after it is the next unit.
    """

    start: int
    end: int
    start_t: float
    end_t: float
    peak: float
    rest_after: bool
    heading_in: np.ndarray | None = field(default=None, compare=False, repr=False)
    heading_out: np.ndarray | None = field(default=None, compare=False, repr=False)
    chord: np.ndarray | None = field(default=None, compare=False, repr=False)
    settled: bool = False


@dataclass(frozen=True)
class SpeedLevels:
    """Speed thresholds of the segmenter [m/s of screw path].

    Attributes
    ----------
    rest : float
        Below this the hand is at rest.
    move : float
        Above this the hand moves (hysteresis: ``move > rest``).
    """

    rest: float
    move: float


def motion_speed(poses: np.ndarray, dt: float, L: float, lag: int) -> np.ndarray:
    """Screw-path rate [m/s] of uniform poses (n, 4, 4): ``s(T_{k-lag}, T_k) / (lag·dt)``.

    Returns
    -------
    ndarray, shape (n,)
        NaN for the first ``lag`` samples.
    """
    n = poses.shape[0]
    v = np.full(n, np.nan)
    P = np.ascontiguousarray(poses, dtype=np.float64)
    for k in range(lag, n):
        v[k] = screw_path_increment(P[k - lag], P[k], L) / (lag * dt)
    return v


#: Fraction of a unit's peak speed where its headings are taken: near the rests or minima around
#: it, where a corner's straight sides still point their own way and a near-stop on a curve has
#: crept along little of it (one fifth; on the replica's development people, half the peak
#: counted corners in 11 of 99 figure eights whose hand nearly stopped at a tight bend).
HEADING_SPEED = 0.2


def heading(A: np.ndarray, B: np.ndarray, L: float) -> np.ndarray:
    """Which way the hand moves from pose ``A`` to pose ``B`` (4, 4): the twist-like vector (6,)
    ``(L·φ, p_B − p_A)`` of the rotation vector φ [rad] of ``R_B R_Aᵀ`` (world axes) and the
    tracker's displacement [m]. A change of world frame turns both halves alike, so the angle
    between two headings (:func:`~framefree.online.span_shape.turn_angle`) does not depend on
    it; a tracker held off the hand's centre of rotation adds the rotation's lever to the
    displacement."""
    A = np.ascontiguousarray(A, dtype=np.float64)
    B = np.ascontiguousarray(B, dtype=np.float64)
    return np.concatenate([L * se3_kernels.rotation_increment_one(A, B), B[:3, 3] - A[:3, 3]])


class MotionSegmenter:
    """Movement units of a stream of uniform poses.

    Parameters
    ----------
    levels : SpeedLevels
        Rest and move speeds [m/s].
    L : float
        Scale length of the screw path [m].
    dt : float
        Grid step [s].
    lag : int
        Samples over which the speed is measured (5: 0.1 s).
    valley_ratio : float
        A speed minimum between two strokes splits them when it is below ``valley_ratio`` × the
        preceding peak and the speed then rises to ``1/valley_ratio`` × the minimum.
    capacity : int
        Poses kept in the buffer.
    settle : float
        Time [s] after which a unit whose speed stays below ``valley_ratio`` × its peak, above
        the rest level, has *settled*: it ends where the speed fell below, the slower motion
        after it starts the next unit, and :attr:`resting` is True for that one pose, so a
        gesture that ended there is confirmed as by a rest. Real hands seldom rest after a
        gesture; they slow down and drift on. ``math.inf`` (the default): never.
    """

    def __init__(
        self,
        levels: SpeedLevels,
        L: float,
        dt: float = 0.02,
        lag: int = 5,
        valley_ratio: float = 0.5,
        capacity: int = 1500,
        settle: float = math.inf,
    ) -> None:
        if not 0 < valley_ratio < 1:
            raise ValueError(f"valley_ratio must be in (0, 1), got {valley_ratio}")
        if not settle > 0:
            raise ValueError(f"settle must be positive, got {settle}")
        self.levels = levels
        self.L = float(L)
        self.dt = float(dt)
        self.lag = int(lag)
        self.valley_ratio = float(valley_ratio)
        self.settle = float(settle)
        self.buffer = PoseBuffer(capacity)
        # the speed of every buffered pose that is the middle of a lag (NaN where none was measured)
        self._speeds = np.full(capacity, np.nan)
        self.speed = math.nan
        self.units: deque[Unit] = deque(maxlen=16)
        self.reset()

    def reset(self) -> None:
        """Start over (after a long gap or a relocation): no unit in progress."""
        self.buffer.reset()
        self._since_restart = 0
        self.moving = False
        self._start = 0
        self._peak = 0.0
        self._vmin = math.inf
        self._imin = 0
        self._below: int | None = None  # where the speed last fell below valley_ratio × peak
        self.settled_now = False
        self._last_rest = self.buffer.count
        self._speeds[:] = np.nan
        self.speed = math.nan

    @property
    def resting(self) -> bool:
        """True while the hand is at rest (no unit in progress), and at the pose where a unit
        settled."""
        return not self.moving or self.settled_now

    def push(self, t: float, T: np.ndarray) -> Unit | None:
        """Add one uniform pose; return the unit that ended with it, if any."""
        k = self.buffer.append(t, T)
        self.settled_now = False
        self._since_restart += 1
        if self._since_restart <= self.lag:
            self._last_rest = k
            return None
        v = self._speed(k)
        self.speed = v
        c = k - self.lag // 2  # the speed describes the middle of the lag
        self._speeds[c % self.buffer.capacity] = v
        lv = self.levels
        if not self.moving:
            if v > lv.move:
                self.moving = True
                self._start = self._last_rest
                self._peak, self._vmin, self._below = v, math.inf, None
            elif v < lv.rest:
                self._last_rest = c
            return None
        if v < lv.rest:
            self.moving = False
            self._last_rest = c
            return self._close(c, rest_after=True)
        if v > self._peak and self._vmin == math.inf:
            self._peak = v
            return None
        if (settled := self._settled(c, v)) is not None:
            return settled
        if v < self.valley_ratio * self._peak and v < self._vmin:
            self._vmin, self._imin = v, c
            return None
        if self._vmin < math.inf and v > self._vmin / self.valley_ratio and v > lv.move:
            unit = self._close(self._imin, rest_after=False)
            self._start, self._peak, self._vmin, self._below = self._imin, v, math.inf, None
            return unit
        return None

    def _settled(self, c: int, v: float) -> Unit | None:
        """The unit in progress, ended where its speed fell below ``valley_ratio`` × its peak,
        if it has stayed below for :attr:`settle` seconds up to the speed ``v`` at running index
        ``c``; the motion from there on is the next unit."""
        if v >= self.valley_ratio * self._peak:
            self._below = None
            return None
        if self._below is None:
            self._below = c
        if (c - self._below) * self.dt < self.settle - 1e-9:
            return None
        end = self._below
        unit = self._close(end, rest_after=False, settled=True)
        self._start, self._peak, self._vmin, self._below = end, v, math.inf, None
        self.settled_now = True
        return unit

    def _speed(self, k: int) -> float:
        """Motion speed [m/s] at the buffered pose ``k``: the screw path from the pose ``lag``
        samples earlier, per second (a segmenter of several trackers adds theirs)."""
        v = screw_path_increment(self.buffer.pose(k - self.lag), self.buffer.pose(k), self.L)
        return v / (self.lag * self.dt)

    def finish(self) -> Unit | None:
        """End the unit in progress at the latest pose (the end of a recording), if any."""
        if not self.moving or self.buffer.count == 0:
            return None
        self.moving = False
        end = self.buffer.count - 1 - self.lag // 2
        self._last_rest = end
        return self._close(end, rest_after=True) if end > self._start else None

    def _close(self, end: int, rest_after: bool, settled: bool = False) -> Unit:
        heading_in, heading_out = self._headings(self._start, end)
        buf = self.buffer
        chord = (heading(buf.pose(self._start), buf.pose(end), self.L)
                 if buf.oldest <= self._start <= end else None)
        unit = Unit(self._start, end, buf.time(self._start), buf.time(end),
                    self._peak, rest_after, heading_in, heading_out, chord, settled)
        self.units.append(unit)
        return unit

    def _headings(self, start: int, end: int) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Headings of the unit ``start..end`` (running indices of the speed's middle) over one lag
        from where it first reaches, and up to where it last keeps, :data:`HEADING_SPEED` × its
        peak speed: the windows lie inside the unit, away from the rests or minima around it."""
        buf = self.buffer
        first = max(start, buf.oldest)
        if end < first:
            return None, None
        speeds = self._speeds[np.arange(first, end + 1) % buf.capacity]
        if not np.isfinite(speeds).any():
            return None, None
        fast = first + np.flatnonzero(speeds >= HEADING_SPEED * np.nanmax(speeds))
        a, b = int(fast[0]), int(fast[-1])
        return (heading(buf.pose(a), buf.pose(min(a + self.lag, buf.count - 1)), self.L),
                heading(buf.pose(max(b - self.lag, buf.oldest)), buf.pose(b), self.L))
