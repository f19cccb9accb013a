"""The shape of a span of movement units: its corners, which way they turn, how long the hand
rests at them, whether the span comes back to where it started, and how far the hand travels.

Every quantity here is computed from the units' headings and chords
(:attr:`~framefree.online.segmentation.Unit.heading_in`, ``heading_out``, ``chord``: screw-like
vectors that a change of world frame turns alike) or from screw paths, so none depends on the
world frame: a turn angle is the angle between two headings, a turn's sense the cosine between
two oriented planes, a closure a ratio of screw paths, a travel a length. The spotter measures them on every
candidate (:mod:`framefree.online.spotting`) and the recognizer on the model recordings, to set
the limits a candidate must keep (:mod:`framefree.online.limits`).

See ``docs/online.md`` (What comes from the models).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..core.progress import progress_increments, screw_path_increment
from ..core.smoothing import gaussian_smooth

if TYPE_CHECKING:
    from .segmentation import Unit

__all__ = [
    "ALTERNATING",
    "REVERSAL_ANGLE",
    "SAME_SENSE",
    "closure",
    "corner_count",
    "corner_rest",
    "is_corner",
    "plane_cosine",
    "travel",
    "turn_angle",
    "turn_kinds",
]


def turn_angle(a: np.ndarray | None, b: np.ndarray | None) -> float:
    """Angle [deg] between two headings (6,): 0 when the hand goes on the same way, 180 when it
    reverses; 0 when either is unknown or zero."""
    if a is None or b is None:
        return 0.0
    norm = float(np.linalg.norm(a) * np.linalg.norm(b))
    if not norm > 0:
        return 0.0
    return math.degrees(math.acos(min(1.0, max(-1.0, float(a @ b) / norm))))


def is_corner(a: Unit, b: Unit, angle: float) -> bool:
    """Whether consecutive units ``a`` and ``b`` meet at a corner sharper than ``angle`` [deg].

    Either the heading turns by more than ``angle`` from where ``a`` ends to where ``b`` begins
    (:func:`turn_angle` of ``a.heading_out`` and ``b.heading_in``), or it turns by more than
    half of it there while the units' chords turn by more than ``angle`` (v16). The second case
    is a polygon drawn fluently: the hand slows at a corner without stopping, the units split at
    the speed minimum inside the rounded corner, and the headings there have partly turned
    already. Two arcs of a circle that a near-stop cuts apart turn, chord to chord, by half
    their sum, but the hand there goes on the same way: no corner."""
    turn = turn_angle(a.heading_out, b.heading_in)
    return turn > angle or (turn > angle / 2 and turn_angle(a.chord, b.chord) > angle)


def corner_count(units: Sequence[Unit], angle: float) -> int:
    """Corners of a span of consecutive units: meetings of one unit and the next that
    :func:`is_corner` calls sharper than ``angle`` [deg]."""
    return sum(is_corner(a, b, angle) for a, b in itertools.pairwise(units))


def corner_rest(units: Sequence[Unit], angle: float) -> float:
    """The longest rest [s] between two consecutive units of a span where the hand's heading
    turns by more than ``angle`` [deg] (:func:`turn_angle`); 0 without one. A hesitation on a
    straight stroke or a smooth curve rests where the hand goes on the same way, so it does not
    count, even where the arcs on either side of it turn, chord to chord, like the sides of a
    corner (:func:`is_corner`; a corner drawn fluently has no rest to count); the rest after a
    reposition, before a drawn shape turns away from it, does."""
    return max((b.start_t - a.end_t for a, b in itertools.pairwise(units)
                if turn_angle(a.heading_out, b.heading_in) > angle), default=0.0)


#: Bits of :func:`turn_kinds`: two corners that turn the same way (around a triangle or a square)
SAME_SENSE = 1
#: ... and a corner that turns back the way the previous one came (a Z, an N, an M)
ALTERNATING = 2


def plane_cosine(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> float:
    """Cosine of the angle between the oriented planes of ``a → b`` and ``c → d`` (vectors of
    any one dimension): ``⟨a∧b, c∧d⟩ / (|a∧b| |c∧d|)`` with ``⟨a∧b, c∧d⟩ = (a·c)(b·d) −
    (a·d)(b·c)``. 1 for two turns the same way in one plane, −1 for a turn back, 0 when either
    pair is parallel (no plane) or the planes are perpendicular."""
    inner = float((a @ c) * (b @ d) - (a @ d) * (b @ c))
    norms = float(((a @ a) * (b @ b) - (a @ b) ** 2) * ((c @ c) * (d @ d) - (c @ d) ** 2))
    return inner / math.sqrt(norms) if norms > 0 else 0.0


#: Sharpest turn [deg] between two chords whose plane says which way the hand turned: a sharper
#: one is a reversal, an out-and-back move, whose plane the hand's small sideways drift decides
#: (on the real Vive recordings, reversals of flapping arms turned by 158–179° and their planes
#: lay every way).
REVERSAL_ANGLE = 150.0


def turn_kinds(units: Sequence[Unit], angle: float) -> int:
    """Which way a span of consecutive units turns at its corners (:func:`corner_count`): the
    bits :data:`SAME_SENSE` and :data:`ALTERNATING` of every pair of consecutive corners, 0 with
    fewer than two corners.

    A corner's turn is the oriented plane from the chord of the unit before it to the chord of
    the unit after it (:attr:`Unit.chord`); two corners turn the same way when the
    :func:`plane_cosine` of their planes is positive. Chords, screw-like headings (6,), turn
    alike with any change of world frame, so the kinds do not depend on it, and a polygon turns
    the same way however it lies in space, while a Z turns back at its second corner. A pair
    with a reversal (chords more than :data:`REVERSAL_ANGLE` apart) says nothing."""
    planes = [(a.chord, b.chord) for a, b in itertools.pairwise(units) if is_corner(a, b, angle)]
    kinds = 0
    for (a, b), (c, d) in itertools.pairwise(planes):
        if any(v is None for v in (a, b, c, d)):
            continue
        if max(turn_angle(a, b), turn_angle(c, d)) > REVERSAL_ANGLE:
            continue
        cos = plane_cosine(a, b, c, d)
        kinds |= SAME_SENSE if cos > 0 else ALTERNATING if cos < 0 else 0
    return kinds


def closure(poses: np.ndarray, L: float) -> float:
    """How far a motion ends from where it started, relative to its length (bi-invariant).

    ``s(T_0, T_end) / Σ_k s(T_k, T_{k+1})`` with ``s`` the screw path [m]: 0 for a motion that
    returns to its start pose (every HPM gesture goes out and comes back), 1 for a motion that goes
    one way (a repositioning move).

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4)
    L : float
        Scale length of the screw path [m].
    """
    P = np.ascontiguousarray(poses, dtype=np.float64)
    if P.shape[0] < 2:
        return 1.0
    total = float(progress_increments(P, "screw", L).sum())
    if not total > 0:
        return 1.0
    return min(1.0, screw_path_increment(P[0], P[-1], L) / total)


def travel(poses: np.ndarray, presmooth: int = 5) -> float:
    """How far the hand travels [m]: the length of the path of its positions, pre-smoothed as the
    classifier smooths poses (a Gaussian of ``presmooth`` samples), so that sensor jitter adds
    little.

    Unlike the screw path, a turn of the hand adds nothing: a wrist that turns while the hand
    stays where it is travels no distance. A world frame change moves every position rigidly, so
    the travel does not depend on it.

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4)
    presmooth : int
        Gaussian window [samples] (1: no smoothing).
    """
    p = np.asarray(poses, dtype=np.float64)[:, :3, 3]
    if p.shape[0] < 2:
        return 0.0
    if presmooth > 1 and p.shape[0] >= presmooth:
        p = gaussian_smooth(p, presmooth)
    return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
