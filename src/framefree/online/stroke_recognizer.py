"""framefree's stroke recognizer: gestures found in continuous motion, without waiting for rests.

Per pose sample ``(t, p, q)``:

1. **acceptance** (:class:`~framefree.online.acceptance.SampleGate`): invalid, repeated, backwards
   and glitched samples dropped, dropouts bridged, long gaps and relocations restart the stream;
2. **stop** (:class:`~framefree.online.stop.StopDetector`): a fast rotation fires a stop first,
   and nothing before it can become a gesture;
3. **boundaries** (:class:`~framefree.online.valleys.Valleys`): the poses on the uniform 50 Hz grid,
   the minima of the smoothed motion speed;
4. **candidates and decision** (:class:`~framefree.online.stroke_spotting.StrokeSpotter`): every
   span between two boundaries of a plausible duration and size, classified by the offline 1-NN
   classifier, accepted below its gesture's threshold; the best overlapping one fires.

Everything specific to a vocabulary comes from its takes and from recorded non-gesture motion
(:mod:`~framefree.online.stroke_calibration`). See ``docs/online.md``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from .acceptance import SampleGate
from .events import STOP, Event
from .model_settings import model_window_spacing
from .segmentation import UniformResampler
from .spotting import SegmentClassifier
from .stop import StopDetector, sustained_peak_speed
from .streaming import StreamingRecognizer
from .stroke_calibration import StrokeCalibration, calibrate
from .stroke_config import StrokeConfig
from .stroke_spotting import StrokeSpotter
from .valleys import Valleys

__all__ = ["StrokeRecognizer"]

#: Counters of the recognizer's own stages (the acceptance stage adds its own).
STAT_KEYS = ("grid", "boundaries", "candidates", "events", "stops", "restarts")

#: Floor of the stop threshold [rad/s]: no take is so still that a wrist flick of less counts.
STOP_FLOOR = 3.0


def _descriptor(c: StrokeConfig) -> Any:
    from ..descriptors import get_descriptor

    return get_descriptor("bilts+", progress="screw", L=c.L, ds_scale=c.ds_scale,
                          n_samples=c.n_samples, presmooth=c.presmooth, axis_prior=c.axis_prior,
                          spacing=c.window_spacing, align=c.align)


class StrokeRecognizer(StreamingRecognizer):
    """Streaming gesture recognizer for continuous motion: candidates between speed minima,
    classified as offline.

    Build it with :meth:`from_trajectories` (or :meth:`from_dataset`), which measures what the
    configuration leaves ``None`` on the takes; the constructor takes a resolved configuration.

    Parameters
    ----------
    classifier : SegmentClassifier
        The models (descriptors of the takes) and the offline descriptor.
    labels : sequence of str, length M
        Gesture of each model.
    config : StrokeConfig
        Resolved configuration.
    calibration : StrokeCalibration, optional
        Kept for reporting.

    Examples
    --------
    >>> rec = StrokeRecognizer.from_trajectories(takes, labels)   # doctest: +SKIP
    >>> rec.warmup()                                               # doctest: +SKIP
    >>> for t, p, q in source:                                     # doctest: +SKIP
    ...     for event in rec.push(t, p, q):
    ...         print(event.label, event.time)
    """

    method = "strokes"

    def __init__(self, classifier: SegmentClassifier, labels: Sequence[str], config: StrokeConfig,
                 calibration: StrokeCalibration | None = None) -> None:
        c = config
        missing = [n for n in ("gesture_thresholds", "size_limits", "min_duration", "max_duration",
                               "min_speeds", "max_pause", "stop_threshold")
                   if getattr(c, n) is None]
        if missing:
            raise ValueError(f"unresolved settings {missing}: use StrokeRecognizer.from_trajectories")
        self.classifier = classifier
        self.labels = [str(s) for s in labels]
        self.gestures = list(dict.fromkeys(self.labels))
        absent = set(self.gestures) - set(c.gesture_thresholds) | set(self.gestures) - set(c.size_limits)
        if absent:
            raise ValueError(f"gesture_thresholds or size_limits lack {sorted(absent)}")
        self.config, self.calibration = c, calibration
        self.gesture_thresholds = {g: float(c.gesture_thresholds[g]) for g in self.gestures}
        self.stop_threshold = float(c.stop_threshold)
        self.gate = SampleGate(max_bridge=c.max_bridge, nominal_period=c.dt)
        self.stop = StopDetector(self.stop_threshold, confirm=0.3)
        self.resampler = UniformResampler(c.dt)
        capacity = math.ceil((c.max_duration + c.max_pause + c.wait + 2.0) / c.dt) + 64
        self.valleys = Valleys(c.L, c.dt, sigma=c.smoothing, capacity=capacity)
        taus = np.array([self.gesture_thresholds[g] for g in self.labels])
        sizes = np.array([c.size_limits[g] for g in self.labels])
        speeds = np.array([c.min_speeds[g] for g in self.labels])
        self.spotter = StrokeSpotter(classifier, taus, sizes, speeds, c.min_duration,
                                     c.max_duration, c.wait, c.max_pause)
        self._counts = dict.fromkeys(STAT_KEYS, 0)
        self.observations: list[tuple[float, np.ndarray]] = []

    @classmethod
    def from_trajectories(cls, trajectories: Sequence[Trajectory], labels: Sequence[str],
                          config: StrokeConfig | None = None, everyday: Sequence[Trajectory] | None = None,
                          **overrides: Any) -> StrokeRecognizer:
        """Build the models from takes and measure what the configuration leaves ``None``.

        Parameters
        ----------
        trajectories : sequence of Trajectory
            Takes, one gesture performance each.
        labels : sequence of str
            Gesture of each take.
        config : StrokeConfig, optional
            Defaults to ``StrokeConfig()``; keyword ``overrides`` replace its fields.
        everyday : sequence of Trajectory, optional
            Recorded motion that is no gesture of the vocabulary (default: the real recordings
            shipped with framefree, :func:`~framefree.online.stroke_calibration.everyday_motions`).
        """
        if len(trajectories) != len(labels):
            raise ValueError(f"{len(trajectories)} trajectories but {len(labels)} labels")
        if not trajectories:
            raise ValueError("no model recordings")
        c = (config or StrokeConfig()).replace(**overrides)
        if c.window_spacing is None:
            c = c.replace(window_spacing=model_window_spacing(trajectories, c))
        descriptor = _descriptor(c)
        classifier = SegmentClassifier(descriptor, [descriptor.compute(tr) for tr in trajectories])
        c, calibration = calibrate(classifier, trajectories, labels, c, everyday)
        if c.stop_threshold is None:
            peak = max(sustained_peak_speed(tr.t, tr.q) for tr in trajectories)
            c = c.replace(stop_threshold=max(STOP_FLOOR, c.stop_margin * peak))
        return cls(classifier, labels, c, calibration)

    @property
    def stats(self) -> dict[str, int]:
        """Counters of the acceptance stage and of the recognizer's stages."""
        cells, full = self.classifier.cells
        return {**self.gate.stats, **self._counts, "dtw_cells": cells, "dtw_cells_unpruned": full}

    def reset(self) -> None:
        """Forget the stream and the counters (a new session)."""
        self.gate.reset()
        self.stop.rearm_now()
        self._restart()
        self._counts = dict.fromkeys(STAT_KEYS, 0)
        self.classifier.cells = [0, 0]

    def _restart(self) -> None:
        self.resampler.reset()
        self.valleys.reset()
        self.spotter.reset()
        self.stop.reset()

    def warmup(self) -> None:
        """Run every stage once on a synthetic motion (loads the compiled kernels), then reset."""
        t = np.arange(0.0, 4.0, self.config.dt)
        x = np.clip((t - 1.0) / 1.5, 0.0, 1.0)
        s = np.sin(np.pi * x**3 * (10 - 15 * x + 6 * x**2))
        for k in range(t.size):
            p = np.array([0.3 * s[k], 0.05 * s[k] ** 2, 0.0])
            q = np.array([math.cos(0.4 * s[k]), 0.0, 0.0, math.sin(0.4 * s[k])])
            self.push(float(t[k]), p, q)
        self.reset()

    def push(self, t: float, p: Sequence[float] | np.ndarray, q: Sequence[float] | np.ndarray
             ) -> list[Event]:
        """Offer one pose sample; return the events it triggers (usually none), in time order.

        Parameters
        ----------
        t : float
            Time stamp [s].
        p : array_like, shape (3,)
            Position [m].
        q : array_like, shape (4,)
            Orientation quaternion ``(w, x, y, z)`` (any norm and sign).
        """
        self.observations = []
        accepted = self.gate.push(t, p, q)
        if accepted.restarted:
            self._counts["restarts"] += 1
            self._restart()
        events: list[Event] = []
        for ts, ps, qs in accepted.samples:
            if self.stop.update(ts, qs):
                self._counts["stops"] += 1
                self.spotter.discard_before(self.valleys.buffer.count)
                events.append(Event(STOP, ts, -1.0, -1))
            T = np.eye(4)
            T[:3, :3] = se3.matrix_from_quaternion(qs)
            T[:3, 3] = ps
            times, poses = self.resampler.push(ts, T)
            for k in range(times.size):
                event = self._on_grid(float(times[k]), poses[k])
                if event is not None:
                    events.append(event)
        return events

    def _on_grid(self, t: float, T: np.ndarray) -> Event | None:
        self._counts["grid"] += 1
        found = self.valleys.push(t, T)
        if not self.stop.armed:  # a stop fired and the hand still turns fast: no gesture
            self.spotter.discard_before(self.valleys.buffer.count)
            return None
        self.spotter.evaluated.clear()
        if found is not None:
            self._counts["boundaries"] += 1
            self.spotter.boundary(found[0], found[1], self.valleys, t)
            self._counts["candidates"] += len(self.spotter.evaluated)
            self.observations.extend(self.spotter.evaluated)
        fired = self.spotter.poll(t)
        if fired is None:
            return None
        self._counts["events"] += 1
        return Event(self.labels[fired.model], t, fired.distance, fired.model)

    def gesture_dissimilarities(self) -> dict[str, float]:
        """Distance of the latest classified candidate to each gesture's nearest model."""
        out = dict.fromkeys(self.gestures, math.inf)
        d = self.spotter.last_distances
        if d is not None:
            for j, g in enumerate(self.labels):
                out[g] = min(out[g], float(d[j]))
        return out

    def describe(self) -> dict[str, Any]:
        """Settings (resolved), models and calibration as a JSON-friendly dict."""
        return {
            "method": self.method,
            "config": self.config.to_dict(),
            "gesture_thresholds": dict(self.gesture_thresholds),
            "stop_threshold": self.stop_threshold,
            "n_models": len(self.labels),
            "gestures": self.gestures,
            "calibration": None if self.calibration is None else self.calibration.summary(),
        }

    @classmethod
    def restore(cls, takes: Sequence[Trajectory], labels: Sequence[str], config: StrokeConfig,
                gesture_thresholds: dict[str, float]) -> StrokeRecognizer:
        """A recognizer over models rebuilt from ``takes`` with a resolved ``config`` and
        thresholds restored (no calibration)."""
        return cls.from_trajectories(list(takes), list(labels),
                                     config.replace(gesture_thresholds=dict(gesture_thresholds)))
