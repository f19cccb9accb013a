"""Which gestures admit a candidate's shape: the limits the spotter checks beside the threshold.

:class:`GestureLimits` holds the rule (closure and opening, size, travel, corners, proportions,
turns, verticality, one go, gestures the tracker does not follow) for one model, several
candidates, or every model at once, and names the limits that refuse a candidate for
``--explain``. :class:`~framefree.online.spotting.Spotter` is one; its constructor sets the
limits (:mod:`framefree.online.limits` and the calibration learn them from the takes).
"""

from __future__ import annotations

import functools
import math
import operator
from collections.abc import Sequence
from typing import Any

import numpy as np

from .candidate import Candidate
from .hand_direction import DirectionTable
from .proportions import ProportionTable

__all__ = ["GestureLimits"]


class GestureLimits:
    """Each model's shape limits, set by the spotter: arrays (M,) or (M, 2) per limit."""

    closure_limits: np.ndarray
    opening_limits: np.ndarray
    return_error: float
    size_limits: np.ndarray
    travel_limits: np.ndarray
    corner_limits: np.ndarray
    proportions: ProportionTable
    forbidden_turns: np.ndarray
    vertical_limits: np.ndarray
    one_go: np.ndarray
    min_pause: float
    unseen: np.ndarray
    directions: DirectionTable

    def admitting_models(self, closure_: float, size: float, corners: int = 0, turns: int = 0,
                         vertical: float = math.nan, pause: float = 0.0, moved: float = math.inf,
                         shares: np.ndarray | None = None) -> np.ndarray:
        """Which models' gestures admit a segment of this closure, size [m], number of corners,
        turn kinds, verticality, longest rest at a corner [s], travel [m],
        and :func:`~framefree.online.proportions.proportions` (K,)
        (M,) bool: the rule of :meth:`admissible`, for every model at once."""
        padded = None if shares is None else self.proportions.padded(np.asarray(shares, float))
        return self._admits(slice(None), closure_, size, corners, turns, vertical, pause, moved,
                            padded)

    def admissible(self, j: int, closures: np.ndarray, sizes: np.ndarray,
                   corners: np.ndarray | int = 0, turns: np.ndarray | int = 0,
                   vertical: np.ndarray | float = math.nan,
                   pauses: np.ndarray | float = 0.0,
                   travels: np.ndarray | float = math.inf,
                   shares: Sequence[np.ndarray] | None = None) -> np.ndarray:
        """Which segments (closures (n,), sizes (n,) [m], corners (n,), turn kinds (n,),
        verticality (n,) and longest rests at a corner (n,) [s], :attr:`Candidate.pause`) may be
        model ``j``'s gesture:
        within its size range, no more closed than its opening limit, within its closure limit
        or ending within :attr:`return_error` of their start (closure × size), with no more
        corners than its corner limit, no turn its gesture never makes, a rest at a corner of
        at most ``min_pause`` if it is drawn in one go (:attr:`one_go`), travelling at least its
        travel limit (travels (n,) [m]; ``inf``: not measured, passes), where a vertical is
        known, within its verticality range (NaN: unknown, passes), with as many corners as
        its takes agree on, within their proportions (``shares``: each segment's
        :func:`~framefree.online.proportions.proportions`; None: not measured, passes), and not
        a gesture the tracker does not follow
        (:attr:`unseen`)."""
        padded = None if shares is None else self.proportions.padded(list(shares))
        return self._admits(j, np.asarray(closures, dtype=float), np.asarray(sizes, dtype=float),
                            np.asarray(corners, dtype=float), np.asarray(turns, dtype=np.int64),
                            np.asarray(vertical, dtype=float), np.asarray(pauses, dtype=float),
                            np.asarray(travels, dtype=float), padded)

    def _admits(self, j: int | slice, closures: Any, sizes: Any, corners: Any, turns: Any = 0,
                vertical: Any = math.nan, pauses: Any = 0.0, travels: Any = math.inf,
                padded: np.ndarray | None = None) -> np.ndarray:
        """The admissibility rule for model(s) ``j`` (broadcast against the segments)."""
        passes = self._limits(j, closures, sizes, corners, turns, vertical, pauses, travels,
                              padded)
        return functools.reduce(operator.and_, passes.values())

    def _limits(self, j: int | slice, closures: Any, sizes: Any, corners: Any, turns: Any = 0,
                vertical: Any = math.nan, pauses: Any = 0.0, travels: Any = math.inf,
                padded: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Each limit of model(s) ``j`` on its own: ``{limit: passes}`` (``padded``:
        :meth:`ProportionTable.padded <framefree.online.proportions.ProportionTable.padded>`
        proportions, or None: not measured)."""
        closes = (closures <= self.closure_limits[j]) | (closures * sizes <= self.return_error)
        kept = (True if padded is None
                else self.proportions.passes(j, np.asarray(corners), padded))
        v_lo, v_hi = self.vertical_limits[j, 0], self.vertical_limits[j, 1]
        return {
            "closure": closes,
            "opening": closures >= self.opening_limits[j],
            "size": (sizes >= self.size_limits[j, 0]) & (sizes <= self.size_limits[j, 1]),
            "travel": travels >= self.travel_limits[j],
            "corners": corners <= self.corner_limits[j],
            "proportions": kept,
            "turns": (np.asarray(turns, dtype=np.int64) & self.forbidden_turns[j]) == 0,
            "vertical": ~((vertical < v_lo) | (vertical > v_hi)),  # NaN: no vertical known
            "one go": ~(self.one_go[j] & (pauses > self.min_pause)),
            "unseen": ~self.unseen[j],
        }

    def refusals(self, candidate: Candidate) -> list[str]:
        """The limits of its nearest model's gesture that refuse ``candidate`` (empty: none
        does; :mod:`framefree.online.diagnosis` says so for a missed gesture)."""
        padded = self.proportions.padded(np.asarray(candidate.proportions, dtype=float))
        passes = self._limits(candidate.model, candidate.closure, candidate.size,
                              candidate.corners, candidate.turns, candidate.vertical,
                              candidate.pause, candidate.travel, padded)
        passes["return"] = not candidate.returning
        passes["tail"] = not candidate.tail
        passes["nearest's limits"] = not candidate.outranked
        return [name for name, ok in passes.items() if not bool(ok)]

    def outranked(self, j: int, distances: np.ndarray, scale: np.ndarray | None, closure_: float,
                  size: float, corners: int, turns: int, vertical: float, pause: float,
                  moved: float, shares: np.ndarray) -> bool:
        """Whether model ``j``, nearest once the cones weighed the candidate's ``distances``
        (M,, as the descriptor gives them) by ``scale`` (M,; None: no cones), is not the
        descriptor's own nearest model and that model's gesture refuses the candidate (its
        closure, size [m], corners, ... as :meth:`admissible` takes them): the cones relabel
        only a motion whose shape the descriptor's nearest gesture admits, and a motion that
        gesture refuses is no gesture, whichever way it moves."""
        if scale is None:
            return False
        unweighed = int(np.argmin(distances))
        return unweighed != j and not bool(self.admissible(
            unweighed, np.array([closure_]), np.array([size]), corners, turns, vertical, pause,
            moved, [shares])[0])
