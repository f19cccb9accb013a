"""A take that rests far longer between its moves than any other take.

The live spotter forms a candidate from consecutive movement units with rests between them no
longer than its pause allowance, learned from all takes together: the longest rest between two
units of any take, times ``span_factor`` (:func:`~framefree.online.limits.candidate_limits`).
One take that holds a second move after a real rest (the way back to the start, a settling move,
two performances) would raise the allowance for every gesture of the library: candidates then
span reaching out, staying and coming back, which fire as out-and-back gestures. Ten check marks
recorded before session 41 did that: one take held its way back after a 1.5 s rest, and *go left*
fired 16 times on the development people (docs/online-history.md, *Session 41*). Since session
42 such a take (:func:`~framefree.online.limits.odd_rest_take`) takes no part in the candidate
limits, and :func:`long_rest_findings` names it, so that the user re-records it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..online.learned import GIVEN
from ..online.limits import OUTLIER_RATIO, longest_gaps, odd_rest_take, recording_units
from ..online.multi_stream import recording_units as combined_units
from ..online.segmentation import SpeedLevels, Unit
from .check import Finding

if TYPE_CHECKING:
    from ..core.trajectory import Trajectory
    from .multi_library import MultiGestureLibrary
    from .store import GestureLibrary

__all__ = ["LongRest", "long_rest", "long_rest_findings", "longest_rests"]


@dataclass(frozen=True)
class LongRest:
    """The take whose rest between two moves is far the longest."""

    name: str
    """The take (``gesture/context/trial``)."""
    rest: float
    """Its longest rest between two movement units [s]."""
    others: float
    """The longest such rest of any other take [s]."""


def longest_rests(library: GestureLibrary | MultiGestureLibrary) -> np.ndarray:
    """The longest rest [s] between two movement units of each take (N,), cut as the library's
    live segmenter cuts it (several trackers: their combined motion; 0: one unit, or none)."""
    learned = library.learned_settings()
    config = library.recognizer_config()
    levels = SpeedLevels(learned.rest_speed, learned.move_speed)
    return longest_gaps([_units(take, levels, config.descriptor.L, config.constants.dt)
                         for take in library.takes.takes])


def _units(take: Trajectory | MultiTrajectory, levels: SpeedLevels, L: float, dt: float
           ) -> list[Unit]:
    if isinstance(take, MultiTrajectory):
        return combined_units(take, levels, L, dt)
    return recording_units(take, levels, L, dt)[1]


def long_rest(library: GestureLibrary | MultiGestureLibrary, ratio: float = OUTLIER_RATIO
              ) -> LongRest | None:
    """The take that rests far longer between two of its moves than any other
    (:func:`~framefree.online.limits.odd_rest_take`: more than ``ratio`` times any other take's
    longest rest, longer than ``min_pause``, in a gesture with other takes), else ``None`` (also
    when the pause allowance was given, not learned from the takes)."""
    if library.learned_settings().provenance.rules.get("max_pause", "").startswith(GIVEN):
        return None
    rests = longest_rests(library)
    k = odd_rest_take(rests, library.takes.labels, library.recognizer_config().constants.min_pause,
                      ratio)
    if k is None:
        return None
    others = np.delete(rests, k)
    return LongRest(library.takes.names[k], float(rests[k]), float(others.max()))


def long_rest_findings(library: GestureLibrary | MultiGestureLibrary) -> list[Finding]:
    """A warning naming the take that rests far longer between its moves than any other
    (:func:`long_rest`), which the candidate limits leave out; empty when there is none."""
    found = long_rest(library)
    if found is None:
        return []
    gesture = found.name.split("/", 1)[0]
    allowed = library.learned_settings().max_pause
    return [Finding(
        "warning", gesture,
        f"take {found.name} rests {found.rest:.1f} s between two of its moves (no other take more "
        f"than {found.others:.1f} s): it may hold a second move (the way back, a settling move), "
        f"so it does not widen how long a gesture may pause inside (up to {allowed:.1f} s, from "
        f"the other takes); re-record it, or remove it (framefree enroll --remove "
        f"{found.name})")]
