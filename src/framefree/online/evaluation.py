"""Event-level evaluation of the recognizer on labelled streams.

Matching rule: an event matches a labelled segment when the labels agree and the event fires between
the segment's start and ``tolerance`` seconds after its end. The first matching event of a segment is
a true positive; every other event (a second detection, a wrong label, an event outside any
segment) is a false positive; a segment without a true positive is a miss (false negative).

Reported: precision, recall, F1, false positives per minute of non-gesture motion (stream time
outside the tolerance-extended segments), and the detection latency after the gesture's end
(event time − segment end; negative when the latency search fires before the end).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import Trajectory
from .events import Event

__all__ = [
    "StreamResult",
    "StreamTrace",
    "TracingRecognizer",
    "combine",
    "match_events",
    "per_gesture",
    "plot_timeline",
    "run_stream",
]


class SegmentLike(Protocol):
    """A labelled stretch: ``label``, ``start_t`` and ``end_t`` [s]."""

    label: str
    start_t: float
    end_t: float


@dataclass
class StreamTrace:
    """What the recognizer saw on a stream, for figures.

    Attributes
    ----------
    times : ndarray, shape (K,)
        Time [s] of each descriptor sample.
    dissimilarity : ndarray, shape (K, G)
        Best matcher output per gesture at each descriptor sample (``inf`` while not ready).
    gestures : list of str, length G
    thresholds : dict of str to float
        τ_g of each gesture (the recognizer's ``gesture_thresholds``; empty if unknown).
    """

    times: np.ndarray
    dissimilarity: np.ndarray
    gestures: list[str]
    thresholds: dict[str, float] = field(default_factory=dict)


@dataclass
class StreamResult:
    """Matching of the events of one (or several pooled) streams with the labels.

    Attributes
    ----------
    tp, fp, fn : int
    latencies : list of float
        Event time − segment end [s] of each true positive.
    nongesture_minutes : float
        Stream time outside the tolerance-extended segments [min].
    details : list of dict
        Per event: time, label, dissimilarity, model, matched segment index or None, verdict.
    """

    tp: int = 0
    fp: int = 0
    fn: int = 0
    latencies: list[float] = field(default_factory=list)
    nongesture_minutes: float = 0.0
    details: list[dict[str, Any]] = field(default_factory=list)
    missed: list[dict[str, Any]] = field(default_factory=list)

    @property
    def precision(self) -> float:
        """TP / (TP + FP) (1 when there is no event)."""
        return self.tp / (self.tp + self.fp) if self.tp + self.fp else 1.0

    @property
    def recall(self) -> float:
        """TP / (TP + FN) (1 when there is no segment)."""
        return self.tp / (self.tp + self.fn) if self.tp + self.fn else 1.0

    @property
    def f1(self) -> float:
        """Harmonic mean of precision and recall."""
        p, r = self.precision, self.recall
        return 2 * p * r / (p + r) if p + r else 0.0

    @property
    def fp_per_minute(self) -> float:
        """False positives per minute of non-gesture motion."""
        return self.fp / self.nongesture_minutes if self.nongesture_minutes > 0 else float(self.fp > 0)

    def summary(self) -> dict[str, Any]:
        """Metrics as a JSON-friendly dict."""
        lat = np.array(self.latencies)
        return {
            "tp": self.tp, "fp": self.fp, "fn": self.fn,
            "precision": self.precision, "recall": self.recall, "f1": self.f1,
            "fp_per_minute": self.fp_per_minute,
            "nongesture_minutes": self.nongesture_minutes,
            "latency_mean_s": float(lat.mean()) if lat.size else None,
            "latency_median_s": float(np.median(lat)) if lat.size else None,
            "latency_max_s": float(lat.max()) if lat.size else None,
        }


def match_events(
    events: Sequence[Event],
    segments: Sequence[SegmentLike],
    duration: float,
    tolerance: float = 0.5,
) -> StreamResult:
    """Match events to labelled segments (see the module docstring).

    Parameters
    ----------
    events : sequence of Event
    segments : sequence of segments (``label``, ``start_t``, ``end_t``)
    duration : float
        Stream duration [s] (for the false positives per minute).
    tolerance : float
        Seconds after a segment's end during which its detection still counts.
    """
    res = StreamResult()
    detected = [False] * len(segments)
    for ev in sorted(events, key=lambda e: e.time):
        match = None
        for k, seg in enumerate(segments):
            if seg.label == ev.label and seg.start_t <= ev.time <= seg.end_t + tolerance:
                match = k
                break
        verdict = "fp"
        if match is not None and not detected[match]:
            detected[match] = True
            res.tp += 1
            res.latencies.append(ev.time - segments[match].end_t)
            verdict = "tp"
        else:
            res.fp += 1
            if match is not None:
                verdict = "fp-repeat"
        res.details.append({"time": ev.time, "label": ev.label, "dissimilarity": ev.dissimilarity,
                            "model": ev.model, "segment": match, "verdict": verdict,
                            "latency": res.latencies[-1] if verdict == "tp" else None})
    for k, seg in enumerate(segments):
        if not detected[k]:
            res.fn += 1
            res.missed.append({"segment": k, "label": seg.label, "start_t": seg.start_t,
                               "end_t": seg.end_t})
    busy = 0.0
    spans = sorted((s.start_t, min(s.end_t + tolerance, duration)) for s in segments)
    cur_a, cur_b = None, None
    for a, b in spans:
        if cur_b is None or a > cur_b:
            if cur_b is not None:
                busy += cur_b - cur_a
            cur_a, cur_b = a, b
        else:
            cur_b = max(cur_b, b)
    if cur_b is not None:
        busy += cur_b - cur_a
    res.nongesture_minutes = max(duration - busy, 0.0) / 60.0
    return res


def combine(results: Sequence[StreamResult]) -> StreamResult:
    """Pool the counts of several streams."""
    out = StreamResult()
    for r in results:
        out.tp += r.tp
        out.fp += r.fp
        out.fn += r.fn
        out.latencies += r.latencies
        out.nongesture_minutes += r.nongesture_minutes
    return out


def per_gesture(results: Sequence[StreamResult]) -> dict[str, dict[str, Any]]:
    """Counts, F1 and latencies per gesture over several streams: a true positive and a miss
    count for the labelled gesture, a false positive for the event's label.

    Returns
    -------
    dict of str to dict
        Per gesture (sorted): ``tp``, ``fp``, ``fn``, ``precision``, ``recall``, ``f1``,
        ``latency_median_s`` (``None`` without a true positive).
    """
    rows: dict[str, StreamResult] = {}
    for res in results:
        for d in res.details:
            row = rows.setdefault(d["label"], StreamResult())
            if d["verdict"] == "tp":
                row.tp += 1
                row.latencies.append(d["latency"])
            else:
                row.fp += 1
        for m in res.missed:
            rows.setdefault(m["label"], StreamResult()).fn += 1
    out = {}
    for g in sorted(rows):
        r = rows[g]
        out[g] = {"tp": r.tp, "fp": r.fp, "fn": r.fn, "precision": r.precision,
                  "recall": r.recall, "f1": r.f1,
                  "latency_median_s": float(np.median(r.latencies)) if r.latencies else None}
    return out


class TracingRecognizer:
    """Wraps a recognizer: pushes samples, collects the events and the per-gesture dissimilarity
    trace (the nearest model of each gesture at every observation the recognizer reports in its
    ``observations``: each classified candidate, or each matched descriptor sample) for figures.

    Parameters
    ----------
    recognizer : Recognizer
        Reset on construction; its pruning is turned off, so that the trace holds every
        gesture's exact distance (the events are the same either way).
    """

    def __init__(self, recognizer: Any) -> None:
        recognizer.reset()
        if hasattr(recognizer, "prune"):
            recognizer.prune = False
        self.recognizer = recognizer
        self.gestures = list(recognizer.gestures)
        self._gidx = np.array([self.gestures.index(s) for s in recognizer.labels])
        self.events: list[Event] = []
        self._times: list[float] = []
        self._rows: list[np.ndarray] = []

    def push(self, t: float, p: np.ndarray, q: np.ndarray) -> list[Event]:
        """Push one pose sample (see ``Recognizer.push``); returns its events."""
        rec = self.recognizer
        events = rec.push(t, p, q)
        self.events.extend(events)
        for when, distances in rec.observations:
            row = np.full(len(self.gestures), np.inf)
            np.minimum.at(row, self._gidx, distances)
            self._times.append(float(when))
            self._rows.append(row)
        return events

    def trace(self) -> StreamTrace:
        """The dissimilarity trace so far."""
        diss = np.array(self._rows).reshape(-1, len(self.gestures))
        thresholds = {
            g: float(v) for g, v in getattr(self.recognizer, "gesture_thresholds", {}).items()
        }
        return StreamTrace(np.array(self._times), diss, self.gestures, thresholds)


def stream_rows(traj: Trajectory | MultiTrajectory) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(t, P, Q)`` of a stream as ``push`` takes it, shapes (N,), (N, 3) and (N, 4) for a
    :class:`~framefree.core.trajectory.Trajectory`; (N,), (N, n, 3) and (N, n, 4) for a
    :class:`~framefree.core.multitrajectory.MultiTrajectory` of n trackers."""
    trackers = getattr(traj, "trackers", None)
    if trackers is None:
        return traj.t, traj.p, traj.q
    return (traj.t, np.stack([tr.p for tr in trackers], axis=1),
            np.stack([tr.q for tr in trackers], axis=1))


def run_stream(recognizer: Any, traj: Trajectory | MultiTrajectory, view: Any = None,
               end_rest: float | None = None) -> tuple[list[Event], StreamTrace]:
    """Reset the recognizer, push a whole stream (a MultiTrajectory for a recognizer of several
    trackers), return its events and a dissimilarity trace (``view``: anything with
    ``update(t, p, q, events)``, e.g. the rerun view, fed every pose).

    The recording's end is taken as the end of the motion: the last pose is pushed again, held
    still, for ``end_rest`` seconds at the stream's sampling interval (None: the recognizer's
    ``max_wait``, the longest a pending gesture waits for a rest; 0: not held), so that a
    gesture the recording ends with is decided as the hand coming to rest would decide it.
    A recording cut right after its last gesture (SFINGE3D's end within 0.2 s of it) otherwise
    leaves that gesture pending forever. The recognizer's pruning is off during the run (the
    trace holds exact distances; the events are the same) and as it was afterwards.
    """
    pruned = getattr(recognizer, "prune", None)
    tracer = TracingRecognizer(recognizer)
    T, P, Q = stream_rows(traj)
    try:
        for k in range(len(traj)):
            events = tracer.push(T[k], P[k], Q[k])
            if view is not None:
                view.update(T[k], P[k], Q[k], events)
        if end_rest is None:
            end_rest = float(getattr(getattr(recognizer, "config", None), "max_wait", 1.0))
        if len(traj) > 1 and end_rest > 0.0:
            step = float(np.median(np.diff(T)))
            for j in range(1, math.ceil(end_rest / step) + 1):
                tracer.push(T[-1] + j * step, P[-1], Q[-1])
    finally:
        if pruned is not None:
            recognizer.prune = pruned
    return tracer.events, tracer.trace()


def plot_timeline(
    path: str | Path,
    segments: Sequence[SegmentLike],
    events: Sequence[Event],
    trace: StreamTrace,
    threshold: float | Mapping[str, float] | None = None,
    title: str = "",
) -> Path:
    """Timeline figure: labelled gestures, events, and how near each classified candidate came to
    a gesture (PNG/PDF/SVG).

    The lower panel shows, for every candidate the recognizer classified, its distance to the
    nearest gesture divided by that gesture's threshold τ_g (coloured by the gesture): below 1 the
    candidate could fire. One line at 1 replaces seven thresholds.

    Parameters
    ----------
    path : str or Path
        Output file.
    segments : sequence
        Labelled gestures (``label``, ``start_t``, ``end_t``).
    events : sequence of Event
    trace : StreamTrace
        Per-gesture dissimilarities (and, from :func:`run_stream`, the per-gesture thresholds).
    threshold : float or mapping of str to float, optional
        Per-gesture thresholds, or one τ for all gestures. Default: ``trace.thresholds``.
    title : str

    Returns
    -------
    Path
        The written file.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = list(dict.fromkeys(list(trace.gestures) + [s.label for s in segments]))
    cmap = plt.get_cmap("tab10")
    color = {lab: cmap(i % 10) for i, lab in enumerate(labels)}
    fig, (ax0, ax1) = plt.subplots(2, 1, figsize=(14, 5.5), sharex=True,
                                   gridspec_kw={"height_ratios": [1, 1.6]})
    _draw_labels_and_events(ax0, segments, events, color)
    ax0.set_title(title)
    _draw_ratios(ax1, trace, _thresholds(trace, threshold), color)
    handles = [plt.Line2D([], [], marker="o", ls="", color=color[g], label=g.replace("_", " "))
               for g in labels]
    fig.legend(handles=handles, loc="center right", fontsize=8, title="gesture", title_fontsize=8,
               frameon=False)
    fig.tight_layout(rect=(0, 0, 0.9, 1))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _draw_labels_and_events(ax: Any, segments: Sequence[SegmentLike], events: Sequence[Event],
                            color: dict[str, Any]) -> None:
    """Upper panel: the labelled gestures as bars, the events as triangles below them."""
    for s in segments:
        ax.axvspan(s.start_t, s.end_t, ymin=0.55, ymax=0.95, color=color.get(s.label, "0.5"), alpha=0.6)
        ax.text(0.5 * (s.start_t + s.end_t), 0.78, s.label.replace("_", "\n"), ha="center",
                va="center", fontsize=7)
    for ev in events:
        ax.plot([ev.time], [0.3], marker="v", ms=8, color=color.get(ev.label, "k"))
        ax.text(ev.time, 0.05, ev.label.replace("_", "\n"), ha="center", va="bottom", fontsize=6)
    ax.set_ylim(0, 1)
    ax.set_yticks([0.3, 0.78], ["events", "labels"])


def _thresholds(trace: StreamTrace, threshold: float | Mapping[str, float] | None) -> dict[str, float]:
    if isinstance(threshold, Mapping):
        return {g: float(v) for g, v in threshold.items()}
    if trace.thresholds:
        return dict(trace.thresholds)
    if threshold is not None:
        return dict.fromkeys(trace.gestures, float(threshold))
    return {}


def _draw_ratios(ax: Any, trace: StreamTrace, taus: dict[str, float], color: dict[str, Any]) -> None:
    """Lower panel: each candidate's distance to its nearest gesture over that gesture's τ."""
    if trace.times.size:
        tau = np.array([taus.get(g, 1.0) for g in trace.gestures])
        ratio = np.where(np.isfinite(trace.dissimilarity), trace.dissimilarity / tau, np.inf)
        nearest = np.argmin(ratio, axis=1)
        best = ratio[np.arange(len(nearest)), nearest]
        finite = np.isfinite(best)
        for g, lab in enumerate(trace.gestures):
            sel = finite & (nearest == g)
            ax.scatter(trace.times[sel], best[sel], s=14, color=color[lab], zorder=3)
    ax.axhspan(1e-3, 1.0, color="0.92", zorder=0)
    ax.axhline(1.0, color="k", ls="--", lw=1)
    ax.text(0.005, 0.5, "below the threshold: may fire", transform=ax.get_yaxis_transform(),
            fontsize=7, va="top", color="0.3")
    ax.set_yscale("log")
    ax.set_ylim(0.05, 20)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("distance / threshold τ\nof the nearest gesture")
