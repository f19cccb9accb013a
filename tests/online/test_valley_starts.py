"""Candidates that start without a rest (``SpottingConstants.valley_starts``, on by default
since v29; docs/online-history.md, *Session 35* and *v29*). On real streams a gesture often
begins straight out of other motion, at the speed minimum between two strokes, where no rest or
dip below the rest level starts a candidate. With ``valley_starts`` a candidate also starts
there, in the tier of the brief starts."""

from __future__ import annotations

import numpy as np
import pytest
from drawing import DT, circle_positions, min_jerk, swipe_and_circle_takes

from framefree.online import Recognizer

A = np.array([0.0, 0.0, 0.0])
B = np.array([0.35, 0.0, 0.0])


@pytest.fixture(scope="module")
def takes():
    return swipe_and_circle_takes(11, np.array([A, B]))


def _circle_into_stroke(overlap: float = 0.25) -> np.ndarray:
    """Positions (n, 3): rest, a circle, and a stroke sideways that begins ``overlap`` × its
    duration before the circle ends (the hand slows between them without resting), rest."""
    rest = round(1.0 / DT)
    circle = circle_positions(radius=0.12, duration=2.0)[rest:-rest]
    n = round(0.6 / DT)
    start = len(circle) - round(overlap * n)
    P = np.repeat(circle[-1:], start + n, axis=0)
    P[:len(circle)] = circle
    share = np.zeros(start + n)
    share[start:] = min_jerk(n)
    P += share[:, None] * np.array([0.0, 0.35, 0.0])
    return np.concatenate([np.repeat(P[:1], rest, axis=0), P, np.repeat(P[-1:], rest, axis=0)])


def _candidates(takes, **settings):
    """The recognizer and every candidate it classified on the circle-into-stroke path."""
    rec = Recognizer.from_trajectories(*takes, **settings)
    rec.background = False
    rec.spotter.log = []
    P = _circle_into_stroke()
    q = np.array([1.0, 0.0, 0.0, 0.0])
    for k, p in enumerate(P):
        rec.push(DT * k, p, q)
    rec.finish()
    return rec, rec.spotter.log


def test_a_stroke_straight_out_of_a_circle_starts_a_candidate_only_with_valley_starts(takes):
    rec, found = _candidates(takes, valley_starts=True)
    rest_level = rec.segmenter.levels.rest
    P = _circle_into_stroke()
    speed = np.linalg.norm(np.diff(P, axis=0), axis=1) / DT
    moving = np.flatnonzero(speed > rest_level)
    # the premise: the hand never rests between the circle and the stroke
    assert np.all(np.diff(moving) == 1)
    starts = {round(c.start_t, 2) for c in found}
    late = [c for c in found if not c.after_rest]
    assert late, "no candidate starts at the speed minimum"
    assert all(c.start_t > 2.0 for c in late)  # after the circle, where the stroke begins
    _, without = _candidates(takes, valley_starts=False)
    assert {round(c.start_t, 2) for c in without} < starts
    assert all(c.after_rest for c in without)


def test_valley_starts_is_on_by_default_and_a_constant(takes):
    rec = Recognizer.from_trajectories(*takes)
    assert rec.spotter.valley_starts is True
    assert not Recognizer.from_trajectories(*takes, valley_starts=False).spotter.valley_starts
