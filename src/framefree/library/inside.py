"""A part of one gesture that fires another: each take replayed through the built recognizer.

:func:`~framefree.library.check.check_takes` compares whole takes with whole takes. Live, the
recognizer also classifies the *parts* of a motion (the candidates that end with every movement
unit), and a gesture may fire on the first half of another one before that one has ended: the arc
out of a *go home* drawn as the first stroke of a check mark whose corner came out round, a hook
at the start of a combo. Nothing of that shows between whole takes.

:func:`fired_inside` replays every take of a library as a stream through the recognizer built
from it, from a rest and into one (:func:`from_rest`, :func:`~framefree.online.evaluation.
run_stream`), and counts the events of another gesture (or a stop signal) that each gesture's
takes give. :func:`inside_findings` turns them into the
findings of ``framefree check``: a warning where some of a gesture's takes fire another gesture,
a problem where more than half do. Measured on the replica: a check mark taught from five takes of
one demonstration (``python benchmarks/eighth_gesture.py --gesture check_mark --demo-seed 1``)
fires inside 3 of the 5 *go home* takes, and live, held-out people's *go home* then gave a check
mark 11 times in 29 (docs/online-history.md, session 38); the four other demonstrations fire
inside no take, and their *go home* keeps every performance.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..core.trajectory import Trajectory
from ..online.evaluation import run_stream
from .check import Finding
from .store import TakeSet

__all__ = ["fired_inside", "from_rest", "inside_findings"]


def fired_inside(recognizer: Any, takes: TakeSet, progress: bool = False
                 ) -> dict[str, dict[str, list[str]]]:
    """Which takes of each gesture fire another gesture when replayed as a stream.

    Parameters
    ----------
    recognizer : Recognizer
        Built from ``takes`` (a library file's :func:`~framefree.library.store.load_recognizer`);
        it is reset before each take and left reset.
    takes : TakeSet
        The takes, each one performance of its gesture. Each is replayed after its first pose
        held still for the recognizer's ``max_wait`` (:func:`from_rest`), and the recording's
        end is held as long (:func:`~framefree.online.evaluation.run_stream`).
    progress : bool
        Show a progress bar on a terminal.

    Returns
    -------
    dict of str to dict of str to list of str
        ``{gesture: {other label fired: names of the gesture's takes that fire it}}``, only the
        gestures whose takes fire something else; ``"stop"`` is a stop signal.
    """
    from tqdm import tqdm

    fired: dict[str, dict[str, list[str]]] = {}
    rows = tqdm(list(zip(takes.takes, takes.labels, takes.names, strict=True)),
                desc="replaying the takes", unit="take", leave=False,
                disable=None if progress else True)
    lead = float(getattr(recognizer.config, "max_wait", 1.0))
    for take, gesture, name in rows:
        events, _ = run_stream(recognizer, from_rest(take, lead))
        for other in sorted({e.label for e in events if e.label != gesture}):
            fired.setdefault(gesture, {}).setdefault(other, []).append(name)
    recognizer.reset()
    return fired


def from_rest(take: Trajectory, seconds: float) -> Trajectory:
    """``take`` after its first pose held still for ``seconds`` [s] at its sampling interval: a
    performance starts from a rest, which a take cut tightly (a benchmark's segmented example)
    does not hold, and the recognizer forms a candidate of the whole only after one."""
    if len(take) < 2 or seconds <= 0:
        return take
    step = float(np.median(np.diff(take.t)))
    n = math.ceil(seconds / step)
    t = np.concatenate([take.t[0] - step * np.arange(n, 0, -1), take.t])
    p = np.concatenate([np.repeat(take.p[:1], n, axis=0), take.p])
    q = np.concatenate([np.repeat(take.q[:1], n, axis=0), take.q])
    return Trajectory(t, p, q, source=take.source)


def inside_findings(fired: dict[str, dict[str, list[str]]], takes: TakeSet) -> list[Finding]:
    """The findings of :func:`fired_inside`: a problem where more than half of a gesture's takes
    fire another gesture (live, that gesture will often give the other one halfway), else a
    warning that names the takes."""
    counts = takes.counts()
    out = []
    for gesture, by in fired.items():
        n_takes = counts[gesture]
        for other, names in by.items():
            what = "a stop signal" if other == "stop" else other
            shown = ", ".join(names[:5]) + (", ..." if len(names) > 5 else "")
            fire = "fires" if len(names) == 1 else "fire"
            head = (f"{len(names)} of {gesture}'s {n_takes} takes, replayed as a stream, {fire} "
                    f"{what} ({shown}): live, a part of a {gesture} may give {what}")
            if 2 * len(names) > n_takes:
                advice = ("record it again more steadily" if other == "stop" else
                          f"record {other} again so that it looks like no part of {gesture}, or "
                          "enroll without one of the two")
                out.append(Finding("problem", gesture, f"{head}; {advice}"))
            else:
                out.append(Finding("warning", gesture, f"{head} now and then; record "
                                   f"{'it' if len(names) == 1 else 'them'} again or leave "
                                   f"{'it' if len(names) == 1 else 'them'} out (--remove {names[0]})"))
    return out
