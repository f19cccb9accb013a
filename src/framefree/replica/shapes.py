"""Shapes a person draws in the air with the hand: letters, zigzags, triangles, waves, spirals.

None of them is an HPM gesture. They are a user's own gestures to enroll, or, left out of a
vocabulary, the motions that must stay silent: a recognizer that fires on a triangle because a
zigzag was enrolled has thresholds that depend on the company a gesture keeps. Some shapes are
kept out of every choice of setting (:data:`HELDOUT_SHAPES`), so that rejection is measured on
shapes nothing was tuned on. The first held-out family (square, letter V, spiral) was run once, for
v6 of the live recognizer; what it showed (squares fire as circles and zigzags) was then worked on,
so it moved to development and a second family, never run before v7's settings were fixed, took
its place.

Each shape is drawn in the frontal plane of the performance (``right`` to the user's right, ``up``
up), with the palm down and the hand not turning. A polyline is drawn stroke by stroke: each side
is a minimum-jerk stroke, so the hand slows down at every corner, as people do (the speed of
drawing falls where the path bends: Lacquaniti, Terzuolo & Viviani, Acta Psychol 54:115, 1983),
with a short hold of up to 80 ms at some corners. Curves (*wave*, *spiral*) are one stroke.

==========  ======================================================================  ========
name        path (nominal size)                                                      closes
==========  ======================================================================  ========
zigzag      a Z: right 24 cm, diagonal back down-left, right again (18 cm tall)      no
triangle    right 24 cm, up-left to the apex 20 cm above the middle, back down       yes
letter_l    down 22 cm, right 14 cm                                                  no
wave        to the right 30 cm while waving up and down ± 5 cm, two periods          no
square      right, down, left, up, 18 cm sides                                       yes
letter_v    down-right to the bottom 20 cm below, up-right to the top (24 cm wide)   no
spiral      one and a half turns inwards, radius 12 cm down to 3.6 cm                no
check_mark  down-right 8 cm across and 10 cm down, then up-right 22 cm across, 24 up   no
letter_n    up 20 cm, diagonal down-right to 16 cm right, up 20 cm                    no
diamond     corners right, bottom, left, top: 22 cm wide, 26 cm tall                  yes
letter_s    two half circles of radius 7 cm, the second turning the other way         no
pentagon    five sides of 14 cm, turning left                                         yes
letter_m    up 20 cm, down-right to the middle 12 cm below, up-right, down 20 cm      no
letter_c    three quarters of a circle of radius 9 cm, from its upper right round     no
            the top and the left to its lower right
==========  ======================================================================  ========

A third family (:data:`FRESH_SHAPES`: pentagon, letter M, letter C) was defined after v8, before
any result of v9 on shapes nobody enrolled, and is only ever performed as unknown motion.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable

import numpy as np

__all__ = ["DEV_SHAPES", "DRAWN_SHAPES", "FRESH_SHAPES", "HELDOUT_SHAPES", "shape_strokes"]

#: A polyline's corners (k, 2) in (right, up) coordinates [m] of the nominal shape, or a curve
#: ``s (n,) -> (n, 2)`` with ``s`` in [0, 1]; ``duration`` [s] per side, or of the curve.
DRAWN_SHAPES: dict[str, dict] = {
    "zigzag": {"corners": [(0, 0), (0.24, 0), (0, -0.18), (0.24, -0.18)], "duration": 0.6},
    "triangle": {"corners": [(0, 0), (0.24, 0), (0.12, 0.20), (0, 0)], "duration": 0.6},
    "letter_l": {"corners": [(0, 0), (0, -0.22), (0.14, -0.22)], "duration": 0.6},
    "wave": {"curve": "wave", "duration": 1.6},
    "square": {"corners": [(0, 0), (0.18, 0), (0.18, -0.18), (0, -0.18), (0, 0)], "duration": 0.55},
    "letter_v": {"corners": [(0, 0), (0.12, -0.20), (0.24, 0)], "duration": 0.6},
    "spiral": {"curve": "spiral", "duration": 2.2},
    "check_mark": {"corners": [(0, 0), (0.08, -0.10), (0.30, 0.14)], "duration": 0.6},
    "letter_n": {"corners": [(0, 0), (0, 0.20), (0.16, 0), (0.16, 0.20)], "duration": 0.55},
    "diamond": {"corners": [(0, 0), (-0.11, -0.13), (0, -0.26), (0.11, -0.13), (0, 0)],
                "duration": 0.5},
    "letter_s": {"curve": "letter_s", "duration": 1.4},
    "pentagon": {"corners": [(0, 0), (0.14, 0), (0.1833, 0.1331), (0.07, 0.2154), (-0.0433, 0.1331), (0, 0)],
                 "duration": 0.45},
    "letter_m": {"corners": [(0, 0), (0, 0.20), (0.09, 0.08), (0.18, 0.20), (0.18, 0)],
                 "duration": 0.5},
    "letter_c": {"curve": "letter_c", "duration": 1.2},
}

#: Shapes for development: to enroll as a new gesture and to tune rejection on.
DEV_SHAPES = ("zigzag", "triangle", "letter_l", "wave", "square", "letter_v", "spiral")
#: Shapes kept out of every choice: only ever performed as motions nobody enrolled.
HELDOUT_SHAPES = ("check_mark", "letter_n", "diamond", "letter_s")
#: A third family, defined after v8 and only ever performed as motions nobody enrolled.
FRESH_SHAPES = ("pentagon", "letter_m", "letter_c")


def _wave(s: np.ndarray) -> np.ndarray:
    return np.stack([0.30 * s, 0.05 * np.sin(4 * math.pi * s)], axis=1)


def _spiral(s: np.ndarray) -> np.ndarray:
    r = 0.12 * (1 - 0.7 * s)
    a = 3 * math.pi * s
    return np.stack([r * np.cos(a) - 0.12, r * np.sin(a)], axis=1)


def _letter_s(s: np.ndarray) -> np.ndarray:
    # counter-clockwise round the upper bowl from its upper right (45°) to its bottom, then
    # clockwise round the lower bowl from its top to its lower left (-135°)
    upper = s < 0.5
    a = np.where(upper, math.pi / 4 + 1.25 * math.pi * (2 * s),
                 math.pi / 2 - 1.25 * math.pi * (2 * s - 1))
    cy = np.where(upper, 0.07, -0.07)
    return np.stack([0.07 * np.cos(a), cy + 0.07 * np.sin(a)], axis=1)


def _letter_c(s: np.ndarray) -> np.ndarray:
    # counter-clockwise from 45° round the top and the left to 315°
    a = math.pi / 4 + 1.5 * math.pi * s
    return np.stack([0.09 * np.cos(a), 0.09 * np.sin(a)], axis=1)


_CURVES: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "wave": _wave, "spiral": _spiral, "letter_s": _letter_s, "letter_c": _letter_c}


def shape_strokes(name: str) -> list[Callable[[np.ndarray], np.ndarray]]:
    """The strokes of a drawn shape as planar offsets from its start.

    Parameters
    ----------
    name : str
        A key of :data:`DRAWN_SHAPES`.

    Returns
    -------
    list of callable
        One function per stroke, mapping progress ``s`` (n,) in [0, 1] to offsets (n, 2) [m] in
        (right, up) coordinates of the nominal shape, measured from the shape's first point.
    """
    spec = DRAWN_SHAPES[name]
    if "curve" in spec:
        curve = _CURVES[spec["curve"]]
        origin = curve(np.zeros(1))[0]
        return [lambda s, c=curve, o=origin: c(np.asarray(s, dtype=np.float64)) - o]
    corners = np.asarray(spec["corners"], dtype=np.float64)
    return [lambda s, a=a, b=b: a + np.asarray(s, dtype=np.float64)[:, None] * (b - a)
            for a, b in itertools.pairwise(corners)]
