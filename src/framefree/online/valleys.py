"""Stroke boundaries without rests: the minima of the smoothed motion speed.

Real hands rarely rest between gestures (on the SFINGE3D sequences the palm keeps moving at about
0.1 m/s, and most swipes start and end without a pause), so a gesture cannot be found by waiting
for a rest. What every performance does have is a speed profile: the hand speeds up into a stroke
and slows down out of it. The boundaries between strokes are therefore taken where the motion
speed has a local minimum, whatever its level:

1. the **motion speed** is the screw path (:func:`~framefree.core.progress.screw_path_increment`,
   frame-free) between the pose now and ``lag`` grid samples ago, per second;
2. it is **smoothed** by a Gaussian of ``sigma`` seconds, truncated at two sigmas (a real tracker's
   orientation jitter adds fast wiggles that are no strokes);
3. a smoothed sample is a **boundary** when it is the lowest within ``±window`` seconds.

A boundary is known ``lag / 2 + 2 sigma + window`` seconds after the pose it marks (0.35 s with
the defaults). Inside a rest the smoothed speed is flat noise and its minima come every few
tenths of a second: they are boundaries too, and the candidates between them are too small to be
any gesture (:mod:`~framefree.online.stroke_spotting` drops them before classifying).
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from ..core.progress import screw_path_increment
from .segmentation import PoseBuffer

__all__ = ["Valleys", "boundaries_of"]


class Valleys:
    """Streaming boundary detector over uniform poses (the running indices of a :class:`PoseBuffer`).

    Parameters
    ----------
    L : float
        Scale length of the screw path [m].
    dt : float
        Grid step [s].
    lag : int
        Grid samples over which the speed is measured (5: 0.1 s).
    sigma : float
        Standard deviation [s] of the Gaussian that smooths the speed (0.1).
    window : float
        Half-width [s] of the neighbourhood a boundary is the minimum of (0.1).
    capacity : int
        Poses kept in the buffer (:attr:`buffer`).

    Attributes
    ----------
    buffer : PoseBuffer
        The uniform poses, by running index.
    path : float
        Smoothed screw path [m] travelled up to the latest smoothed sample (differences between two
        boundaries are the path of the motion between them).
    """

    def __init__(self, L: float, dt: float = 0.02, lag: int = 5, sigma: float = 0.1,
                 window: float = 0.1, capacity: int = 1500) -> None:
        if not (L > 0 and dt > 0 and lag >= 1 and sigma > 0 and window > 0):
            raise ValueError("L, dt, sigma and window must be positive and lag at least 1")
        self.L, self.dt, self.lag = float(L), float(dt), int(lag)
        half = max(1, round(2.0 * sigma / dt))
        x = np.arange(-half, half + 1) * dt
        kernel = np.exp(-0.5 * (x / sigma) ** 2)
        self._kernel = kernel / kernel.sum()
        self._w = max(1, round(window / dt))
        self.buffer = PoseBuffer(capacity)
        self._speeds = np.zeros(capacity)  # smoothed speed by running index (ring)
        #: delay [grid samples] between a pose and the moment it can be a boundary
        self.delay = self.lag // 2 + half + self._w
        self.reset()

    def reset(self) -> None:
        """Start over (a gap or a relocation): no speed, no boundary."""
        self.buffer.reset()
        self._raw: deque[float] = deque(maxlen=self._kernel.size)
        self._smooth: deque[tuple[int, float, float]] = deque(maxlen=2 * self._w + 1)
        self._since_restart = 0
        self._last = -math.inf
        self._speeds[:] = 0.0
        self.path = 0.0
        self.speed = math.nan

    def push(self, t: float, T: np.ndarray) -> tuple[int, float] | None:
        """Add one uniform pose; return ``(running index, smoothed path [m])`` of a boundary that
        became known with it, or ``None``."""
        k = self.buffer.append(t, T)
        self._since_restart += 1
        if self._since_restart == 1:
            self._smooth.append((k, 0.0, 0.0))  # the first pose of a stream starts a candidate
            return self._emit(k, 0.0)
        if self._since_restart <= self.lag:
            return None
        v = screw_path_increment(self.buffer.pose(k - self.lag), self.buffer.pose(k), self.L)
        self._raw.append(v / (self.lag * self.dt))
        if len(self._raw) < self._kernel.size:
            return None
        self.speed = float(np.dot(self._kernel, self._raw))
        self.path += self.speed * self.dt
        centre = k - self.lag // 2 - self._kernel.size // 2  # the pose the smoothed speed describes
        self._speeds[centre % self.buffer.capacity] = self.speed
        self._smooth.append((centre, self.speed, self.path))
        if len(self._smooth) < self._smooth.maxlen:
            return None
        index, value, path = self._smooth[self._w]
        if value <= min(s[1] for s in self._smooth):
            return self._emit(index, path)
        return None

    def peak_speed(self, start: int, end: int) -> float:
        """Highest smoothed speed [m/s] between two running indices (inclusive) still held."""
        start = max(start, self.buffer.oldest)
        if end < start:
            return 0.0
        return float(self._speeds[np.arange(start, end + 1) % self.buffer.capacity].max())

    def _emit(self, index: int, path: float) -> tuple[int, float] | None:
        if index - self._last <= self._w:  # a flat minimum: its first sample only
            return None
        self._last = index
        return index, path


def boundaries_of(poses: np.ndarray, L: float, dt: float = 0.02, **kwargs: float
                  ) -> tuple[list[tuple[int, float]], np.ndarray]:
    """The boundaries a :class:`Valleys` finds in a whole recording (uniform poses (n, 4, 4)).

    Returns
    -------
    boundaries : list of (int, float)
        ``(index into poses, smoothed path [m])``, the last pose included as a boundary.
    speeds : ndarray, shape (n,)
        The smoothed speed [m/s] of each pose (0 where none was measured).
    """
    n = poses.shape[0]
    det = Valleys(L, dt, capacity=max(2, n), **kwargs)
    out = []
    for k in range(n):
        b = det.push(k * dt, poses[k])
        if b is not None:
            out.append(b)
    if not out or out[-1][0] != n - 1:
        out.append((n - 1, det.path))
    return out, det._speeds[:n].copy()
