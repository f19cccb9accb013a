"""The proportions of a shape drawn with corners: how long each stroke is against the next.

A check mark is a short stroke down and a long stroke up; two sides of a square, a letter V
and a letter L are two strokes of about equal length. Their corners turn by about the same
angle, and the descriptor's time warping stretches one stroke and shrinks the other freely, so
the distance alone does not tell them apart: on the replica's development people, 11 of a
taught check mark's 15 false positives were the halves of squares and Vs, at 0.64-0.99 τ.

Where a gesture's takes agree on their number of corners, the strokes between the corners have
proportions, and a candidate with as many corners must keep them within ``factor`` of the
takes' range (:func:`proportion_limits`). A stroke's length is the sum of its units'
:attr:`~framefree.online.segmentation.Unit.chord` norms (screw-like vectors: a change of world
frame does not change them), so a hesitation inside a stroke does not change it. A candidate
with another number of corners is not limited here (the corner limit judges it). See
``docs/online.md`` (What it learns from the takes).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .span_shape import is_corner

if TYPE_CHECKING:
    from .segmentation import Unit

__all__ = ["ProportionTable", "proportion_limits", "proportions", "stroke_lengths"]

#: Shortest stroke [m of screw path] a proportion is taken against (a stroke of no length).
_SHORTEST = 1e-6


def stroke_lengths(units: Sequence[Unit], angle: float) -> np.ndarray:
    """Length [m] of each stroke of a span of consecutive units (K + 1,) for its K corners
    (:func:`~framefree.online.span_shape.is_corner` sharper than ``angle`` [deg]): the sum of
    the chord norms of the units between two corners (an unknown chord counts 0)."""
    lengths = [0.0]
    for k, unit in enumerate(units):
        if k and is_corner(units[k - 1], unit, angle):
            lengths.append(0.0)
        if unit.chord is not None:
            lengths[-1] += float(np.linalg.norm(unit.chord))
    return np.array(lengths)


def proportions(units: Sequence[Unit], angle: float) -> np.ndarray:
    """Natural log of each stroke's length over the next one's (K,) for a span of K corners
    (:func:`stroke_lengths`); empty without a corner."""
    lengths = np.maximum(stroke_lengths(units, angle), _SHORTEST)
    return np.log(lengths[:-1] / lengths[1:])


def proportion_limits(values: Sequence[np.ndarray], factor: float, most_corners: int = 1
                      ) -> list[tuple[float, float]] | None:
    """Limits on a gesture's proportions from its takes' (``values``, each (K,) of
    :func:`proportions`): for each pair of consecutive strokes, the smallest and largest length
    ratio of the takes, divided and multiplied by ``factor`` (≥ 1); ``None`` (no limit) unless
    at least two takes agree on K corners, 1 ≤ K ≤ ``most_corners``.

    On the real Vive recordings of six people (``benchmarks/real_proportions.py``), limits from
    one person's takes that agree on one corner hold 86 of the other people's 90 performances
    with one corner at a factor of 2, while those agreeing on two corners (a golf swing, an
    uppercut: swings whose reversals each person places elsewhere) hold only 104 of 133: hence
    one corner, a V-like shape, by default."""
    n = len(values[0]) if values else 0
    if len(values) < 2 or len({len(v) for v in values}) > 1 or not 1 <= n <= most_corners:
        return None
    logs = np.vstack([np.asarray(v, dtype=float) for v in values])
    widen = math.log(factor)
    return [(math.exp(lo - widen), math.exp(hi + widen))
            for lo, hi in zip(logs.min(axis=0), logs.max(axis=0), strict=True)]


class ProportionTable:
    """Every model's proportion limits, checked against candidates at once.

    Parameters
    ----------
    limits : sequence of (list of (float, float)) or None, shape (M,)
        Per model, the (smallest, largest) length ratio of each pair of consecutive strokes of
        its gesture (:func:`proportion_limits`), or ``None`` for no limit.
    """

    def __init__(self, limits: Sequence[Sequence[tuple[float, float]] | None]) -> None:
        n_models = len(limits)
        #: the number of corners each model's limits hold for (M,); -1: no limit
        self.corners = np.array([-1 if x is None else len(x) for x in limits], dtype=np.int64)
        self.width = int(max(self.corners.max(initial=0), 0))
        self.lower = np.full((n_models, self.width), -np.inf)
        self.upper = np.full((n_models, self.width), np.inf)
        for j, x in enumerate(limits):
            if x:
                ratios = np.log(np.asarray(x, dtype=float))
                self.lower[j, :len(x)], self.upper[j, :len(x)] = ratios[:, 0], ratios[:, 1]

    @property
    def active(self) -> bool:
        """Whether any model is limited."""
        return self.width > 0

    def padded(self, values: Sequence[np.ndarray] | np.ndarray) -> np.ndarray:
        """Candidates' :func:`proportions`, one row each, cut or padded to the table's width
        (n, W); a single candidate's (K,) gives (W,)."""
        if isinstance(values, np.ndarray) and values.ndim == 1:
            return self.padded([values])[0]
        out = np.zeros((len(values), self.width))
        for i, v in enumerate(values):
            n = min(len(v), self.width)
            out[i, :n] = np.asarray(v, dtype=float)[:n]
        return out

    def passes(self, j: int | slice, corners: np.ndarray | int, padded: np.ndarray) -> np.ndarray:
        """Whether candidates with ``corners`` (n,) and :meth:`padded` proportions (n, W) keep
        model ``j``'s limits (or a single candidate every model's, ``j`` a slice): those with
        another number of corners than the limits hold for always do."""
        corners = np.asarray(corners)
        if not self.active:
            return np.ones(np.broadcast(corners, self.corners[j]).shape, dtype=bool)
        inside = ((padded >= self.lower[j]) & (padded <= self.upper[j])).all(axis=-1)
        return (corners != self.corners[j]) | inside
