"""Stop detector: a fast rotation of the hand, measured over a short time window.

The signal is the *windowed angular speed*: the rotation angle between the orientation now and the
orientation at least ``window`` seconds ago, divided by the actual time between the two samples
[rad/s]. Measured over 60-100 ms instead of one sample interval, it is not inflated by
time-stamp jitter (±8 ms on a 20 ms period changes it by at most about 16 ms / window) nor by
repeated or interpolated samples.

The detector fires once the windowed angular speed has stayed above the threshold for
``min_duration`` seconds, then stays silent until the speed has fallen below ``rearm`` × threshold
and for ``refractory`` seconds after firing (one stop per stop signal).
:func:`sustained_peak_speed` calibrates the threshold on recordings that must not fire (the
threshold is then a margin times the fastest model rotation).

The per-sample detector of the paper's recognizer is
:class:`framefree.online.paper.stop.SampleRateStopDetector`.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable

import numpy as np

__all__ = [
    "StopDetector",
    "WindowedAngularSpeed",
    "sustained_peak_speed",
    "windowed_angular_speeds",
]


def rotation_angle(a: np.ndarray, b: np.ndarray) -> float:
    """Angle [rad] of the rotation between unit quaternions ``a`` and ``b`` (4,), either sign."""
    c = min(1.0, abs(float(np.dot(a, b))))
    return 2.0 * math.acos(c)


class WindowedAngularSpeed:
    """Streaming angular speed over a time window.

    Parameters
    ----------
    window : float
        Shortest time span [s] the speed is measured over (0.08).
    max_samples : int
        Bound on the samples kept (the window holds ``window`` / period + 1 of them).

    Attributes
    ----------
    value : float
        Latest windowed angular speed [rad/s]; NaN until the samples span ``window`` seconds.
    """

    def __init__(self, window: float = 0.08, max_samples: int = 256) -> None:
        if not window > 0:
            raise ValueError(f"window must be positive, got {window}")
        self.window = float(window)
        self._buf: deque[tuple[float, np.ndarray]] = deque(maxlen=int(max_samples))
        self.value = math.nan

    def reset(self) -> None:
        """Forget the samples."""
        self._buf.clear()
        self.value = math.nan

    def update(self, t: float, q: np.ndarray) -> float:
        """Add a sample (time [s], unit quaternion (4,)); return the windowed speed [rad/s].

        Samples whose time does not increase are ignored (the value is unchanged).
        """
        buf = self._buf
        if buf and t <= buf[-1][0]:
            return self.value
        buf.append((float(t), np.asarray(q, dtype=np.float64)))
        horizon = t - self.window
        while len(buf) > 1 and buf[1][0] <= horizon:
            buf.popleft()
        t0, q0 = buf[0]
        self.value = rotation_angle(q0, q) / (t - t0) if t0 <= horizon else math.nan
        return self.value


def windowed_angular_speeds(t: np.ndarray, q: np.ndarray, window: float = 0.08) -> np.ndarray:
    """Windowed angular speed [rad/s] at every sample of a recording (NaN where undefined).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Time stamps [s].
    q : ndarray, shape (n, 4)
        Unit quaternions ``(w, x, y, z)``.
    """
    w = WindowedAngularSpeed(window, max_samples=max(256, len(t)))
    return np.array([w.update(float(t[k]), q[k]) for k in range(len(t))])


def sustained_peak_speed(
    t: np.ndarray, q: np.ndarray, window: float = 0.08, min_duration: float = 0.04
) -> float:
    """Largest windowed angular speed [rad/s] sustained for ``min_duration`` seconds.

    A :class:`StopDetector` with the same ``window`` and ``min_duration`` and a threshold above
    this value never fires on the recording.
    """
    t = np.asarray(t, dtype=np.float64)
    s = np.nan_to_num(windowed_angular_speeds(t, q, window), nan=0.0)
    best = 0.0
    for k in range(len(t)):
        start = int(np.searchsorted(t, t[k] - min_duration, side="right")) - 1
        if start < 0:
            continue
        best = max(best, float(s[start : k + 1].min()))
    return best


class StopDetector:
    """Threshold on the windowed angular speed, with a minimum duration, a shape check and re-arming.

    A rotation faster than ``threshold`` for ``min_duration`` seconds is a stop *candidate*. With
    ``confirm`` > 0 it is checked for the shape of a stop signal, a quick back-and-forth, before it
    fires: if within ``confirm`` seconds the angular speed over the longer ``confirm`` window
    reaches ``sustain_ratio`` × the peak short-window speed, the hand has kept turning one way for
    that long — a fast gesture stroke, not a stop — and the candidate is dropped; otherwise it fires
    ``confirm`` seconds after it began. A rotation faster than ``instant`` × ``threshold`` fires at
    once. ``confirm = 0`` gives the plain threshold detector.

    Parameters
    ----------
    threshold : float
        Angular speed threshold [rad/s].
    window : float
        Time span [s] of the angular speed measurement (0.08).
    min_duration : float
        Time [s] the speed must stay above the threshold before the detector fires (0.04).
    rearm : float
        Fraction of the threshold below which the detector re-arms after firing (0.7).
    refractory : float
        Time [s] after firing during which the detector stays silent (1.5).
    confirm : float
        Shape check [s]: how long a candidate waits, and the window of the sustained speed (0).
    sustain_ratio : float
        Sustained speed over ``confirm`` relative to the peak speed that marks a gesture stroke.
    instant : float
        A candidate this many times above ``threshold`` fires without the shape check.

    Attributes
    ----------
    angular_speed : float
        Latest windowed angular speed [rad/s] (NaN until the window is filled).
    armed : bool
        False from a stop until the speed falls below ``rearm`` × threshold.
    """

    def __init__(
        self,
        threshold: float,
        window: float = 0.08,
        min_duration: float = 0.04,
        rearm: float = 0.7,
        refractory: float = 1.5,
        confirm: float = 0.0,
        sustain_ratio: float = 0.82,
        instant: float = 1.6,
    ) -> None:
        if not threshold > 0:
            raise ValueError(f"stop threshold must be positive, got {threshold}")
        if not min_duration >= 0:
            raise ValueError(f"min_duration must be non-negative, got {min_duration}")
        if not confirm >= 0:
            raise ValueError(f"confirm must be non-negative, got {confirm}")
        self.threshold = float(threshold)
        self.min_duration = float(min_duration)
        self.rearm = float(rearm)
        self.refractory = float(refractory)
        self.confirm = float(confirm)
        self.sustain_ratio = float(sustain_ratio)
        self.instant = float(instant)
        self._speed = WindowedAngularSpeed(window)
        self._sustained = WindowedAngularSpeed(confirm) if confirm > 0 else None
        self.window = self._speed.window
        self.armed = True
        self._fired_at = -math.inf
        self._settle_until = -math.inf
        self.reset()

    def reset(self) -> None:
        """Forget the samples (after a restart of the stream); keep the armed state."""
        self._speed.reset()
        if self._sustained is not None:
            self._sustained.reset()
        self._t: float | None = None
        self._run_start: float | None = None
        self._pending_since: float | None = None
        self._peak = 0.0
        self._recent: deque[float] = deque(maxlen=3)
        self._vetoed = False
        self.angular_speed = math.nan

    def rearm_now(self) -> None:
        """Forget the last stop as well (a new session)."""
        self.reset()
        self.armed = True
        self._fired_at = -math.inf
        self._settle_until = -math.inf

    def settle(self, t: float) -> None:
        """The tracker's pose jumped at ``t`` [s] (a relocation): fire no stop for ``refractory``
        seconds. A tracking error that flips the orientation and recovers turns the reported
        hand faster than it can turn (real hand tracking, SFINGE3D: 49 rad/s for one frame,
        then 15-17 rad/s back), which is no stop signal."""
        self._settle_until = float(t) + self.refractory

    @property
    def active(self) -> bool:
        """True while the hand rotates fast, until re-armed, and within ``refractory`` of a stop."""
        if self._run_start is not None or not self.armed:
            return True
        return self._t is not None and self._t - self._fired_at < self.refractory

    def _fire(self, t: float) -> bool:
        self.armed = False
        self._fired_at = t
        self._pending_since = None
        return True

    def _check_shape(self, t: float, speed: float, sustained: float) -> bool:
        """A pending candidate: drop it if the rotation is sustained, fire it when its time is up.

        The peak is taken over the median of the last three short-window speeds, so that one
        jittered time stamp cannot inflate it."""
        self._recent.append(speed)
        robust = sorted(self._recent)[len(self._recent) // 2]
        if robust > self._peak:
            self._peak = robust
        if sustained >= self.sustain_ratio * self._peak:
            self._pending_since = None
            self._vetoed = True
            return False
        if t - self._pending_since >= self.confirm:
            return self._fire(t)
        return False

    def update(self, t: float, q: np.ndarray) -> bool:
        """Feed a sample (time [s], unit quaternion (4,)); True when a stop fires."""
        t = float(t)
        if self._t is not None and t <= self._t:
            return False
        self._t = t
        speed = self._speed.update(t, q)
        sustained = self._sustained.update(t, q) if self._sustained is not None else math.nan
        self.angular_speed = speed
        if self._pending_since is not None:
            return self._check_shape(t, speed if speed == speed else 0.0,
                                     sustained if sustained == sustained else 0.0)
        if not speed > self.threshold:  # also NaN: window not filled yet
            self._run_start = None
            if speed < self.rearm * self.threshold:
                self.armed = True
                self._vetoed = False
            return False
        if self._run_start is None:
            self._run_start = t
        quiet = t - self._fired_at < self.refractory or t < self._settle_until
        if (self.armed and not self._vetoed and not quiet
                and t - self._run_start >= self.min_duration):
            if self.confirm == 0.0 or speed >= self.instant * self.threshold:
                return self._fire(t)
            self._pending_since = self._run_start
            self._peak = 0.0
            self._recent.clear()
            return self._check_shape(t, speed, sustained if sustained == sustained else 0.0)
        return False

    def run(self, samples: Iterable[tuple[float, np.ndarray]]) -> list[float]:
        """Times [s] at which the detector fires over a sequence of ``(t, q)``."""
        return [t for t, q in samples if self.update(t, q)]
