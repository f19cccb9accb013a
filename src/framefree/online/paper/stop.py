"""The per-sample stop detector of the paper's recognizer: a fast rotation of the hand.

See docs/online-paper.md, *The paper's stop detector*.

The signal is the magnitude of the quaternion derivative of the raw time stream,
``|q̇| ≈ |q_k - q_{k-1}| / Δt`` with sign-continuous unit quaternions; for unit quaternions
``|q̇| = |ω| / 2``, so the threshold is half an angular speed [rad/s].

Debouncing (the paper publishes none; docs/online-paper.md, *Choices for the paper's open
points*): the detector fires when ``|q̇|`` has exceeded the threshold on ``samples`` consecutive
samples, then stays silent until ``|q̇|`` has fallen below ``rearm × threshold`` (one stop per
fast rotation).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from ...core.trajectory import Trajectory

__all__ = ["SampleRateStopDetector", "debounced_peak_rate", "quaternion_rates"]


def quaternion_rates(traj: Trajectory) -> np.ndarray:
    """``|q_k - q_{k-1}| / (t_k - t_{k-1})`` for k = 1..N-1 (sign-continuous quaternions) [1/s]."""
    dq = np.linalg.norm(np.diff(traj.q, axis=0), axis=1)
    return dq / np.diff(traj.t)


def debounced_peak_rate(traj: Trajectory, samples: int) -> float:
    """Largest value that ``|q̇|`` exceeds on ``samples`` consecutive samples of a recording."""
    r = quaternion_rates(traj)
    if r.size < samples:
        return 0.0
    if samples == 1:
        return float(r.max())
    win = np.lib.stride_tricks.sliding_window_view(r, samples)
    return float(win.min(axis=1).max())


class SampleRateStopDetector:
    """Threshold on the per-sample ``|q̇|`` with debouncing and re-arming (the paper's detector).

    Sensitive to time-stamp jitter and duplicated samples (one interval of a few milliseconds
    inflates ``|q̇|``); :class:`~framefree.online.stop.StopDetector` measures over a time window
    instead.

    Parameters
    ----------
    threshold : float
        ``|q̇|`` threshold [1/s] (half the angular speed in rad/s).
    samples : int
        Consecutive samples above the threshold needed to fire.
    rearm : float
        Fraction of the threshold below which the detector re-arms after firing.
    refractory : float
        Time [s] after firing during which the detector stays silent.

    Attributes
    ----------
    rate : float
        The last ``|q̇|`` [1/s] (NaN before two samples).
    active : bool
        True while the rotation is fast (at or above the threshold, or not yet re-armed).
    """

    def __init__(
        self, threshold: float, samples: int = 2, rearm: float = 0.7, refractory: float = 1.5
    ) -> None:
        if not threshold > 0:
            raise ValueError(f"stop threshold must be positive, got {threshold}")
        self.threshold = float(threshold)
        self.samples = int(samples)
        self.rearm = float(rearm)
        self.refractory = float(refractory)
        self._fired_at = -math.inf
        self.reset()

    def reset(self) -> None:
        """Forget the previous sample (after a gap or a relocation); keep the armed state."""
        self._t: float | None = None
        self._q: np.ndarray | None = None
        self._run = 0
        self.rate = math.nan
        if not hasattr(self, "armed"):
            self.armed = True

    @property
    def active(self) -> bool:
        """True while the hand rotates fast or the detector has not re-armed yet."""
        return self._run > 0 or not self.armed or (
            self._t is not None and self._t - self._fired_at < self.refractory
        )

    def update(self, t: float, q: np.ndarray) -> bool:
        """Feed a sample (time [s], unit quaternion (4,) sign-continuous); True when a stop fires."""
        fired = False
        if self._q is not None and self._t is not None and t > self._t:
            d = q - self._q
            self.rate = math.sqrt(float(d @ d)) / (t - self._t)
            if self.rate > self.threshold:
                self._run += 1
                quiet = t - self._fired_at < self.refractory
                if self.armed and self._run >= self.samples and not quiet:
                    fired = True
                    self.armed = False
                    self._fired_at = t
            else:
                self._run = 0
                if self.rate < self.rearm * self.threshold:
                    self.armed = True
        self._t = t
        self._q = q
        return fired

    def run(self, samples: Iterable[tuple[float, np.ndarray]]) -> list[float]:
        """Times [s] at which the detector fires over a sequence of ``(t, q)``."""
        return [t for t, q in samples if self.update(t, q)]
