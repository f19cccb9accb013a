"""Turns: a triangle turns the same way at every corner, a Z turns back — in any world frame.

Two consecutive corners turn the same way when the oriented planes of their chords agree
(``plane_cosine`` > 0). The tests check the plane algebra, draw polylines stroke by stroke in
random world frames and mirror images, check the rule that forbids the kind a gesture's
demonstrations never make, the recognizer that applies it, and on real Vive recordings that other
people never show a turn one person's takes forbid.
"""

from __future__ import annotations

import numpy as np
import pytest
from drawing import DT, LEVELS, drawn_positions, drawn_takes, tracker_poses
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.benchmark.take_geometry import other_peoples, take_geometry
from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer, RecognizerConfig
from framefree.online.evaluation import run_stream
from framefree.online.limits import forbidden_turns
from framefree.online.segmentation import MotionSegmenter
from framefree.online.span_shape import ALTERNATING, SAME_SENSE, plane_cosine, turn_kinds
from real_data import MACHETE, SHIPPED_MACHETE

ZIGZAG = np.array([[0, 0, 0], [0.24, 0, 0], [0, -0.18, 0], [0.24, -0.18, 0]], float)
LETTER_U = np.array([[0, 0, 0], [0, -0.2, 0], [0.2, -0.2, 0], [0.2, 0, 0]], float)
TRIANGLE = np.array([[0, 0, 0], [0.24, 0, 0], [0.12, 0.2, 0], [0, 0, 0]], float)
SQUARE = np.array([[0, 0, 0], [0.18, 0, 0], [0.18, -0.18, 0], [0, -0.18, 0], [0, 0, 0]], float)
OUT_AND_BACK_TWICE = np.array([[0, 0, 0], [0.3, 0, 0], [0, 0.01, 0], [0.3, 0.02, 0]], float)

frames = st.builds(lambda xi: se3.pose_from_twist(np.asarray(xi)),
                   st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6))
MIRROR = np.diag([1.0, -1.0, 1.0, 1.0])  # a left-handed drawer's zigzag is an S-like Z


def _units(positions: np.ndarray, X: np.ndarray) -> list:
    seg = MotionSegmenter(LEVELS, L=0.1, dt=DT)
    return [u for k, T in enumerate(tracker_poses(positions, X)) if (u := seg.push(DT * k, T))]


def test_plane_cosine_of_turning_on_turning_back_and_no_plane():
    x, y, z = np.eye(3)
    assert plane_cosine(x, y, y, -x) == pytest.approx(1.0)  # left, then left again
    assert plane_cosine(x, y, y, x) == pytest.approx(-1.0)  # left, then back right
    assert plane_cosine(x, y, y, z) == pytest.approx(0.0)  # into another plane
    assert plane_cosine(x, 2 * x, y, x) == 0.0  # no turn, no plane


@settings(max_examples=25, deadline=None)
@given(vectors=st.lists(st.floats(-1.0, 1.0), min_size=24, max_size=24), X=frames)
def test_plane_cosine_does_not_see_the_world_frame(vectors, X):
    """A change of world frame turns both halves of every 6-vector heading alike."""
    a, b, c, d = np.reshape(vectors, (4, 6))
    R = X[:3, :3]
    a2, b2, c2, d2 = (np.concatenate([R @ v[:3], R @ v[3:]]) for v in (a, b, c, d))
    assert plane_cosine(a2, b2, c2, d2) == pytest.approx(plane_cosine(a, b, c, d), abs=1e-9)


@settings(max_examples=15, deadline=None)
@given(X=frames, hold=st.sampled_from([0.0, 0.06, 0.3]), mirrored=st.booleans())
def test_drawn_polygons_turn_one_way_and_a_zigzag_turns_back_in_any_frame(X, hold, mirrored):
    X = X @ MIRROR if mirrored else X
    assert turn_kinds(_units(drawn_positions(ZIGZAG, hold_s=hold), X), 60.0) == ALTERNATING
    for polygon in (LETTER_U, TRIANGLE, SQUARE):
        assert turn_kinds(_units(drawn_positions(polygon, hold_s=hold), X), 60.0) == SAME_SENSE


def test_reversals_and_single_corners_say_nothing():
    assert turn_kinds(_units(drawn_positions(OUT_AND_BACK_TWICE), np.eye(4)), 60.0) == 0
    assert turn_kinds(_units(drawn_positions(ZIGZAG[:3]), np.eye(4)), 60.0) == 0  # one corner
    assert turn_kinds([], 60.0) == 0


def test_a_turn_is_forbidden_only_where_the_demonstrations_agree():
    assert forbidden_turns([ALTERNATING] * 5) == SAME_SENSE
    assert forbidden_turns([SAME_SENSE] * 5) == ALTERNATING
    assert forbidden_turns([SAME_SENSE, SAME_SENSE, 0]) == 0  # a take without two corners
    assert forbidden_turns([SAME_SENSE | ALTERNATING] * 3) == 0
    assert forbidden_turns([ALTERNATING]) == 0  # one take says nothing about how others vary
    assert forbidden_turns([]) == 0


@pytest.fixture(scope="module")
def drawn_recognizer():
    rng = np.random.default_rng(3)
    takes = drawn_takes(ZIGZAG, 5, rng) + drawn_takes(TRIANGLE, 5, rng)
    labels = ["zigzag"] * 5 + ["triangle"] * 5
    return Recognizer.from_trajectories(takes, labels, turns=True), (takes, labels)


def test_the_recognizer_forbids_what_the_demonstrations_never_do(drawn_recognizer):
    rec, (takes, labels) = drawn_recognizer
    assert rec.learned_.forbidden_turns == {"zigzag": SAME_SENSE, "triangle": ALTERNATING}
    sp = rec.spotter
    j = rec.labels.index("zigzag")
    size = float(np.mean(sp.size_limits[j]))
    closure_ = 0.5 * (sp.opening_limits[j] + sp.closure_limits[j])
    ok = sp.admissible(j, np.full(4, closure_), np.full(4, size), np.full(4, 2),
                       np.array([0, ALTERNATING, SAME_SENSE, SAME_SENSE | ALTERNATING]))
    assert list(ok) == [True, True, False, False]
    # by default (v25) only the Z's limit applies: the triangle's takes never turn back, but
    # real people's swings that one person turns one way turn back in other people's hands
    off = Recognizer.from_trajectories(takes, labels, turns=False)
    kinds = np.array([SAME_SENSE, ALTERNATING])
    assert list(off.spotter.admissible(j, np.full(2, closure_), np.full(2, size), np.full(2, 2),
                                       kinds)) == [False, True]
    t = rec.labels.index("triangle")
    closed = 0.5 * (sp.opening_limits[t] + sp.closure_limits[t])
    assert off.spotter.admissible(t, np.full(2, closed), np.full(2, np.mean(sp.size_limits[t])),
                                  np.full(2, 2), kinds).all()
    blind = Recognizer.from_trajectories(takes, labels, turns=False, corners=False)
    assert blind.spotter.admissible(j, np.full(2, closure_), np.full(2, size), np.full(2, 2),
                                    kinds).all()


@pytest.fixture(scope="module")
def zigzag_alone():
    """The zigzag enrolled alone with one loose threshold for all: only the turns tell a U apart
    (with ``turns``, by default, and with no turn limit at all)."""
    takes = drawn_takes(ZIGZAG, 5, np.random.default_rng(3))
    return [Recognizer.from_trajectories(takes, ["zigzag"] * 5, threshold=0.2, **extra)
            for extra in ({"turns": True}, {}, {"forbidden_turns": {}})]


@settings(max_examples=5, deadline=None)
@given(X=frames)
def test_a_letter_u_as_large_as_the_zigzag_is_not_taken_for_it(zigzag_alone, X):
    """A U has the zigzag's size, corners and opening; it turns the same way at both corners."""
    rng = np.random.default_rng(7)
    for points, label in ((ZIGZAG, "zigzag"), (LETTER_U * 1.2, None)):
        P = drawn_positions(points + rng.uniform(-0.02, 0.02, points.shape) * [1, 1, 0])
        stream = Trajectory.from_poses(DT * np.arange(P.shape[0]), tracker_poses(P, X))
        fired = [[e.label for e in run_stream(rec, stream)[0] if e.label != "stop"]
                 for rec in zigzag_alone]
        expected = [label] if label else []
        assert fired == [expected, expected, ["zigzag"]]


def _real_turns() -> dict:
    """{(controller, person, gesture): [turn kinds of each take]} of the real Vive recordings."""
    return {key: [kinds for *_, kinds in takes] for key, takes in take_geometry(MACHETE).items()}


def test_real_people_turn_the_way_another_persons_takes_forbid():
    """Why ``turns`` is off by default (v17): on the real Vive recordings, where one person's
    takes all turn one way (the *golf swing*), other people's performances turn the other way
    (all six people, takes cut at v17's rest level: 20 of 50; the shipped subset keeps two takes
    of it per person, 0 of 8, too few to show it). The rule holds for drawn polygons, not for
    real people's gestures. No real person's takes always turn back (a Z's limit, which v25
    applies by default): every limit found forbids a turn back."""
    if MACHETE == SHIPPED_MACHETE:
        pytest.skip("the shipped subset's 8 golf swings are too few; needs the six people's data")
    turns = _real_turns()
    limits = checked = refused = 0
    for key, own in turns.items():
        never = forbidden_turns(own)
        if not never:
            continue
        assert never == ALTERNATING
        limits += 1
        others = other_peoples(turns, key)
        checked += len(others)
        refused += sum(bool(k & never) for k in others)
    assert limits >= 1 and checked >= 4
    assert refused > 0
    assert not RecognizerConfig().turns
