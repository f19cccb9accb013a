"""Which way the hand turns in its own frame (``RecognizerConfig.hand_frame``, v29): a motion
that turns the hand about another axis than a gesture's takes must match more closely to pass
for it.

The tests check the measure (unchanged by the world frame, turned by the tracker's place in the
hand, none for a hand that hardly turns), the recognizer that learns a cone of axes from takes
that agree (by default) and the spotter that weighs a candidate outside it ``OFF_CONE_FACTOR``
times farther, whichever of its two cones it leaves.
"""

from __future__ import annotations

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.hand_direction import MIN_TURN, OFF_CONE_FACTOR, hand_turn
from framefree.online.learned import LearnedSettings
from framefree.online.segmentation import Unit
from framefree.online.spotting import Spotter

DT = 0.02
frames = st.builds(lambda xi: se3.pose_from_twist(np.asarray(xi)),
                   st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6))


def _min_jerk(n: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, n)
    return 10 * s**3 - 15 * s**4 + 6 * s**5


def _turning(degrees: float, axis: tuple[float, float, float] = (0.0, 0.0, 1.0), n: int = 60,
             rest: int = 0) -> np.ndarray:
    """Poses (n + 2 rest, 4, 4) of a hand that moves 30 cm along x while turning ``degrees``
    about ``axis`` of its first pose, with ``rest`` still poses before and after."""
    s = np.r_[np.zeros(rest), _min_jerk(n), np.ones(rest)]
    u = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    P = np.repeat(np.eye(4)[None], s.size, axis=0)
    P[:, 0, 3] = 0.3 * s
    for k, a in enumerate(math.radians(degrees) * s):
        P[k, :3, :3] = se3.rotation_from_vector(a * u)
    return P


@settings(max_examples=10, deadline=None)
@given(X=frames)
def test_the_hand_turn_does_not_depend_on_the_world_frame(X):
    P = _turning(90.0)
    assert hand_turn(X @ P) == pytest.approx(hand_turn(P), abs=1e-9)


@settings(max_examples=10, deadline=None)
@given(G=frames)
def test_a_tracker_turned_in_the_hand_turns_the_axis(G):
    """``T → T G``: the turn is seen from the turned frame, its axis turns by ``Gᵀ`` (the
    tracker's offset in the hand does not matter)."""
    P = _turning(90.0, axis=(0.2, -0.5, 1.0))
    assert hand_turn(P @ G) == pytest.approx(G[:3, :3].T @ hand_turn(P), abs=1e-9)


def test_the_axis_of_the_largest_turn_with_its_sense():
    assert hand_turn(_turning(90.0)) == pytest.approx([0, 0, 1], abs=1e-12)
    assert hand_turn(_turning(-90.0)) == pytest.approx([0, 0, -1], abs=1e-12)
    # out and back: the axis of the turn out, where the hand is turned farthest
    out_and_back = np.concatenate([_turning(60.0), _turning(60.0)[::-1]])
    assert hand_turn(out_and_back) == pytest.approx([0, 0, 1], abs=1e-12)
    half = hand_turn(_turning(180.0, axis=(1.0, 1.0, 0.0)))
    assert abs(half @ np.array([1.0, 1.0, 0.0]) / math.sqrt(2)) == pytest.approx(1.0, abs=1e-6)


def test_no_axis_for_a_hand_that_hardly_turns():
    assert hand_turn(_turning(0.9 * MIN_TURN)) is None
    assert hand_turn(_turning(1.1 * MIN_TURN)) is not None
    assert hand_turn(_turning(90.0)[:1]) is None
    assert hand_turn(_turning(5.0), min_angle=4.0) is not None


def _turning_takes(n: int, degrees: float, seed: int) -> list[Trajectory]:
    """``n`` takes of a 30 cm stroke that turns the hand about its z axis, each in its own
    world frame, with a little spread in the axis and the amount."""
    rng = np.random.default_rng(seed)
    takes = []
    for _ in range(n):
        axis = np.array([0.0, 0.0, 1.0]) + 0.15 * rng.standard_normal(3)
        P = _turning(degrees * rng.uniform(0.8, 1.2), tuple(axis), n=int(rng.integers(50, 70)),
                     rest=20)
        P[:, :3, 3] += 0.0005 * rng.standard_normal((P.shape[0], 3))  # sensor noise
        X = se3.pose_from_twist(rng.uniform(-3.0, 3.0, 6))
        takes.append(Trajectory.from_poses(DT * np.arange(P.shape[0]), X @ P))
    return takes


@pytest.fixture(scope="module")
def turning_recognizers():
    """Twelve turning strokes, enrolled with and without ``hand_frame``."""
    takes = _turning_takes(12, 90.0, 3)
    return [Recognizer.from_trajectories(takes, ["turn"] * 12, threshold=0.3, hand_frame=flag,
                                         cone_takes=12)
            for flag in (True, False)]


def test_the_recognizer_learns_a_cone_of_axes_only_with_hand_frame(turning_recognizers):
    with_frame, without = turning_recognizers
    *mean, angle = with_frame.learned_.rotation_limits["turn"]
    assert mean == pytest.approx([0, 0, 1], abs=0.1)
    assert 0 < angle < 60
    assert with_frame.learned_.provenance.rules["rotation_limits"].endswith("hand_turn")
    assert with_frame.spotter.rotations.active
    assert without.learned_.rotation_limits is None
    assert not without.spotter.rotations.active


def test_no_cone_of_axes_from_takes_that_hardly_turn():
    takes = _turning_takes(12, 0.5 * MIN_TURN, 4)
    rec = Recognizer.from_trajectories(takes, ["slide"] * 12, threshold=0.3, cone_takes=12)
    assert rec.learned_.rotation_limits == {}
    assert not rec.spotter.rotations.active


def test_the_cones_of_axes_go_to_json_and_back(turning_recognizers):
    rec = turning_recognizers[0]
    learned = LearnedSettings.from_dict(json.loads(json.dumps(rec.learned_.to_dict())))
    assert learned.rotation_limits == rec.learned_.rotation_limits


def _turning_spotter(degrees: float, directions: np.ndarray | None) -> tuple[Spotter, object]:
    """A spotter of two models with cones of axes about the tracker's +z (model 0) and −z
    (model 1) and, optionally, cones of hand directions; its descriptor (a stub) puts every
    candidate at distance 0.5 from both. The buffer holds one stroke along x that turns the
    hand ``degrees`` about z."""
    P = _turning(degrees, n=51)
    classifier = SimpleNamespace(models=[np.zeros((5, 1))] * 2, pruning=False,
                                 distances=lambda t, poses: (np.array([0.5, 0.5]), 0.3))
    spotter = Spotter(classifier, np.ones(2), margin=0, direction_limits=directions,
                      rotation_limits=np.array([[0, 0, 1.0, 30.0], [0, 0, -1.0, 30.0]]))
    buffer = SimpleNamespace(oldest=0, slice=lambda a, b: (DT * np.arange(a, b + 1), P[a:b + 1]))
    spotter.add_unit(Unit(0, 50, 0.0, 1.0, 0.5, True))
    return spotter, buffer


@pytest.mark.parametrize("degrees, model", [(90.0, 0), (-90.0, 1)])
def test_a_candidate_turning_about_another_axis_counts_farther(degrees, model):
    spotter, buffer = _turning_spotter(degrees, None)
    (c,) = spotter.candidates(buffer)
    assert c.model == model
    other = 1 - model
    assert spotter.last_distances[model] == pytest.approx(0.5)
    assert spotter.last_distances[other] == pytest.approx(OFF_CONE_FACTOR * 0.5)


def test_outside_either_cone_counts_farther_once():
    """Outside the cone of axes and the cone of directions: the factor once, not twice."""
    both_away = np.array([[-1.0, 0, 0, 10.0], [-1.0, 0, 0, 10.0]])  # every model moves along −x
    spotter, buffer = _turning_spotter(90.0, both_away)
    spotter.candidates(buffer)
    assert spotter.last_distances == pytest.approx([OFF_CONE_FACTOR * 0.5] * 2)


def test_a_hand_that_hardly_turns_is_not_weighed():
    spotter, buffer = _turning_spotter(0.5 * MIN_TURN, None)
    spotter.candidates(buffer)
    assert spotter.last_distances == pytest.approx([0.5, 0.5])
