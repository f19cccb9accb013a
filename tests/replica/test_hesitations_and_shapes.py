"""Hesitant people, performer styles and shapes drawn in the air: they move as documented."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.replica import (
    DEV_SHAPES,
    DRAWN_SHAPES,
    FRESH_SHAPES,
    HELDOUT_SHAPES,
    person,
    plan_gesture,
)
from framefree.replica.motion import Motion, hesitant_stroke, overlapped, stroke, translation_path
from framefree.replica.people import POPULATION, STYLES, styled
from framefree.replica.people_streams import take_session

LINE = translation_path(np.eye(4), lambda s: s[:, None] * np.array([0.3, 0.0, 0.0]))


def _speed(piece, dt: float = 0.005) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(0.0, piece.duration, dt)
    p = piece.fn(t)[:, :3, 3]
    return t[:-1], np.linalg.norm(np.diff(p, axis=0), axis=1) / dt


@settings(max_examples=30, deadline=None)
@given(at=st.floats(0.3, 0.7), pause=st.floats(0.1, 0.6), residual=st.floats(0.03, 0.2))
def test_a_hesitation_nearly_stops_the_hand_and_keeps_the_path(at, pause, residual) -> None:
    plain, hesitant = stroke(LINE, 1.0), hesitant_stroke(LINE, 1.0, 1.0, at, pause, residual)
    assert hesitant.duration > plain.duration
    np.testing.assert_allclose(hesitant.end, plain.end, atol=1e-9)
    np.testing.assert_allclose(hesitant.start, plain.start, atol=1e-12)
    t, v = _speed(hesitant)
    # in the middle of the slow phase the hand moves at about `residual` of the plain speed there
    mid = at * 1.0 + 0.12 + pause / 2
    _, v_plain = _speed(plain)
    assert v[np.searchsorted(t, mid)] <= 1.05 * residual * v_plain.max()
    assert v[np.searchsorted(t, mid)] > 0  # nearly stops: it does not stand still


def test_people_who_never_hesitate_perform_as_before_hesitations_existed() -> None:
    """Golden values computed with the replica before hesitations were modelled (commit 10d8cec):
    a person who never hesitates draws the same performance, and a hesitant person's other
    fields are those drawn then."""
    calm = person(1)
    assert calm.hesitation == 0.0
    plan = plan_gesture("go_left", np.random.default_rng(3), person=calm)
    assert [s.duration for s in plan.strokes] == pytest.approx(
        [0.4952467167821591, 0.054876538650618076, 0.5771172488396916], rel=1e-12)
    assert plan.strokes[-1].end[0, 3] == pytest.approx(0.26042032234102996, rel=1e-12)
    hesitant = person(3)
    assert hesitant.hesitation > 0
    assert (hesitant.size, hesitant.tempo, hesitant.variability) == pytest.approx(
        (1.2274027520114408, 1.3888243845033388, 0.8539521314299866), rel=1e-12)


def test_some_people_hesitate_and_their_strokes_last_longer() -> None:
    hesitant = [person(s) for s in range(40) if person(s).hesitation > 0]
    share = len(hesitant) / 40
    assert 0.15 < share < 0.6  # POPULATION["hesitant"] = 0.35
    lo, hi = POPULATION["hesitation"]
    assert all(lo <= p.hesitation <= hi for p in hesitant)
    always = replace(hesitant[0], hesitation=1.0)
    never = replace(hesitant[0], hesitation=0.0)
    slow = plan_gesture("go_down", np.random.default_rng(1), person=always).duration
    assert slow > plan_gesture("go_down", np.random.default_rng(1), person=never).duration


def test_styles_keep_the_body_and_change_the_movement() -> None:
    p = person(5)
    for name, style in STYLES.items():
        q = styled(p, name)
        assert (q.stature, q.grip_rotation, q.pause) == (p.stature, p.grip_rotation, p.pause)
        assert all(getattr(q, k) == v for k, v in style.items())
    with pytest.raises(ValueError, match="unknown style"):
        styled(p, "nervous")


def _square_sides(duration: float = 0.6) -> list:
    corners = np.array([[0, 0, 0], [0.2, 0, 0], [0.2, 0.2, 0], [0, 0.2, 0.05]], dtype=float)
    sides, pose = [], np.eye(4)
    for a, b in itertools.pairwise(corners):
        side = stroke(translation_path(pose, lambda s, d=b - a: s[:, None] * d), duration)
        sides.append(side)
        pose = side.end
    return sides


@settings(max_examples=25, deadline=None)
@given(overlap=st.floats(0.0, 0.6))
def test_fluent_strokes_keep_the_path_and_round_the_corners(overlap) -> None:
    """Superposed strokes end where the chained ones end and take ``overlap`` × a stroke less per
    corner; the hand stops at a corner only without overlap."""
    sides = _square_sides()
    chained, fluent = Motion(sides), overlapped(sides, overlap)
    np.testing.assert_allclose(fluent.end, chained.end, atol=1e-12)
    np.testing.assert_allclose(fluent.start, chained.pieces[0].start, atol=1e-12)
    assert fluent.duration == pytest.approx(chained.duration - 2 * overlap * 0.6)
    t, v = _speed(fluent, 0.002)
    corner = (t > 0.45) & (t < fluent.duration - 0.45)  # both corners, away from start and end
    slowest = v[corner].min() / v.max()
    if overlap == 0.0:
        t0 = np.arange(0.0, chained.duration, 0.05)
        np.testing.assert_allclose(fluent.fn(t0), chained.at(t0), atol=1e-12)
        assert slowest < 0.01
    elif overlap > 0.15:
        assert slowest > 0.05


def test_fluent_people_draw_without_stopping_and_the_rest_as_before() -> None:
    """Half the people draw fluently; every other field, and every HPM gesture, is what it was
    before fluent drawing was modelled (the golden values above), and a fluent person's drawn
    shapes are one superposed stroke."""
    people = [person(s) for s in range(40)]
    fluent = [p for p in people if p.coarticulation > 0]
    assert 0.3 < len(fluent) / 40 < 0.7  # POPULATION["fluent"] = 0.5
    lo, hi = POPULATION["coarticulation"]
    assert all(lo <= p.coarticulation <= hi for p in fluent)
    who = fluent[0]
    zigzag = plan_gesture("zigzag", np.random.default_rng(0), person=who)
    stopping = plan_gesture("zigzag", np.random.default_rng(0), person=replace(who, coarticulation=0.0))
    assert len(zigzag.strokes) == 1 and len(stopping.strokes) >= 3
    assert zigzag.duration < stopping.duration
    go_left = plan_gesture("go_left", np.random.default_rng(0), person=who)
    same = plan_gesture("go_left", np.random.default_rng(0), person=replace(who, coarticulation=0.0))
    assert [s.duration for s in go_left.strokes] == [s.duration for s in same.strokes]
    with pytest.raises(ValueError, match="coarticulation"):
        replace(who, coarticulation=1.0)
    with pytest.raises(ValueError, match="overlap"):
        overlapped(_square_sides(), -0.1)


def _closure(name: str, seed: int) -> float:
    plan = plan_gesture(name, np.random.default_rng(seed), person=person(seed))
    m = Motion(plan.strokes)
    P = m.at(np.arange(0.0, m.duration, 0.01))[:, :3, 3]
    return float(np.linalg.norm(P[-1] - P[0]) / np.linalg.norm(np.diff(P, axis=0), axis=1).sum())


@pytest.mark.parametrize("name", list(DRAWN_SHAPES))
def test_drawn_shapes_close_or_stay_open_as_documented(name: str) -> None:
    closes = name in ("triangle", "square", "diamond", "pentagon")
    for seed in range(3):
        c = _closure(name, seed)
        assert (c < 0.1) if closes else (c > 0.15), (name, seed, c)


def test_shape_families_are_disjoint() -> None:
    families = [set(DEV_SHAPES), set(HELDOUT_SHAPES), set(FRESH_SHAPES)]
    assert sum(len(f) for f in families) == len(set.union(*families))
    assert set.union(*families) == set(DRAWN_SHAPES)


def test_a_take_session_has_every_performance_and_the_ways_back() -> None:
    session = take_session("zigzag", person(2), n_takes=4, seed=1)
    assert [s.label for s in session.segments] == ["zigzag"] * 4
    kinds = [a.kind for a in session.activities]
    assert kinds.count("way back") == 3 and kinds.count("gesture") == 4
    with pytest.raises(ValueError, match="unknown gesture"):
        take_session("moonwalk", person(2))
