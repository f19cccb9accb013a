"""Live recognition of gestures made with several trackers at once (a controller in each hand).

:class:`MultiRecognizer` is :class:`~framefree.online.recognizer.Recognizer` for poses of
several trackers: ``push(t, P, Q)`` with one row per tracker. Per tracker, the samples pass the
acceptance gate, the stop detector and the uniform 50 Hz grid (smoothed, every tracker alike,
when the takes are noisy or the user sets ``smoothing``); the grids are joined
(:class:`~framefree.online.multi_stream.GridJoiner`) and cut into movement units on the
trackers' combined motion speed; every candidate that ends with a unit is classified by the
offline :class:`~framefree.classifier.NearestNeighborClassifier` fitted on the model recordings
(:mod:`~framefree.online.multi_spotting`), so a candidate gets the label the offline classifier
gives the same motion. Events, their order, the stop signal (either hand), background
classification and the statistics are the single-tracker recognizer's.

What comes from the models (:func:`resolve_multi_learned`): the smoothing (from the position
noise of every tracker's takes together, :func:`smoothed_samples`), the rest and move levels of the
combined speed, the candidate limits (units, duration, pauses), each gesture's size range, the
thresholds τ_g (the offline rule :func:`~framefree.rejection.thresholds_from_models`, P + N, with
P also measured on the models as the live spotter cuts them, :func:`multi_thresholds`), the
acceptance gates' speed limits (:func:`~framefree.online.acceptance.gate_limits`), the stop
threshold (the fastest rotation of any tracker of any model), and how long a pending gesture
waits for a longer one that begins the same way (:func:`~framefree.online.continuations.
continuation_waits`, measured by running the recognizer over the takes).
See ``docs/online.md`` (Several trackers).
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core import se3
from ..core.multitrajectory import MultiTrajectory
from ..rejection import thresholds_from_models
from .acceptance import HAND_HELD_SPEEDS, SampleGate, gate_limits
from .config import RecognizerConfig
from .continuations import continuation_waits
from .events import Event
from .learned import (
    GIVEN,
    LearnedSettings,
    restored_provenance,
    rule_name,
    split_settings,
    takes_digest,
)
from .model_settings import LearnedDraft, resolve_smoothing, stop_threshold_rule
from .multi_spotting import MultiSegmentClassifier, MultiSpotter, path_size
from .multi_stream import (
    GridJoiner,
    MultiMotionSegmenter,
    StopGroup,
    live_cut,
    multi_candidate_limits,
    multi_speed_levels,
)
from .recognizer import STAT_KEYS, Recognizer
from .segmentation import SpeedLevels, UniformResampler, Unit
from .smoothing import GridSmoother
from .stop import StopDetector, sustained_peak_speed

__all__ = ["MultiRecognizer", "multi_thresholds", "resolve_multi_learned", "smoothed_samples"]


def _classifier(invariance: str) -> Any:
    from ..classifier import NearestNeighborClassifier

    return NearestNeighborClassifier(invariance=invariance)


def resolve_multi_learned(samples: Sequence[MultiTrajectory], labels: Sequence[str],
                          config: RecognizerConfig, classifier: Any,
                          draft: LearnedDraft | None = None) -> LearnedSettings:
    """Learn every value a :class:`MultiRecognizer` uses that ``draft`` does not hold yet.

    Parameters
    ----------
    samples : sequence of MultiTrajectory
        The model recordings (the same trackers in the same order).
    labels : sequence of str
    config : RecognizerConfig
    classifier : NearestNeighborClassifier
        Fitted on ``samples`` (its model-to-model distances give the thresholds).
    draft : LearnedDraft, optional
        Values given instead of learned.
    """
    draft = draft or LearnedDraft()
    k, L, v = config.constants, config.descriptor.L, draft.values
    gestures = list(dict.fromkeys(labels))
    if draft.missing("rest_speed", "move_speed"):
        lv = multi_speed_levels(samples, L, k.dt, k.speed_lag, k.noise_factor, k.peak_fraction,
                                k.move_factor, k.rest_before)
        draft.fill(multi_speed_levels, rest_speed=lv.rest, move_speed=lv.move)
    levels = SpeedLevels(v["rest_speed"], v["move_speed"])
    if draft.missing("max_units", "max_duration", "max_pause", "pause_ratio"):
        units, duration, pause, ratio = multi_candidate_limits(
            samples, levels, L, k.span_factor, k.pause_factor, k.dt, labels, k.min_pause)
        draft.fill(multi_candidate_limits, max_units=units, max_duration=duration,
                   max_pause=pause, pause_ratio=ratio)
    if draft.missing("size_limits"):
        sizes: dict[str, list[float]] = {g: [] for g in gestures}
        for smp, g in zip(samples, labels, strict=True):
            sizes[g].append(path_size(smp))
        draft.fill(rule_name(path_size) + " / size_factor and × size_growth",
                   size_limits={g: (min(x) / k.size_factor, max(x) * k.size_growth)
                                for g, x in sizes.items()})
    if config.gesture_thresholds is not None:
        draft.fill(f"{GIVEN}: gesture_thresholds", gesture_thresholds=config.gesture_thresholds)
    if config.threshold is not None:
        draft.fill(f"{GIVEN}: threshold", gesture_thresholds=dict.fromkeys(gestures, config.threshold))
    if draft.missing("gesture_thresholds"):
        draft.fill(multi_thresholds,
                   gesture_thresholds=multi_thresholds(samples, labels, classifier, levels, config))
    if config.stop_threshold is not None:
        draft.fill(f"{GIVEN}: stop_threshold", stop_threshold=config.stop_threshold)
    if draft.missing("stop_threshold"):
        peak = max(sustained_peak_speed(tr.t, tr.q, k.stop_window, k.stop_min_duration)
                   for smp in samples for tr in smp.trackers)
        draft.fill(stop_threshold_rule(), stop_threshold=max(k.stop_floor, k.stop_margin * peak))
    digest = takes_digest(tr.to_array() for smp in samples for tr in smp.trackers)
    return draft.settings(len(samples), digest)


def multi_thresholds(samples: Sequence[MultiTrajectory], labels: Sequence[str], classifier: Any,
                     levels: SpeedLevels, c: RecognizerConfig) -> dict[str, float]:
    """τ_g = P_g + N_g per gesture: the offline rule (:func:`~framefree.rejection.
    thresholds_from_models`) with ``P_g`` the larger of the models' own leave-one-out distance
    and that of the models as the live spotter cuts them (:func:`~framefree.online.multi_stream.
    live_cut`: without what the recordings hold before the first and after the last stroke),
    each to its nearest other model of the gesture."""
    labels_ = np.asarray(labels)
    D = classifier.distance_matrix(list(samples))
    tau = thresholds_from_models(D, list(labels))
    k = c.constants
    cuts = [live_cut(s, levels, c.descriptor.L, k.dt, k.speed_lag, k.valley_ratio, k.margin)
            for s in samples]
    keep = [k for k, s in enumerate(cuts) if s is not None]
    Dc = np.full((len(samples), len(samples)), np.inf)
    Dc[keep] = classifier.distance_matrix([cuts[k] for k in keep])
    np.fill_diagonal(Dc, np.inf)
    np.fill_diagonal(D, np.inf)
    for g in tau:
        own = labels_ == g
        if own.sum() < 2:
            continue
        p_off = float(D[np.ix_(own, own)].min(axis=1).max())
        live = Dc[np.ix_(own, own)].min(axis=1)
        live = live[np.isfinite(live)]
        if live.size:
            tau[g] += max(0.0, float(live.max()) - p_off)
    return tau


def smoothed_samples(samples: Sequence[MultiTrajectory], config: RecognizerConfig,
                     draft: LearnedDraft, restoring: bool = False) -> list[MultiTrajectory]:
    """Fill ``draft``'s ``smoothing`` from the takes of every tracker together
    (:func:`~framefree.online.model_settings.resolve_smoothing`) and return the samples as the
    recognizer will see the stream: each tracker smoothed alike on the uniform grid."""
    flat = [tr for smp in samples for tr in smp.trackers]
    smoothed = resolve_smoothing(flat, config, draft, restoring)
    if not draft.values["smoothing"]:
        return list(samples)
    out, k = [], 0
    for smp in samples:
        n = smp.n_trackers
        out.append(MultiTrajectory(tuple(smoothed[k:k + n]), smp.names, smp.up, smp.source))
        k += n
    return out


class MultiRecognizer(Recognizer):
    """Streaming recognizer of gestures made with several trackers together.

    Build it with :meth:`from_samples`. ``push(t, P, Q)`` takes one pose of every tracker.

    Parameters
    ----------
    classifier : MultiSegmentClassifier
        The fitted offline classifier, wrapped.
    labels : sequence of str, length M
    config : RecognizerConfig
        The user's settings.
    learned : LearnedSettings
        What was learned from the models (:func:`resolve_multi_learned`).
    invariance : str
        The classifier's invariance (reported by :meth:`describe`).

    Notes
    -----
    The acceptance gates' speed limits are ``learned.gate_speeds``
    (:func:`~framefree.online.acceptance.gate_limits`; None: a hand-held tracker's).
    """

    def __init__(self, classifier: MultiSegmentClassifier, labels: Sequence[str],
                 config: RecognizerConfig, learned: LearnedSettings, invariance: str = "gravity"
                 ) -> None:
        c, s, k = config, learned, config.constants
        self.smoother = None  # one smoother per tracker instead
        n = len(classifier.names)
        self.smoothers = [GridSmoother(s.smoothing, k.dt) for _ in range(n)] if s.smoothing else []
        self.smoothing_delay = self.smoothers[0].delay if self.smoothers else 0.0
        self.classifier = classifier
        self.labels = [str(x) for x in labels]
        self.gestures = list(dict.fromkeys(self.labels))
        self.config = c
        self.learned_ = s
        self.calibration = None
        self.invariance = invariance
        self.tracker_names = classifier.names
        self.n_trackers = len(classifier.names)
        self.gesture_thresholds = {g: float(s.gesture_thresholds[g]) for g in self.gestures}
        self.model_thresholds = np.array([self.gesture_thresholds[g] for g in self.labels])
        self.stop_threshold = float(s.stop_threshold)
        n = self.n_trackers
        speed, turn = s.gate_speeds or HAND_HELD_SPEEDS
        self.gate_speeds = (float(speed), float(turn))
        self.gates = [SampleGate(max_bridge=c.max_bridge, nominal_period=k.dt,
                                 max_speed=self.gate_speeds[0],
                                 max_angular_speed=self.gate_speeds[1]) for _ in range(n)]
        self.stop = StopGroup([StopDetector(self.stop_threshold, k.stop_window, k.stop_min_duration,
                                            k.stop_rearm, k.stop_refractory, k.stop_confirm,
                                            k.stop_sustain_ratio, k.stop_instant)
                               for _ in range(n)])
        self.resamplers = [UniformResampler(k.dt) for _ in range(n)]
        self.joiner = GridJoiner(n, k.dt)
        longest_wait = max([c.max_wait, *(s.continuations or {}).values()])
        capacity = math.ceil((s.max_duration + longest_wait + 2.0) / k.dt) + 2 * k.margin
        self.segmenter = MultiMotionSegmenter(SpeedLevels(s.rest_speed, s.move_speed),
                                              c.descriptor.L, k.dt, k.speed_lag, k.valley_ratio,
                                              capacity, n)
        sizes = np.array([s.size_limits.get(g, (0.0, np.inf)) for g in self.labels]) if c.size else None
        waits = (None if s.continuations is None
                 else np.array([s.continuations.get(g, 0.0) for g in self.labels]))
        self.spotter = MultiSpotter(
            classifier, self.model_thresholds, sizes, waits, max_units=s.max_units,
            max_duration=s.max_duration, max_pause=s.max_pause, margin=k.margin,
            confirm=c.confirm, max_wait=c.max_wait, L=c.descriptor.L, pause_ratio=s.pause_ratio,
            min_pause=k.min_pause, fire_on_motion=k.fire_on_motion, rest_before=k.rest_before,
            model_gestures=self.labels)
        self._counts = dict.fromkeys(STAT_KEYS, 0)
        self.observations: list[tuple[float, np.ndarray]] = []
        self._worker = None
        self._recent_units: deque[Unit] = deque(maxlen=max(1, s.max_units))

    @classmethod
    def from_samples(cls, samples: Sequence[MultiTrajectory], labels: Sequence[str],
                     config: RecognizerConfig | None = None, invariance: str = "gravity",
                     learned: LearnedSettings | None = None, **overrides: Any) -> MultiRecognizer:
        """Fit the offline classifier on the model recordings and learn from them every value
        not given (:func:`resolve_multi_learned`).

        Parameters
        ----------
        samples : sequence of MultiTrajectory
            Model recordings, one gesture performance each, all with the same trackers.
        labels : sequence of str
        config : RecognizerConfig, optional
            Keyword ``overrides`` change its settings by name, or fix a learned value.
        invariance : {"gravity", "full"}
            Of the offline classifier (:class:`~framefree.classifier.NearestNeighborClassifier`).
            ``"gravity"`` (the default here, unlike offline): keeps the world's vertical (+z in
            framefree's frame, which multi-tracker CSV and Machete files are read into). On the
            six Machete Vive people, each left out of the models in turn, live F1 0.985 against
            0.986 with ``"full"`` (v24, one gesture apart; docs/multi-trackers.md); offline, the
            four people kept apart lost less with it (issue 39). ``"full"`` for a world whose
            vertical is unknown.
        learned : LearnedSettings, optional
            Learned values to keep instead of deriving them (a library's); a value left None is
            derived.
        """
        if len(samples) != len(labels):
            raise ValueError(f"{len(samples)} samples but {len(labels)} labels")
        if not samples:
            raise ValueError("no model recordings")
        counts = {s.n_trackers for s in samples}
        if len(counts) != 1:
            raise ValueError(f"model recordings with different numbers of trackers: {sorted(counts)}")
        if overrides.get("hand_frame"):
            raise ValueError("hand_frame applies to one tracker: several trackers' directions in "
                             "their frames are not learned")
        config, given = split_settings(overrides, config)
        draft = LearnedDraft({**(learned.values() if learned is not None else {}), **given})
        if learned is not None:  # what a library learned keeps its rules
            draft.rules.update({n: r for n, r in learned.provenance.rules.items()
                                if n not in given and n in draft.rules})
        if draft.missing("gate_speeds"):  # every tracker's takes, both limits
            draft.fill(gate_limits, gate_speeds=gate_limits([tr for smp in samples
                                                             for tr in smp.trackers]))
        # the takes as the live recognizer will see the stream
        seen = smoothed_samples(samples, config, draft, learned is not None)
        clf = _classifier(invariance).fit(seen, list(labels))
        resolved = resolve_multi_learned(seen, labels, config, clf, draft)
        wrapped = MultiSegmentClassifier(clf, samples[0].names, samples[0].up)
        if resolved.continuations is None:  # learned by running the recognizer over the takes
            probe = cls(wrapped, labels, config, resolved, invariance)
            rules = {**resolved.provenance.rules, "continuations": rule_name(continuation_waits)}
            resolved = resolved.replace(
                continuations=continuation_waits(probe, samples, labels),
                provenance=dataclasses.replace(resolved.provenance, rules=rules))
        if learned is not None:
            resolved = resolved.replace(provenance=restored_provenance(resolved, learned))
        return cls(wrapped, labels, config, resolved, invariance)

    # ---------------------------------------------------------------------------------- running
    @property
    def stats(self) -> dict[str, int]:
        """Counters of every tracker's acceptance stage (summed) and of the recognizer's stages."""
        gate: dict[str, int] = {}
        for g in self.gates:
            for k, v in g.stats.items():
                gate[k] = gate.get(k, 0) + v
        return {**gate, **self._counts, "dtw_cells": 0, "dtw_cells_unpruned": 0}

    @property
    def prune(self) -> bool:
        """Always False: a candidate is compared with every model."""
        return False

    @prune.setter
    def prune(self, value: bool) -> None:
        pass

    def reset(self) -> None:
        """Forget the stream and the counters (a new session)."""
        if self._worker is not None:
            self._worker.wait()
        for g in self.gates:
            g.reset()
        self.stop.rearm_now()
        self._restart()
        self._counts = dict.fromkeys(STAT_KEYS, 0)

    def _restart(self) -> None:
        for r in [*self.resamplers, *self.smoothers]:
            r.reset()
        self.joiner.reset()
        self.segmenter.reset()
        self._recent_units.clear()
        self._decide_later(self.spotter.reset)
        self.stop.reset()

    def warmup(self) -> None:
        """Run every stage once on a synthetic two-handed motion, then reset."""
        t = np.arange(0.0, 6.0, self.config.constants.dt)
        x = np.clip((t - 1.0) / 1.5, 0.0, 1.0)
        s = np.sin(np.pi * x**3 * (10 - 15 * x + 6 * x**2))
        offsets = np.arange(self.n_trackers)[:, None] * np.array([0.0, 0.4, 0.0])
        for k in range(t.size):
            P = offsets + np.array([0.3 * s[k], 0.05 * s[k] ** 2, 0.1 * s[k]])
            Q = np.tile([math.cos(0.4 * s[k]), 0.0, 0.0, math.sin(0.4 * s[k])], (self.n_trackers, 1))
            self.push(float(t[k]), P, Q)
        self.finish()
        self.reset()

    def push(self, t: float, p: Any, q: Any) -> list[Event]:
        """Offer one pose of every tracker; return the events it triggers (usually none).

        Parameters
        ----------
        t : float
            Time stamp [s].
        p : array_like, shape (n_trackers, 3)
            Positions [m], in the models' tracker order.
        q : array_like, shape (n_trackers, 4)
            Orientations ``(w, x, y, z)`` (any norm and sign; a NaN row: that tracker lost
            tracking, its gate bridges or restarts).
        """
        self.observations = []
        P = np.asarray(p, dtype=np.float64).reshape(self.n_trackers, 3)
        Q = np.asarray(q, dtype=np.float64).reshape(self.n_trackers, 4)
        accepted = [g.push(t, P[j], Q[j]) for j, g in enumerate(self.gates)]
        if any(a.restarted for a in accepted):
            self._counts["restarts"] += 1
            self._restart()
        stops = []
        for j, acc in enumerate(accepted):
            for ts, ps, qs in acc.samples:
                if self.stop.update(j, ts, qs):
                    stops.append(ts)
                T = np.eye(4)
                T[:3, :3] = se3.matrix_from_quaternion(qs)
                T[:3, 3] = ps
                grid = self.resamplers[j].push(ts, T)
                self.joiner.add(j, *(self.smoothers[j].push(*grid) if self.smoothers else grid))
        for _ in stops:
            self._counts["stops"] += 1
            self._decide_later(self.spotter.discard_before, self.segmenter.buffer.count)
        events: list[Event] = []
        for tg, poses in self.joiner.ready():
            event = self._on_grid(tg, poses)
            if event is not None:
                events.append(event)
        for ts in stops:
            event = self._decide_later(self._stop_event, ts)
            if event is not None:
                events.append(event)
        if self._worker is not None:
            events.extend(self._collect(self._worker.done()))
        events.sort(key=lambda e: (e.time, not e.is_stop))
        return events

    def describe(self) -> dict[str, Any]:
        """Parameters (resolved), trackers and models as a JSON-friendly dict."""
        out = super().describe()
        out.update(trackers=list(self.tracker_names), invariance=self.invariance,
                   gate_speeds=list(self.gate_speeds),
                   model_lengths=[int(m.shape[0]) for m in self.classifier.models])
        return out
