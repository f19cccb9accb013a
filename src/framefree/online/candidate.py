"""A candidate gesture as the spotter classified it (:mod:`framefree.online.spotting`): its span,
its nearest model and distance, and the shape measures its gesture's limits were checked on."""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Candidate"]


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
