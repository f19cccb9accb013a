"""A practitioner's baseline: sliding windows over the palm positions, 1-NN by DTW, a threshold.

``--method window`` / :class:`WindowSpotter`. It is what one writes first when asked to spot
gestures in a stream, kept small so that a reader can check it, and measured beside framefree's
recognizer and the paper's (docs/online.md, *Three live recognizers side by side*):

* **representation**: the palm positions only, resampled in time to ``n_points`` samples and made
  translation-invariant by subtracting their mean. No orientation, no frame invariance: models
  and stream are assumed to come from the same sensor in the same world frame, as they do when
  one person enrolls and uses one tracker (and on SFINGE3D). Rotation of the world, grip or size
  are not compensated: that is the practitioner's bet this baseline stands for;
* **windows**: ending at the newest pose, every ``stride`` seconds, of the shortest, median and
  longest duration of the model takes (the takes as recorded, rests included);
* **motion gate**: a window whose path (of its resampled points) is shorter than ``min_path``
  × the shortest take's is not compared: a window of rest with the first tenths of a second of a
  gesture is otherwise near every take of a small gesture;
* **distance**: DTW with the Euclidean distance between points [m], summed along the path and
  divided by the path's length, to every take: the nearest take (1-NN) names the gesture;
* **threshold** per gesture, from the takes alone: the ``threshold_quantile`` of the
  leave-one-out distances of its takes (each take to the nearest other take of the gesture),
  times ``threshold_factor``;
* **decision**: while windows lie below their gesture's threshold the lowest ratio
  distance/threshold is kept; it fires once no window is below, or after ``patience``
  evaluations without a lower one; then nothing fires for ``refractory`` seconds (default: the
  shortest take's duration);
* **stop signal**: no take demonstrates it, so a window matcher cannot learn it; framefree's stop
  detector (:class:`~framefree.online.stop.StopDetector`, threshold from the takes as for the
  default recognizer) is borrowed, so that all three methods are compared on the same events.
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from ..core.trajectory import Trajectory
from ..errors import FramefreeError
from .acceptance import well_formed
from .config import RecognizerConfig
from .events import STOP, Event
from .stop import StopDetector, sustained_peak_speed
from .streaming import StreamingRecognizer

__all__ = ["WindowConfig", "WindowSpotter", "dtw_distances", "path_length", "window_points"]

#: Counters of :attr:`WindowSpotter.stats`.
STAT_KEYS = ("samples", "accepted", "nan", "bad_quaternion", "not_later", "gaps", "windows",
             "still", "events", "stops")


@dataclass(frozen=True)
class WindowConfig:
    """Settings of :class:`WindowSpotter` (``None``: derived from the model takes).

    ``stride``, ``threshold_quantile``, ``patience`` and ``min_path`` were chosen together by F1 on
    SFINGE3D sequences 1-18 (quantile 0.5 / 0.75 / 0.9 / 1, stride 0.1 / 0.2 s, patience 3 / 10,
    gate 0 / 0.5; docs/online.md, *Three live recognizers side by side*), never on the sequences
    or people reported.

    Attributes
    ----------
    n_points : int
        Samples every window and every take is resampled to (in time).
    stride : float
        Seconds between two evaluations of the windows (0.2).
    durations : tuple of float or None
        Window durations [s]; ``None``: the shortest, median and longest take.
    threshold : float or None
        One threshold for every gesture [m]; ``None``: per gesture from the takes.
    threshold_quantile, threshold_factor : float
        τ_g = factor × this quantile of gesture g's leave-one-out distances (0.9 and 1).
    min_path : float
        The motion gate: fraction of the shortest take's path [m] a window must travel.
    patience : int
        Evaluations without a lower ratio after which the kept candidate fires (10).
    refractory : float or None
        Seconds after an event during which nothing fires; ``None``: the shortest take.
    max_gap : float
        A gap in the time stamps longer than this [s] starts the windows afresh.
    stop : bool
        Borrow framefree's stop detector (see the module docstring).
    stop_threshold : float or None
        Its threshold [rad/s]; ``None``: as :class:`~framefree.online.RecognizerConfig` derives it.
    """

    n_points: int = 32
    stride: float = 0.2
    durations: tuple[float, ...] | None = None
    threshold: float | None = None
    threshold_quantile: float = 0.9
    threshold_factor: float = 1.0
    min_path: float = 0.5
    patience: int = 10
    refractory: float | None = None
    max_gap: float = 0.5
    stop: bool = True
    stop_threshold: float | None = None

    def __post_init__(self) -> None:
        if self.n_points < 4:
            raise ValueError(f"n_points must be at least 4, got {self.n_points}")
        for name in ("stride", "threshold_factor", "max_gap"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if not 0.0 <= self.min_path < 1.0:
            raise ValueError(f"min_path must be in [0, 1), got {self.min_path}")
        if not 0.0 <= self.threshold_quantile <= 1.0:
            raise ValueError(f"threshold_quantile must be in [0, 1], got {self.threshold_quantile}")
        if self.threshold is not None and not self.threshold > 0:
            raise ValueError(f"threshold must be positive, got {self.threshold}")
        if self.durations is not None and not all(d > 0 for d in self.durations):
            raise ValueError(f"durations must be positive, got {self.durations}")

    def replace(self, **changes: Any) -> WindowConfig:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)


def window_points(t: np.ndarray, p: np.ndarray, n_points: int) -> np.ndarray:
    """Positions resampled at ``n_points`` equally spaced times, minus their mean.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Increasing time stamps [s].
    p : ndarray, shape (N, 3)
        Positions [m].
    n_points : int

    Returns
    -------
    ndarray, shape (n_points, 3)
        Translation-invariant positions [m].
    """
    tq = np.linspace(t[0], t[-1], n_points)
    out = np.column_stack([np.interp(tq, t, p[:, c]) for c in range(3)])
    return out - out.mean(axis=0)


@njit(cache=True)
def dtw_distances(x, models):
    """DTW distance of ``x`` (n, 3) to every model of ``models`` (M, n, 3): the Euclidean point
    distances [m] summed along the best path (steps (1,0), (0,1), (1,1)), divided by its length;
    returns (M,) [m]."""
    n = x.shape[0]
    M = models.shape[0]
    out = np.empty(M)
    cost = np.empty((n, n))
    steps = np.empty((n, n))
    for j in range(M):
        y = models[j]
        for a in range(n):
            for b in range(n):
                d = math.sqrt((x[a, 0] - y[b, 0]) ** 2 + (x[a, 1] - y[b, 1]) ** 2
                              + (x[a, 2] - y[b, 2]) ** 2)
                if a == 0 and b == 0:
                    cost[a, b], steps[a, b] = d, 1.0
                    continue
                best, k = math.inf, 0.0
                if a > 0 and cost[a - 1, b] < best:
                    best, k = cost[a - 1, b], steps[a - 1, b]
                if b > 0 and cost[a, b - 1] < best:
                    best, k = cost[a, b - 1], steps[a, b - 1]
                if a > 0 and b > 0 and cost[a - 1, b - 1] <= best:
                    best, k = cost[a - 1, b - 1], steps[a - 1, b - 1]
                cost[a, b], steps[a, b] = best + d, k + 1.0
        out[j] = cost[n - 1, n - 1] / steps[n - 1, n - 1]
    return out


def path_length(x: np.ndarray) -> float:
    """Length [m] of the polyline through the points ``x`` (n, 3)."""
    return float(np.linalg.norm(np.diff(x, axis=0), axis=1).sum())


def _leave_one_out(models: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """Distance of each take (M,) [m] to the nearest other take of its gesture (inf if alone)."""
    out = np.full(len(labels), np.inf)
    for j in range(len(labels)):
        same = labels == labels[j]
        same[j] = False
        if same.any():
            out[j] = float(dtw_distances(models[j], models[same]).min())
    return out


def _stop_detector(trajectories: Sequence[Trajectory], threshold: float | None) -> StopDetector:
    """framefree's stop detector with the default recognizer's settings."""
    c = RecognizerConfig().constants
    if threshold is None:
        peak = max(sustained_peak_speed(tr.t, tr.q, c.stop_window, c.stop_min_duration)
                   for tr in trajectories)
        threshold = max(c.stop_floor, c.stop_margin * peak)
    return StopDetector(threshold, c.stop_window, c.stop_min_duration, c.stop_rearm,
                        c.stop_refractory, c.stop_confirm, c.stop_sustain_ratio, c.stop_instant)


class WindowSpotter(StreamingRecognizer):
    """The practitioner's sliding-window 1-NN spotter (see the module docstring).

    Parameters
    ----------
    models : ndarray, shape (M, n_points, 3)
        Every take's positions, resampled and centred (:func:`window_points`) [m].
    labels : sequence of str, length M
        Gesture of each take.
    config : WindowConfig
        With ``durations`` and ``refractory`` set (:meth:`from_trajectories` derives them).
    gesture_thresholds : dict of str to float
        τ_g [m] of each gesture.
    stop : StopDetector or None
        The borrowed stop detector (None: no stop events).

    Attributes
    ----------
    method : str
        ``"window"``.
    gestures : list of str
        Distinct labels in first-appearance order.
    stats : dict of str to int
        Counters (:data:`STAT_KEYS`).
    observations : list of (float, ndarray (M,))
        The time [s] and the distance to every take of each evaluation of the latest :meth:`push`.
    """

    method = "window"

    def __init__(self, models: np.ndarray, labels: Sequence[str], config: WindowConfig,
                 gesture_thresholds: dict[str, float], stop: StopDetector | None = None) -> None:
        if config.durations is None or config.refractory is None:
            raise ValueError("config.durations and config.refractory must be set")
        self.models = np.ascontiguousarray(models, dtype=np.float64)
        self.labels = [str(s) for s in labels]
        self.gestures = list(dict.fromkeys(self.labels))
        self.config = config
        self.gesture_thresholds = {g: float(gesture_thresholds[g]) for g in self.gestures}
        self._tau = np.array([self.gesture_thresholds[s] for s in self.labels])
        self.stop = stop
        self.stop_threshold = stop.threshold if stop is not None else math.inf
        self._span = max(config.durations) + 2 * config.stride
        self.min_path = config.min_path * min(path_length(x) for x in self.models)
        self.reset()

    @classmethod
    def from_trajectories(cls, trajectories: Sequence[Trajectory], labels: Sequence[str],
                          config: WindowConfig | None = None, **overrides: Any) -> WindowSpotter:
        """Takes → models, window durations, thresholds and refractory period.

        Parameters
        ----------
        trajectories : sequence of Trajectory
            The model takes (one performance each, rests included).
        labels : sequence of str
            Gesture of each take.
        config : WindowConfig, optional
            Keyword ``overrides`` replace its fields.

        Raises
        ------
        FramefreeError
            Without takes, with as many labels as takes, or with a setting it does not have.
        """
        if len(trajectories) != len(labels) or not trajectories:
            raise FramefreeError(f"{len(trajectories)} model takes and {len(labels)} labels: "
                                 "the window baseline needs one label per take, and takes")
        unknown = set(overrides) - {f.name for f in dataclasses.fields(WindowConfig)}
        if unknown:
            names = ", ".join("--" + k.replace("_", "-") for k in sorted(unknown))
            raise FramefreeError(f"{names} do not apply to --method window")
        c = (config or WindowConfig()).replace(**overrides)
        dur = np.array([float(tr.t[-1] - tr.t[0]) for tr in trajectories])
        if c.durations is None:
            c = c.replace(durations=tuple(float(x) for x in np.unique(np.quantile(dur, [0, 0.5, 1]))))
        if c.refractory is None:
            c = c.replace(refractory=float(dur.min()))
        models = np.array([window_points(tr.t, tr.p, c.n_points) for tr in trajectories])
        labs = np.array([str(s) for s in labels])
        loo = _leave_one_out(models, labs)
        tau = {}
        for g in dict.fromkeys(labs.tolist()):
            d = loo[(labs == g) & np.isfinite(loo)]
            if c.threshold is not None:
                tau[g] = c.threshold
            elif d.size == 0:
                raise FramefreeError(f"gesture {g} has one take: the window baseline needs two "
                                     "to set its threshold (or give --threshold)")
            else:
                tau[g] = c.threshold_factor * float(np.quantile(d, c.threshold_quantile))
        stop = _stop_detector(trajectories, c.stop_threshold) if c.stop else None
        return cls(models, labs.tolist(), c, tau, stop)

    def reset(self) -> None:
        """Forget the stream."""
        self._t: deque[float] = deque()
        self._p: deque[np.ndarray] = deque()
        self._next_eval = -math.inf
        self._quiet_until = -math.inf
        self._pending: tuple[float, int, float, int] | None = None  # ratio, model, d, stale
        self.observations: list[tuple[float, np.ndarray]] = []
        self.stats = dict.fromkeys(STAT_KEYS, 0)
        if self.stop is not None:
            self.stop.rearm_now()

    def warmup(self) -> None:
        """Compile the DTW kernel (then forget the stream)."""
        dtw_distances(self.models[0], self.models[:1])
        self.reset()

    def push(self, t: float, p: Sequence[float] | np.ndarray,
             q: Sequence[float] | np.ndarray) -> list[Event]:
        """Offer one pose sample (``t`` [s], ``p`` (3,) [m], ``q`` (4,) ``w, x, y, z``); return
        its events (a stop, a gesture, or none)."""
        self.stats["samples"] += 1
        self.observations = []
        sample = well_formed(t, p, q, self.stats)
        if sample is None:
            return []
        t, p, q = sample
        if self._t and t <= self._t[-1]:
            self.stats["not_later"] += 1
            return []
        if self._t and t - self._t[-1] > self.config.max_gap:
            self.stats["gaps"] += 1
            self._t.clear()
            self._p.clear()
        self.stats["accepted"] += 1
        self._t.append(t)
        self._p.append(p)
        while self._t[0] < t - self._span:
            self._t.popleft()
            self._p.popleft()
        if self.stop is not None and self.stop.update(t, q):
            self.stats["stops"] += 1
            self._pending = None
            self._quiet_until = t + self.config.refractory
            return [Event(STOP, t, -1.0, -1)]
        if t < self._next_eval or t < self._quiet_until:
            return []
        self._next_eval = t + self.config.stride
        return self._evaluate(t)

    def _evaluate(self, t: float) -> list[Event]:
        """Compare the windows ending now with every take; keep or fire the best candidate."""
        times = np.array(self._t)
        pos = np.array(self._p)
        best = np.full(len(self.labels), np.inf)
        for dur in self.config.durations:
            if times[-1] - times[0] < dur - 0.5 * self.config.stride:
                continue
            sel = times >= t - dur
            if sel.sum() < 3:
                continue
            x = window_points(times[sel], pos[sel], self.config.n_points)
            if path_length(x) < self.min_path:
                self.stats["still"] += 1
                continue
            best = np.minimum(best, dtw_distances(x, self.models))
            self.stats["windows"] += 1
        if not np.isfinite(best).any():
            return []
        self.observations.append((t, best))
        ratio = best / self._tau
        j = int(np.argmin(ratio))
        r = float(ratio[j])
        pend = self._pending
        if r < 1.0 and (pend is None or r < pend[0]):
            self._pending = (r, j, float(best[j]), 0)
            return []
        if pend is None:
            return []
        self._pending = (*pend[:3], pend[3] + 1)
        if r >= 1.0 or pend[3] + 1 >= self.config.patience:
            return self._fire(t)
        return []

    def _fire(self, t: float) -> list[Event]:
        assert self._pending is not None
        _, j, d, _ = self._pending
        self._pending = None
        self._quiet_until = t + self.config.refractory
        self.stats["events"] += 1
        return [Event(self.labels[j], t, d, j)]

    def describe(self) -> dict[str, Any]:
        """Settings, derived values and thresholds as a JSON-friendly dict."""
        return {"method": self.method, "config": dataclasses.asdict(self.config),
                "gesture_thresholds": dict(self.gesture_thresholds),
                "stop_threshold": self.stop_threshold, "n_models": len(self.labels),
                "gestures": self.gestures}
