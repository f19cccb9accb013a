"""Why a live recognizer missed a gesture or fired on other motion, from the candidates it
classified (``framefree evaluate-stream --explain``).

:func:`explain_stream` runs a recognizer over a labelled stream while its spotter logs every
candidate (:func:`logging_candidates`, :attr:`Spotter.log
<framefree.online.spotting.Spotter.log>`); :func:`explain` then takes each missed gesture through
the spotter's stages in order and names the first one it did not pass:

``no candidate``
    no candidate overlapped it: its motion made no movement unit (too slow for the move level),
    or no candidate could start there (after a rest, within the longest span, after the last
    event or stop);
``cut elsewhere``
    every candidate overlapping it shares less than half of their joint span with it: they start
    too early (at the last rest) or run on into the next motion;
``another gesture``
    the candidates that cover it are nearest another gesture's model;
``beyond its threshold``
    nearest its gesture, but at more than τ (the ratio says how far);
``refused by a limit``
    nearest its gesture and below τ, refused by a shape limit (which ones are named);
``accepted, not fired``
    accepted, then replaced by another candidate, or fired after the tolerance.

Each false positive is explained by the candidate that fired: its span, nearest gesture, ratio to
τ, size and travel, and the labelled gesture it overlaps, if any.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from ..errors import FramefreeError
from .candidate import Candidate
from .evaluation import StreamResult, match_events, run_stream

__all__ = ["MISS_REASONS", "explain", "explain_stream", "logging_candidates"]

#: The reasons a gesture is missed, in the order of the spotter's stages.
MISS_REASONS = ("no candidate", "cut elsewhere", "another gesture", "beyond its threshold",
                "refused by a limit", "accepted, not fired")


@contextmanager
def logging_candidates(rec: Any) -> Iterator[list[Candidate]]:
    """While the block runs, every candidate ``rec``'s spotter classifies is appended to the list
    it yields (unbounded: for a diagnosis, not a live session)."""
    spotter = getattr(rec, "spotter", None)
    if spotter is None or not hasattr(spotter, "log"):
        raise FramefreeError("only framefree's segment recognizer (--method segments) can explain "
                             "its misses: this one has no candidates")
    spotter.log = log = []
    try:
        yield log
    finally:
        spotter.log = None


def explain_stream(rec: Any, trajectory: Any, segments: Sequence[Any], tolerance: float = 0.5
                   ) -> tuple[StreamResult, dict[str, list[dict[str, Any]]]]:
    """Run ``rec`` (a :class:`~framefree.online.Recognizer`) over a labelled stream
    (``trajectory`` and its ``segments``); return the matched events (:func:`match_events`) and
    :func:`explain`'s answer."""
    with logging_candidates(rec) as log:
        events, _ = run_stream(rec, trajectory)
    res = match_events(events, segments, float(trajectory.t[-1] - trajectory.t[0]), tolerance)
    return res, explain(res, segments, log, rec.labels, rec.spotter)


def _overlap(c: Candidate, start: float, end: float) -> float:
    """Intersection over union of a candidate's span and ``[start, end]`` [s]."""
    inter = min(c.end_t, end) - max(c.start_t, start)
    union = max(c.end_t, end) - min(c.start_t, start)
    return max(inter, 0.0) / union if union > 0 else 0.0


def _row(c: Candidate, labels: Sequence[str]) -> dict[str, Any]:
    return {"start_t": c.start_t, "end_t": c.end_t, "gesture": labels[c.model], "ratio": c.ratio,
            "size_m": c.size, "travel_m": None if math.isinf(c.travel) else c.travel,
            "units": c.n_units, "accepted": c.accepted}


def _miss(seg: dict[str, Any], log: Sequence[Candidate], labels: Sequence[str],
          spotter: Any) -> dict[str, Any]:
    """The first stage a missed gesture did not pass, and the candidate that came closest."""
    start, end, label = seg["start_t"], seg["end_t"], seg["label"]
    near = [c for c in log if c.end_t > start and c.start_t < end]
    out = {"label": label, "start_t": start, "end_t": end}
    if not near:
        return {**out, "reason": "no candidate", "candidate": None}
    covering = [c for c in near if _overlap(c, start, end) >= 0.5]
    if not covering:
        best = max(near, key=lambda c: _overlap(c, start, end))
        return {**out, "reason": "cut elsewhere", "candidate": _row(best, labels)}
    own = [c for c in covering if labels[c.model] == label]
    if not own:
        best = min(covering, key=lambda c: c.ratio)
        return {**out, "reason": "another gesture", "candidate": _row(best, labels)}
    accepted = [c for c in own if c.accepted]
    if accepted:
        best = min(accepted, key=lambda c: c.ratio)
        return {**out, "reason": "accepted, not fired", "candidate": _row(best, labels)}
    below = [c for c in own if c.ratio < 1.0]
    if below:
        best = min(below, key=lambda c: c.ratio)
        return {**out, "reason": "refused by a limit", "candidate": _row(best, labels),
                "limits": spotter.refusals(best)}
    best = min(own, key=lambda c: c.ratio)
    return {**out, "reason": "beyond its threshold", "candidate": _row(best, labels)}


def _fired(detail: dict[str, Any], log: Sequence[Candidate]) -> Candidate | None:
    """The accepted candidate an event came from (same model and distance, ended before it)."""
    found = [c for c in log if c.accepted and c.model == detail["model"]
             and c.distance == detail["dissimilarity"] and c.end_t <= detail["time"] + 1e-9]
    return found[-1] if found else None


def explain(res: StreamResult, segments: Sequence[Any], log: Sequence[Candidate],
            labels: Sequence[str], spotter: Any) -> dict[str, list[dict[str, Any]]]:
    """Why each gesture of ``res`` was missed and what each false positive was.

    Parameters
    ----------
    res : StreamResult
        The events of a stream matched to its ``segments`` (:func:`match_events`).
    segments : sequence of Segment
        The stream's labelled gestures.
    log : sequence of Candidate
        Every candidate the spotter classified on that stream, in order.
    labels : sequence of str
        The gesture of each model (``rec.labels``).
    spotter : Spotter
        The spotter that classified them (for :meth:`~framefree.online.spotting.Spotter.refusals`).

    Returns
    -------
    dict
        ``{"missed": [...], "false_positives": [...]}``: for each miss its label, span, ``reason``
        (one of :data:`MISS_REASONS`), the candidate that came closest (``None`` for
        ``no candidate``) and, when refused by a limit, the ``limits``; for each false positive
        its time, label, the candidate that fired and the labelled gestures it overlaps.
    """
    missed = [_miss(m, log, labels, spotter) for m in res.missed]
    false_positives = []
    for d in res.details:
        if d["verdict"] == "tp":
            continue
        c = _fired(d, log)
        overlaps = [] if c is None else [s.label for s in segments
                                         if s.start_t < c.end_t and s.end_t > c.start_t]
        false_positives.append({"time": d["time"], "label": d["label"], "verdict": d["verdict"],
                                "candidate": None if c is None else _row(c, labels),
                                "overlaps": overlaps})
    return {"missed": missed, "false_positives": false_positives}
