"""A take that rests far longer between its moves than any other take.

The live spotter forms a candidate from consecutive movement units with rests between them no
longer than its pause allowance, and that allowance is learned from all takes together: the
longest rest between two units of any take, times ``span_factor``
(:func:`~framefree.online.limits.candidate_limits`). One take that holds a second move after a real
rest (the way back to the start, a settling move, two performances) raises the allowance for every
gesture of the library: candidates then span reaching out, staying and coming back, which fire as
out-and-back gestures. Ten check marks recorded before session 41 did that: one take held its way
back after a 1.5 s rest, and *go left* fired 16 times on the development people
(docs/online-history.md, *Session 41*). :func:`long_rest_findings` names such a take.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..online.learned import GIVEN
from ..online.limits import recording_units
from ..online.segmentation import SpeedLevels
from .check import Finding

if TYPE_CHECKING:
    from .store import GestureLibrary

__all__ = ["LongRest", "long_rest", "long_rest_findings", "longest_rests"]

#: How many times longer than any other take's the longest rest must be to be named.
OUTLIER_RATIO = 2.0


@dataclass(frozen=True)
class LongRest:
    """The take whose rest between two moves is far the longest."""

    name: str
    """The take (``gesture/context/trial``)."""
    rest: float
    """Its longest rest between two movement units [s]."""
    others: float
    """The longest such rest of any other take [s]."""


def longest_rests(library: GestureLibrary) -> np.ndarray:
    """The longest rest [s] between two movement units of each take (N,), cut as the library's
    live segmenter cuts it (0: one unit, or none)."""
    learned = library.learned_settings()
    config = library.recognizer_config()
    levels = SpeedLevels(learned.rest_speed, learned.move_speed)
    out = np.zeros(len(library.takes.takes))
    for k, take in enumerate(library.takes.takes):
        _, units = recording_units(take, levels, config.descriptor.L, config.constants.dt)
        gaps = [b.start_t - a.end_t for a, b in itertools.pairwise(units)]
        out[k] = max(gaps, default=0.0)
    return out


def long_rest(library: GestureLibrary, ratio: float = OUTLIER_RATIO) -> LongRest | None:
    """The take whose longest rest between two moves is more than ``ratio`` times any other
    take's and longer than a gesture may rest at a corner anyway (``min_pause``), else ``None``
    (also when the pause allowance was given, not learned from the takes)."""
    if library.learned_settings().provenance.rules.get("max_pause", "").startswith(GIVEN):
        return None
    rests = longest_rests(library)
    if rests.size < 3:
        return None
    order = np.argsort(rests)
    worst, second = float(rests[order[-1]]), float(rests[order[-2]])
    if worst <= library.recognizer_config().constants.min_pause or worst <= ratio * second:
        return None
    return LongRest(library.takes.names[int(order[-1])], worst, second)


def long_rest_findings(library: GestureLibrary) -> list[Finding]:
    """A warning naming the take that rests far longer between its moves than any other
    (:func:`long_rest`), with the pause it allows every gesture; empty when there is none."""
    found = long_rest(library)
    if found is None:
        return []
    gesture = found.name.split("/", 1)[0]
    allowed = library.learned_settings().max_pause
    return [Finding(
        "warning", gesture,
        f"take {found.name} rests {found.rest:.1f} s between two of its moves (no other take more "
        f"than {found.others:.1f} s), so every gesture may now pause up to {allowed:.1f} s inside, "
        f"and reaching out, staying and coming back may fire: it may hold a second move (the way "
        f"back, a settling move); re-record it, or remove it (framefree enroll --remove "
        f"{found.name})")]
