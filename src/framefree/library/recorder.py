"""Recording takes live: one long recording of a gesture performed again and again, cut into takes
as the rests after them arrive (:class:`TakeRecorder`, what ``framefree record`` runs).

Between performances of an open stroke (a swipe, a Z) the hand goes back to the start, and that
move is left out (:func:`is_way_back`); a performance that pauses at its turning point longer than
the shortest rest is joined back together. :mod:`framefree.library.takes` finds the takes.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ..core.trajectory import MIN_SAMPLES, Trajectory
from .takes import SPEED_PERIOD, TakeSettings, TakeSpan, cut_take, find_takes

__all__ = ["RETRACE", "TakeRecorder", "is_way_back", "retraces"]

#: How long, against the way out, the way back of an out-and-back gesture is at least (path
#: lengths of the hand's position): the second half of a performance retraces the first.
RETRACE = 0.8


def _travel(take: Trajectory) -> tuple[float, float]:
    """Distance [m] between the take's first and last position, and its path length [m]."""
    return (float(np.linalg.norm(take.p[-1] - take.p[0])),
            float(np.linalg.norm(np.diff(take.p, axis=0), axis=1).sum()))


def _is_open(take: Trajectory, open_ratio: float = 0.15) -> bool:
    """Whether a take ends away from its start: at least ``open_ratio`` of its path length."""
    away, path = _travel(take)
    return path > 0 and away >= open_ratio * path


def is_way_back(previous: Trajectory, take: Trajectory, tolerance: float = 0.5,
                open_ratio: float = 0.15) -> bool:
    """True if ``take`` is the hand going back to where ``previous`` began.

    When a gesture ends away from where it starts (an *open* stroke: a swipe, a Z, an L), a person
    recording it several times moves the hand back to the start between performances, and that
    move is cut as a take of its own. It starts near where ``previous`` ended, within
    ``tolerance`` × the distance ``previous`` travelled, and goes most of the way back: it ends
    within that distance of where ``previous`` began, or at least twice as near to where
    ``previous`` began as to where it ended (a person who comes back past the start, or beside
    it, has still come back); and ``previous`` is open: that
    distance is at least ``open_ratio`` × its path length (a gesture that comes back to its
    start has no way back). Positions are the tracker's, so the test does
    not depend on the world frame; a grip offset of a few centimetres is small against the
    distance an open stroke travels.

    Parameters
    ----------
    previous : Trajectory
        The last take kept (not itself a way back).
    take : Trajectory
        The take that followed it.
    tolerance, open_ratio : float

    Returns
    -------
    bool
    """
    if not _is_open(previous, open_ratio):
        return False
    away = _travel(previous)[0]
    starts_at_end = np.linalg.norm(take.p[0] - previous.p[-1]) <= tolerance * away
    to_start = np.linalg.norm(take.p[-1] - previous.p[0])
    ends_at_start = (to_start <= tolerance * away
                     or 2.0 * to_start <= np.linalg.norm(take.p[-1] - previous.p[-1]))
    return bool(starts_at_end and ends_at_start)


def retraces(first: Trajectory, second: Trajectory, ratio: float = RETRACE) -> bool:
    """Whether ``second``, which goes back to where ``first`` began (:func:`is_way_back`), may be
    the second half of one out-and-back performance: its path is at least ``ratio`` × the
    path of ``first``. The hand going back to the start after an open stroke takes a shorter way
    wherever the stroke is not straight (after a Z or a check mark: 0.39–0.73 of its path on the
    replica's development people), while the way back of an out-and-back gesture retraces its way
    out (0.93–1.15 of it)."""
    return _travel(second)[1] >= ratio * _travel(first)[1]


class TakeRecorder:
    """Cuts takes out of a live pose stream as soon as the rest after them is long enough.

    Samples are buffered; :meth:`poll` looks for takes that are complete (followed by at least
    ``min_rest`` seconds of rest) and returns the new ones. The rest level is re-derived from
    everything recorded so far, so the first poll should come after a first performance.

    Two kinds of motion between performances are not returned but listed in :attr:`left_out`
    with the reason: the hand going back to where the previous take began (:func:`is_way_back`:
    the return between performances of an open stroke), and a move whose screw path is less than
    ``min_relative_path`` times the largest take's so far (settling the hand, not a performance).

    A move that follows an open take *after a pause much shorter than this person's rests* is
    no new performance and no way back but the rest of that take: a performance that hesitated
    at its turning point (an out-and-back gesture whose pause there outlasted ``min_rest``) or at
    a corner. It is joined to the take and listed in :attr:`joined`, unless it goes back to
    where the take began by a much shorter way than the take's own (:func:`retraces`): then it
    is the way back after an open stroke, which a person may start soon. Much shorter: under
    ``pause_ratio`` × the median of the recording's rests so far (the rest before the first take
    included). So an open take is returned only once the next move (or the end of the recording)
    shows that it is complete; a joined take that is still open waits again.

    Parameters
    ----------
    settings : TakeSettings, optional
        Defaults to ``TakeSettings()``.
    keep_all : bool
        Return every take, leaving nothing out.
    min_relative_path : float
        Smallest screw path of a take relative to the largest move kept before it (a joined take
        counts by its pieces, so the halves of a later hesitant performance are not "small").
    pause_ratio : float
        A move (not a small one) that follows an open take after less than this fraction of the
        recording's median rest is joined to it (0.6; 0: never).
    """

    def __init__(self, settings: TakeSettings | None = None, keep_all: bool = False,
                 min_relative_path: float = 0.25, pause_ratio: float = 0.6) -> None:
        self.settings = settings or TakeSettings()
        self.keep_all = keep_all
        self.min_relative_path = float(min_relative_path)
        self.pause_ratio = float(pause_ratio)
        self._rows: list[np.ndarray] = []
        self._done_until = -math.inf
        self._last_kept: Trajectory | None = None
        self._last_span: TakeSpan | None = None
        self._held: tuple[TakeSpan, Trajectory] | None = None
        self._rests: list[float] = []
        self._largest = 0.0
        self.spans: list[TakeSpan] = []
        #: (span, reason) of every take left out: ``"way back"`` or ``"small"``
        self.left_out: list[tuple[TakeSpan, str]] = []
        #: (first, second, joined) spans of every performance put back together after a pause
        self.joined: list[tuple[TakeSpan, TakeSpan, TakeSpan]] = []

    def _reason_to_leave_out(self, span: TakeSpan, take: Trajectory) -> str | None:
        if self.keep_all:
            return None
        if span.path < self.min_relative_path * self._largest:
            return "small"
        if self._last_kept is not None and is_way_back(self._last_kept, take):
            return "way back"
        return None

    def push(self, t: float, p: np.ndarray, q: np.ndarray) -> None:
        """Buffer one pose sample (time [s], position (3,) [m], quaternion (4,) w, x, y, z)."""
        row = np.concatenate([[float(t)], np.asarray(p, dtype=float).ravel(),
                              np.asarray(q, dtype=float).ravel()])
        if not np.isfinite(row).all() or (self._rows and row[0] <= self._rows[-1][0]):
            return
        self._rows.append(row)

    @property
    def recording(self) -> Trajectory | None:
        """Everything recorded so far (``None`` before the first few samples)."""
        if len(self._rows) < MIN_SAMPLES:
            return None
        return Trajectory.from_array(np.array(self._rows), source="recording")

    def _new(self, final: bool) -> Iterator[tuple[TakeSpan, Trajectory]]:
        traj = self.recording
        if traj is None or traj.duration < MIN_SAMPLES * SPEED_PERIOD:
            return
        now = float(traj.t[-1])
        for sp in find_takes(traj, self.settings):
            if sp.onset <= self._done_until:
                continue
            if not final and now - sp.end < self.settings.min_rest:
                break
            self._done_until = sp.end
            rest = sp.onset - (self._last_span.end if self._last_span else float(traj.t[0]))
            self._last_span = sp
            take = cut_take(traj, sp, f"take {len(self.spans) + 1}")
            reason = self._reason_to_leave_out(sp, take)
            if (reason != "small" and self._held is not None and self._is_pause(rest)
                    and not self._way_back_of_held(reason, take)):
                both, whole = self._join(traj, self._held[0], sp)
                if _is_open(whole):  # it may go on after another pause (a Z held at each corner)
                    self._held = (both, whole)
                else:
                    yield self._keep(both, whole)
                continue
            self._rests.append(rest)
            if reason is not None:
                self.left_out.append((sp, reason))
                if self._held is not None:
                    yield self._keep(*self._held)
                continue
            if self._held is not None:
                yield self._keep(*self._held)
            self._last_kept = take
            self._largest = max(self._largest, sp.path)
            if self.keep_all or not _is_open(take):
                yield self._keep(sp, take)
            else:  # complete only once the next move is known not to be its second half
                self._held = (sp, take)
        if final and self._held is not None:
            yield self._keep(*self._held)

    def _way_back_of_held(self, reason: str | None, take: Trajectory) -> bool:
        """Whether ``take``, left out as a way back (``reason``: the held take is the last one
        kept), goes back to where the held take began without retracing it."""
        return reason == "way back" and not retraces(self._held[1], take)

    def _is_pause(self, rest: float) -> bool:
        """Whether a rest is much shorter than the recording's rests so far."""
        return bool(self._rests) and rest < self.pause_ratio * float(np.median(self._rests))

    def _join(self, traj: Trajectory, first: TakeSpan, second: TakeSpan) -> tuple[TakeSpan, Trajectory]:
        """The performance ``first`` … ``second`` as one take."""
        both = TakeSpan(first.onset, second.end, first.start, second.stop,
                        max(first.peak_speed, second.peak_speed), first.path + second.path)
        self.joined.append((first, second, both))
        take = cut_take(traj, both, f"take {len(self.spans) + 1}")
        self._last_kept = take
        return both, take

    def _keep(self, span: TakeSpan, take: Trajectory) -> tuple[TakeSpan, Trajectory]:
        self._held = None
        self.spans.append(span)
        return span, take

    @property
    def pending(self) -> int:
        """Takes found but not yet returned (0 or 1: an open take waiting for the next move)."""
        return int(self._held is not None)

    def poll(self) -> list[tuple[TakeSpan, Trajectory]]:
        """Takes completed since the last call: (span, take) pairs."""
        return list(self._new(final=False))

    def finish(self) -> list[tuple[TakeSpan, Trajectory]]:
        """At the end of the recording: the remaining takes, including a last one without rest."""
        return list(self._new(final=True))
