"""framefree's live recognizer: whole gestures spotted in the stream and classified as offline.

Per pose sample ``(t, p, q)``, four small stages:

1. **acceptance** (:class:`~framefree.online.acceptance.SampleGate`): invalid, repeated, backwards
   and glitched samples are dropped, quaternion signs made continuous, dropouts up to
   ``max_bridge`` seconds bridged by ScLERP, longer gaps and relocations restart the stream; a
   sample is a glitch when it moves faster than three times the takes' fastest, or than a
   hand-held tracker when the takes are slower (:func:`~framefree.online.acceptance.gate_limits`);
2. **stop detection** (:class:`~framefree.online.stop.StopDetector`): windowed angular speed; a
   stop fires first and nothing that overlaps the fast rotation can become a gesture; for
   ``stop_refractory`` seconds after a relocation no stop fires (a tracking error settling);
3. **segmentation** (:mod:`~framefree.online.segmentation`): the samples are put on the uniform
   50 Hz grid and cut into movement units at rests and speed minima;
4. **classification and decision** (:mod:`~framefree.online.spotting`): every candidate segment
   that ends with a unit is classified by the offline 1-NN classifier (same descriptor, same DTW),
   accepted below its gesture's threshold and within its closure limit, and the best accepted
   candidate fires once the hand rests after it.

Everything the recognizer needs besides a few constants about people comes from the model
recordings (:meth:`Recognizer.from_trajectories`). See ``docs/online.md``.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from ..io.library_file import LibraryError, library_takes, read_library_file
from .acceptance import HAND_HELD_SPEEDS, SampleGate, gate_limits
from .background import SerialWorker
from .config import RecognizerConfig
from .events import STOP, Event
from .learned import LearnedSettings, restored_provenance, rule_name, split_settings
from .library_settings import settings_from_meta
from .model_settings import (
    LearnedDraft,
    make_spotter,
    model_window_spacing,
    resolve_learned,
    resolve_smoothing,
    segment_descriptor,
)
from .noisy_orientation import IDENTITY, resolve_orientation
from .segment_classifier import SegmentClassifier
from .segmentation import (
    MotionSegmenter,
    PoseBuffer,
    SpeedLevels,
    UniformResampler,
    Unit,
)
from .smoothing import GridSmoother
from .stop import StopDetector
from .streaming import StreamingRecognizer
from .thresholds import SegmentThresholds

__all__ = ["STAT_KEYS", "Recognizer"]

#: Counters of the recognizer's own stages (the acceptance stage adds its own, see
#: :data:`~framefree.online.acceptance.GATE_STAT_KEYS`).
STAT_KEYS = ("grid", "units", "candidates", "events", "stops", "restarts")


class Recognizer(StreamingRecognizer):
    """Streaming gesture recognizer: segment spotting with offline-identical classification.

    Build it with :meth:`from_trajectories` or :meth:`from_dataset`, which learn from the takes
    every value the user does not set, or with :meth:`load` from a gesture library; the
    constructor takes the learned values ready.

    Parameters
    ----------
    classifier : SegmentClassifier
        Model descriptors and the descriptor that computed them.
    labels : sequence of str, length M
        Gesture of each model.
    config : RecognizerConfig
        The user's settings (with the descriptor settings and constants).
    learned : LearnedSettings
        Everything learned from the takes (:func:`~framefree.online.model_settings.
        resolve_learned`), at least the speed levels, candidate limits and thresholds.
    calibration : SegmentThresholds, optional
        Kept for reporting.

    Attributes
    ----------
    config : RecognizerConfig
        As given.
    learned_ : LearnedSettings
        As given: the learned values and their provenance.
    gesture_thresholds : dict of str to float
        τ_g per gesture.
    stop_threshold : float
        Stop detector threshold [rad/s].
    stats : dict of str to int
        Counters of every stage.
    observations : list of (float, ndarray (M,))
        Candidates classified during the latest :meth:`push`: end time [s] and distance to every
        model (for traces and figures).

    Examples
    --------
    >>> rec = Recognizer.from_dataset("hpm", model_context="original_1")  # doctest: +SKIP
    >>> rec.warmup()                                                        # doctest: +SKIP
    >>> for t, p, q in source:                                              # doctest: +SKIP
    ...     for event in rec.push(t, p, q):
    ...         print(event.label, event.time)
    """

    method = "segments"

    def __init__(
        self,
        classifier: SegmentClassifier,
        labels: Sequence[str],
        config: RecognizerConfig,
        learned: LearnedSettings,
        calibration: SegmentThresholds | None = None,
    ) -> None:
        c, s, k = config, learned, config.constants
        missing = [n for n in ("rest_speed", "move_speed", "max_units", "max_duration", "max_pause",
                               "pause_ratio", "gesture_thresholds", "stop_threshold")
                   if getattr(s, n) is None]
        if missing:
            raise ValueError(f"unlearned values {missing}: use Recognizer.from_trajectories")
        self.classifier = classifier
        self.labels = [str(x) for x in labels]
        self.gestures = list(dict.fromkeys(self.labels))
        absent = set(self.gestures) - set(s.gesture_thresholds)
        if absent:
            raise ValueError(f"gesture_thresholds lacks {sorted(absent)}")
        self.config = c
        self.learned_ = s
        self.calibration = calibration
        self.gesture_thresholds = {g: float(s.gesture_thresholds[g]) for g in self.gestures}
        self.model_thresholds = np.array([self.gesture_thresholds[g] for g in self.labels])
        self.stop_threshold = float(s.stop_threshold)
        #: the orientation is too noisy to use: every sample's quaternion taken as the identity
        self.positions_only = bool(s.positions_only)
        speed, turn = s.gate_speeds or HAND_HELD_SPEEDS
        self.gate = SampleGate(max_bridge=c.max_bridge, nominal_period=k.dt, max_speed=speed,
                               max_angular_speed=turn)
        self.stop = StopDetector(self.stop_threshold, k.stop_window, k.stop_min_duration,
                                 k.stop_rearm, k.stop_refractory, k.stop_confirm,
                                 k.stop_sustain_ratio, k.stop_instant)
        self.resampler = UniformResampler(k.dt)
        self.smoother = GridSmoother(s.smoothing, k.dt) if s.smoothing else None
        #: How late [s] the smoothed grid poses reach the spotter: an event fires that much after
        #: the time of the pose it is decided on.
        self.smoothing_delay = 0.0 if self.smoother is None else self.smoother.delay
        capacity = math.ceil((s.max_duration + c.max_wait + 2.0) / k.dt) + 2 * k.margin
        self.segmenter = MotionSegmenter(SpeedLevels(s.rest_speed, s.move_speed), c.descriptor.L,
                                         k.dt, k.speed_lag, k.valley_ratio, capacity,
                                         settle=k.settle)
        self.spotter = make_spotter(classifier, self.model_thresholds, c, s, self.labels)
        self._counts = dict.fromkeys(STAT_KEYS, 0)
        self.classifier.cells = [0, 0]  # the calibration's searches are not the stream's
        self.observations: list[tuple[float, np.ndarray]] = []
        self._worker: SerialWorker | None = None
        self._recent_units: deque[Unit] = deque(maxlen=max(1, s.max_units))

    # ------------------------------------------------------------------------------ construction
    @classmethod
    def from_trajectories(
        cls,
        trajectories: Sequence[Trajectory],
        labels: Sequence[str],
        config: RecognizerConfig | None = None,
        learned: LearnedSettings | None = None,
        **overrides: Any,
    ) -> Recognizer:
        """Build the models from the takes and learn from them every value not given.

        Parameters
        ----------
        trajectories : sequence of Trajectory
            Model recordings (takes), one gesture performance each (with a little rest before
            and after).
        labels : sequence of str
            Gesture of each recording.
        config : RecognizerConfig, optional
            The user's settings (default ``RecognizerConfig()``).
        learned : LearnedSettings, optional
            Learned values to keep instead of deriving them (a library's); a value left None is
            derived.
        **overrides
            Changes by name: a user setting, a descriptor setting or constant
            (:meth:`RecognizerConfig.replace`), or a learned value to fix (``max_units=3``).
        """
        if len(trajectories) != len(labels):
            raise ValueError(f"{len(trajectories)} trajectories but {len(labels)} labels")
        if not trajectories:
            raise ValueError("no model recordings")
        config, given = split_settings(overrides, config)
        draft = LearnedDraft({**(learned.values() if learned is not None else {}), **given})
        if learned is not None:  # what a library learned keeps its rules
            draft.rules.update({n: r for n, r in learned.provenance.rules.items()
                                if n not in given and n in draft.rules})
        # the takes as the live recognizer will see the stream (after the library's rules: the
        # user's smoothing replaces a library's value and its rule)
        trajectories = resolve_orientation(trajectories, config, draft, learned is not None)
        if draft.missing("gate_speeds"):  # from the takes as the gate will see the stream
            draft.fill(f"{rule_name(gate_limits)} (the speed from the takes, the angular speed "
                       "a hand-held tracker's)", gate_speeds=gate_limits(trajectories, turns=False))
        trajectories = resolve_smoothing(trajectories, config, draft, learned is not None)
        if learned is not None and config.hand_frame:  # calibrated with the factor of before
            draft.fill("a library saved before framefree learned whether the sensor's frame is "
                       "fixed: the cones' factor it was calibrated with", fixed_frame=False)
        if config.descriptor.relative_window and draft.missing("window_spacing"):
            draft.fill(model_window_spacing,
                       window_spacing=model_window_spacing(trajectories, config))
        descriptor = segment_descriptor(config, draft.values["window_spacing"])
        classifier = SegmentClassifier(descriptor, [descriptor.compute(tr) for tr in trajectories])
        resolved, calibration = resolve_learned(trajectories, labels, config, classifier, draft)
        if learned is not None:
            resolved = resolved.replace(provenance=restored_provenance(resolved, learned))
        return cls(classifier, labels, config, resolved, calibration)

    @classmethod
    def restore(
        cls,
        takes: Sequence[Trajectory],
        labels: Sequence[str],
        config: RecognizerConfig,
        learned: LearnedSettings,
    ) -> Recognizer:
        """A recognizer over models rebuilt from ``takes`` with the learned values restored (no
        calibration; a value the library lacks is learned from the takes).

        This is the only place that knows how a recognizer is restored from a gesture library.
        """
        return cls.from_trajectories(list(takes), list(labels), config, learned)

    @classmethod
    def load(cls, path: str | Path) -> Recognizer:
        """A recognizer from a gesture library file written by ``framefree enroll``
        (:mod:`framefree.library`): models rebuilt from the stored takes, learned values
        restored, no calibration. A library of the previous format is migrated
        (:func:`~framefree.online.library_settings.settings_from_meta`).

        Raises
        ------
        LibraryError
            When the file is not a library, was written in a format that cannot be migrated, or
            its settings do not fit this framefree (one line, saying how to rebuild it).
        """
        path = Path(path)
        meta, rows = read_library_file(path)
        if meta.get("trackers"):
            raise LibraryError(f"{path}: a gesture library of several trackers; load it with "
                               "framefree.library.multi_library.load_multi_library(path)"
                               ".recognizer()")
        config, learned = settings_from_meta(path, meta, rows)
        takes = library_takes(path, rows, meta["names"])
        return cls.restore(takes, meta["labels"], config, learned)

    # ---------------------------------------------------------------------------------- running
    @property
    def stats(self) -> dict[str, int]:
        """Counters of the acceptance stage and of the recognizer's own stages, and the DTW cells
        the candidates' classification computed (``dtw_cells``) against what an unpruned search
        would have computed (``dtw_cells_unpruned``)."""
        cells, full = self.classifier.cells
        return {**self.gate.stats, **self._counts, "dtw_cells": cells, "dtw_cells_unpruned": full}

    @property
    def prune(self) -> bool:
        """Whether candidates are classified with exact pruning (:mod:`framefree.core.pruning`):
        the same decisions, fewer DTW computations. Off, every model's distance is computed (the
        per-gesture dissimilarities of :meth:`gesture_dissimilarities` and of traces are then
        exact for every gesture, not only the nearest)."""
        return self.classifier.prune

    @prune.setter
    def prune(self, value: bool) -> None:
        self.classifier.prune = bool(value)

    @property
    def background(self) -> bool:
        """Whether candidates are classified on a worker thread (:mod:`~framefree.online.
        background`), off the pose path: :meth:`push` then returns within a fraction of a
        millisecond whatever the vocabulary, and a gesture event comes out of a later
        :meth:`push` (or :meth:`finish`) as soon as the worker has decided it, stamped with the
        time of the pose that fired it as inline. The events are those of the inline recognizer,
        and they leave :meth:`push` in time order: a stop waits behind the decisions about
        earlier poses (:meth:`_stop_event`).
        Off by default; :meth:`close` (or setting it off) stops the thread."""
        return self._worker is not None

    @background.setter
    def background(self, value: bool) -> None:
        if bool(value) == self.background:
            return
        if value:
            self._worker = SerialWorker()
        else:
            self._collect(self._worker.wait())
            self._worker.close()
            self._worker = None

    def finish(self) -> list[Event]:
        """Wait for the worker to decide everything pushed so far; return the events it still
        held (inline, or when it has caught up: none). Call it at the end of a recording."""
        if self._worker is None:
            return []
        return self._collect(self._worker.wait())

    def close(self) -> None:
        """Stop the worker thread, if any (the recognizer then runs inline)."""
        self.background = False

    def __getstate__(self) -> dict[str, Any]:
        state = dict(self.__dict__)
        state["_worker"] = None  # a copy runs inline
        return state

    def reset(self) -> None:
        """Forget the stream and the counters (a new session)."""
        if self._worker is not None:
            self._worker.wait()
        self.gate.reset()
        self.stop.rearm_now()
        self._restart()
        self._counts = dict.fromkeys(STAT_KEYS, 0)
        self.classifier.cells = [0, 0]

    def _restart(self) -> None:
        self.resampler.reset()
        if self.smoother is not None:
            self.smoother.reset()
        self.segmenter.reset()
        self._recent_units.clear()
        self._decide_later(self.spotter.reset)
        self.stop.reset()

    def warmup(self) -> None:
        """Run every stage once on a synthetic motion (loads the compiled kernels), then reset."""
        t = np.arange(0.0, 6.0, self.config.constants.dt)
        x = np.clip((t - 1.0) / 1.5, 0.0, 1.0)
        s = np.sin(np.pi * x**3 * (10 - 15 * x + 6 * x**2))
        for k in range(t.size):
            p = np.array([0.3 * s[k], 0.05 * s[k] ** 2, 0.0])
            q = np.array([math.cos(0.4 * s[k]), 0.0, 0.0, math.sin(0.4 * s[k])])
            self.push(float(t[k]), p, q)
        self.finish()
        self.reset()

    def push(self, t: float, p: Sequence[float] | np.ndarray, q: Sequence[float] | np.ndarray
             ) -> list[Event]:
        """Offer one pose sample; return the events it triggers (usually none).

        Parameters
        ----------
        t : float
            Time stamp [s] (the stream's clock).
        p : array_like, shape (3,)
            Position [m].
        q : array_like, shape (4,)
            Orientation quaternion ``(w, x, y, z)`` (any norm and sign).

        Returns
        -------
        list of Event
            Stop events and gesture events, in time order.
        """
        self.observations = []
        accepted = self.gate.push(t, p, IDENTITY if self.positions_only else q)
        if accepted.restarted:
            self._counts["restarts"] += 1
            self._restart()
            if accepted.relocated:
                self.stop.settle(t)
        events: list[Event] = []
        for ts, ps, qs in accepted.samples:
            events.extend(self._on_sample(ts, ps, qs))
        if self._worker is not None:
            events.extend(self._collect(self._worker.done()))
        events.sort(key=lambda e: (e.time, not e.is_stop))
        return events

    def _on_sample(self, t: float, p: np.ndarray, q: np.ndarray) -> list[Event]:
        events: list[Event] = []
        stopped = self.stop.update(t, q)
        if stopped:
            self._counts["stops"] += 1
            self._decide_later(self.spotter.discard_before, self.segmenter.buffer.count)
        T = np.eye(4)
        T[:3, :3] = se3.matrix_from_quaternion(q)
        T[:3, 3] = p
        times, poses = self.resampler.push(t, T)
        if self.smoother is not None:
            times, poses = self.smoother.push(times, poses)
        for k in range(times.size):
            event = self._on_grid(float(times[k]), poses[k])
            if event is not None:
                events.append(event)
        if stopped:  # in line behind every decision about earlier poses (see _stop_event)
            event = self._decide_later(self._stop_event, t)
            if event is not None:
                events.append(event)
        return events

    @staticmethod
    def _stop_event(t: float) -> Event:
        """The stop signal of the pose at ``t`` [s].

        With a worker it is queued like a spotter step, after the steps of every pose up to and
        including this one, so it leaves :meth:`push` only after every gesture those poses fire:
        the events come out in time order whatever the worker's lag (a stop never overtakes an
        earlier gesture; the price is that a stop waits for the classifications already queued,
        milliseconds in real time, see ``docs/online.md``)."""
        return Event(STOP, t, -1.0, -1)

    def _on_grid(self, t: float, T: np.ndarray) -> Event | None:
        self._counts["grid"] += 1
        unit = self.segmenter.push(t, T)
        buffer = self.segmenter.buffer
        if not self.stop.armed:  # a stop fired and the hand still turns fast: it is not a gesture
            return self._decide_later(self.spotter.discard_before, buffer.count)
        if unit is not None:
            self._counts["units"] += 1
            self._recent_units.append(unit)
            if self._worker is not None:  # the worker reads candidates from a copy
                buffer = buffer.snapshot(self._recent_units[0].start - self.spotter.margin)
        return self._decide_later(self._spot, t, self.segmenter.resting, unit, buffer)

    def _spot(self, t: float, resting: bool, unit: Unit | None, buffer: PoseBuffer) -> Event | None:
        """The spotter's step for one uniform pose (:meth:`Spotter.step`), as an event."""
        n_before = len(self.spotter.evaluated)
        fired = self.spotter.step(t, resting, unit, buffer)
        self._counts["candidates"] += len(self.spotter.evaluated) - n_before
        if fired is None:
            return None
        self._counts["events"] += 1
        # a smoothed pose is decided on once the poses after it have come: that is when it fires
        return Event(self.labels[fired.model], t + self.smoothing_delay, fired.distance,
                     fired.model)

    def _decide_later(self, fn: Callable[..., Event | None], *args: Any) -> Event | None:
        """Run a spotter step now (inline: its event, if any) or queue it on the worker (None;
        its event comes out of :meth:`_collect` later). Steps run in the order they are made."""
        if self._worker is not None:
            self._worker.submit(self._observed, fn, *args)
            return None
        event, observed = self._observed(fn, *args)
        self.observations.extend(observed)
        return event

    def _observed(self, fn: Callable[..., Event | None], *args: Any
                  ) -> tuple[Event | None, list[tuple[float, np.ndarray]]]:
        self.spotter.evaluated.clear()
        return fn(*args), list(self.spotter.evaluated)

    def _collect(self, results: list[tuple[Event | None, list]]) -> list[Event]:
        events = []
        for event, observed in results:
            self.observations.extend(observed)
            if event is not None:
                events.append(event)
        return events

    def gesture_dissimilarities(self) -> dict[str, float]:
        """Distance of the latest classified candidate to each gesture's nearest model (with
        :attr:`prune`, exact for an accepted candidate's nearest gesture; other values, and a
        refused candidate's, may be lower bounds)."""
        out = dict.fromkeys(self.gestures, math.inf)
        d = self.spotter.last_distances
        if d is not None:
            for j, g in enumerate(self.labels):
                out[g] = min(out[g], float(d[j]))
        return out

    def describe(self) -> dict[str, Any]:
        """Everything the recognizer runs with, as a JSON-friendly dict: ``config``, the user's
        settings (with the descriptor settings and constants nested), ``learned``, every value
        learned from the takes with its provenance, the models and the calibration."""
        return {
            "method": self.method,
            "config": self.config.to_dict(),
            "learned": self.learned_.to_dict(),
            "gesture_thresholds": dict(self.gesture_thresholds),
            "stop_threshold": self.stop_threshold,
            "n_models": len(self.labels),
            "gestures": self.gestures,
            "model_lengths": [int(m.shape[0]) for m in self.classifier.models],
            "calibration": None if self.calibration is None else self.calibration.summary(),
        }
