"""A candidate gesture as the spotter classified it (:mod:`framefree.online.spotting`): its span,
its nearest model and distance, and the shape measures its gesture's limits were checked on; and
which spans of the latest movement units may be one (:func:`candidate_spans`)."""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from .segmentation import Unit

__all__ = ["Candidate", "candidate_spans", "refuse_tails"]


@dataclass(frozen=True)
class Candidate:
    """A classified candidate segment.

    Attributes
    ----------
    start, end : int
        Running indices of its first and last uniform pose (without the margin).
    start_t, end_t : float
        The same as times [s].
    model : int
        Index of the nearest model.
    distance : float
        Distance to that model.
    ratio : float
        ``distance / τ`` of that model's gesture; accepted when below 1.
    n_units : int
        Number of movement units it spans.
    closure : float
        Screw path from its first to its last pose over its length (0: back at the start).
    size : float
        Total screw path [m] of its pre-smoothed poses.
    accepted : bool
        Below the threshold and within the closure, size and corner limits of its nearest
        model's gesture.
    corners : int
        Turns sharper than the spotter's ``corner_angle`` between its units.
    turns : int
        Which ways its corners turn (:func:`~framefree.online.span_shape.turn_kinds` bits).
    vertical : float
        Its :func:`~framefree.online.vertical.verticality` (NaN when no vertical is known).
    pause : float
        Its longest rest [s] between two units that meet at a corner
        (:func:`~framefree.online.span_shape.corner_rest`).
    travel : float
        How far the hand's position travels in it [m]
        (:func:`~framefree.online.span_shape.travel`).
    returning : bool
        Whether it is the way back after the gesture that fired last, as that gesture
        (:mod:`~framefree.online.returns`): refused.
    after_rest : bool
        Whether it starts after a full rest (False: after a brief dip below the rest level,
        or with ``valley_starts`` at a speed minimum without a rest).
    tail : bool
        Whether it starts after a brief dip and is the tail of the candidate one unit longer,
        which starts after a full rest and is nearest the same gesture
        (:func:`refuse_tails`): refused.
    proportions : tuple of float
        The natural log of each stroke's length over the next one's, between its corners
        (:func:`~framefree.online.proportions.proportions`; empty when no gesture's proportions
        are limited).
    direction : tuple of float
        Its hand direction (3,) in the tracker's frame
        (:func:`~framefree.online.hand_direction.hand_direction`; empty when no gesture's
        direction is limited or it does not move).
    outranked : bool
        Whether the model nearest by the descriptor alone, before the cones of hand directions
        weigh the distances, is another gesture's whose limits refuse this candidate: refused
        (the cones relabel only a motion whose shape that gesture admits).
    """

    start: int
    end: int
    start_t: float
    end_t: float
    model: int
    distance: float
    ratio: float
    n_units: int
    closure: float = 0.0
    size: float = 0.0
    accepted: bool = False
    corners: int = 0
    turns: int = 0
    vertical: float = math.nan
    pause: float = 0.0
    travel: float = math.inf
    returning: bool = False
    after_rest: bool = True
    tail: bool = False
    proportions: tuple[float, ...] = ()
    direction: tuple[float, ...] = ()
    outranked: bool = False


def candidate_spans(
    units: Sequence[Unit],
    max_units: int,
    max_duration: float,
    max_pause: float,
    after: int = -1,
    pause_ratio: float = math.inf,
    min_pause: float = 0.0,
) -> list[tuple[Unit, int]]:
    """The candidates ending with the last unit: ``(first unit, number of units)`` pairs.

    A candidate has at most ``max_units`` units, lasts at most ``max_duration`` seconds and starts
    after running index ``after``. Its longest rest may last at most ``pause_ratio`` × the
    duration of a stroke (a slow person pauses longer, in proportion), but never less than
    ``min_pause`` nor more than ``max_pause`` seconds. A stroke's duration is the candidate's
    span without that rest, shared by at most two strokes (out and back): for two units, the mean
    of the two. A hesitation cuts a stroke into pieces with short rests between them; measured
    on the pieces, a stroke would look short and leave room for no reversal pause at all.
    """
    out: list[tuple[Unit, int]] = []
    if not units:
        return out
    last = units[-1]
    longest_rest = 0.0
    for n in range(1, min(max_units, len(units)) + 1):
        first = units[-n]
        span = last.end_t - first.start_t
        if first.start <= after or span > max_duration:
            break
        if n > 1:
            longest_rest = max(longest_rest, units[-n + 1].start_t - first.end_t)
            stroke = (span - longest_rest) / min(n, 2)
            if longest_rest > max_pause:
                break
            if longest_rest > max(min_pause, pause_ratio * stroke):
                continue  # a longer candidate, with more of the strokes, may allow this rest
        out.append((first, n))
    return out


def refuse_tails(batch: Sequence[Candidate], gesture: Callable[[int], int]) -> list[Candidate]:
    """``batch`` (the candidates ending with one unit, shortest first) with every accepted
    candidate after a brief dip refused (:attr:`Candidate.tail`) when the candidate one unit
    longer starts after a full rest and is nearest the same gesture (``gesture``: a model's
    gesture): that one is the performance, begun at the rest, and was judged as a whole. The hand
    slows at the corners of a drawn shape without resting; the rest of a letter M after its first
    corner is an N, a zigzag turned, and must not fire a zigzag that the whole M did not."""
    out = list(batch)
    for k, (part, whole) in enumerate(itertools.pairwise(batch)):
        if (part.accepted and not part.after_rest and whole.after_rest
                and whole.n_units == part.n_units + 1
                and gesture(whole.model) == gesture(part.model)):
            out[k] = dataclasses.replace(part, accepted=False, tail=True)
    return out
