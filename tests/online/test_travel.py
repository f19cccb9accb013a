"""The travel limit (v18, v22): a candidate must move the hand, not only turn it, about as far as
its gesture's takes do. The size limit measures the screw path, to which a turn of the wrist adds
as much as a move of the hand; in real continuous motion (SFINGE3D) small reaches whose palm turned
as it stopped passed a swipe's size limit on their turn alone. Since v22 a gesture that moves the
hand must travel as far as its median take (over the size factor); one that turns the hand more
than it moves it keeps the takes' 10th percentile."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.datasets.people_layout import load_people
from framefree.online import Recognizer, SpottingConstants
from framefree.online.limits import (
    TURNING_PERCENTILE,
    gesture_travels,
    travel_limit,
    travel_percentiles,
    travel_shares,
)
from framefree.online.segmentation import SpeedLevels
from framefree.online.span_shape import closure, travel

RNG = np.random.default_rng(3)


def _arc(n: int = 60, radius: float = 0.2, turn: float = 1.0) -> np.ndarray:
    """Poses (n, 4, 4) of a hand drawing a quarter circle while its wrist turns by ``turn`` rad."""
    s = np.linspace(0.0, 1.0, n)
    axis = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    poses = np.tile(np.eye(4), (n, 1, 1))
    for k, x in enumerate(s):
        a = 0.5 * math.pi * x
        poses[k, :3, 3] = radius * np.array([math.cos(a), math.sin(a), 0.1 * x])
        poses[k, :3, :3] = se3.rotation_from_vector(axis * turn * x)
    return poses


@settings(max_examples=25, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi), st.floats(-2.0, 2.0))
def test_travel_does_not_depend_on_the_world_frame(a, b, shift):
    poses = _arc()
    R = se3.rotation_from_vector(np.array([math.cos(a), math.sin(a), 0.3]) / math.hypot(1.0, 0.3) * b)
    G = np.eye(4)
    G[:3, :3] = R
    G[:3, 3] = [shift, -shift, 0.5 * shift]
    moved = G @ poses
    assert travel(moved) == pytest.approx(travel(poses), rel=1e-9)


def test_a_turn_in_place_travels_nowhere():
    """A wrist that turns while the hand stays has a screw path but no travel."""
    poses = np.tile(np.eye(4), (60, 1, 1))
    for k in range(60):
        poses[k, :3, :3] = se3.rotation_from_vector(np.array([0.0, 0.0, 1.0]) * k / 59 * 2.0)
    poses[:, :3, 3] += 1e-4 * RNG.standard_normal((60, 3))  # sensor jitter
    assert travel(poses) < 0.01
    assert closure(poses, 0.1) > 0.9  # it moved on the screw path: it went one way


def test_travel_is_the_path_length_of_a_smooth_motion():
    poses = _arc(n=400, turn=0.0)
    expected = math.hypot(0.5 * math.pi * 0.2, 0.02)  # a helix-like quarter circle
    assert travel(poses, presmooth=1) == pytest.approx(expected, rel=1e-3)


def test_the_travel_limit_is_a_small_take_over_the_factor():
    travels = [0.2, 0.5, 0.55, 0.6, 0.7]
    assert travel_limit(travels, 1.5) == pytest.approx(np.percentile(travels, 10) / 1.5)
    assert travel_limit([], 1.5) == 0.0
    # one take far smaller than the others hardly moves it
    assert travel_limit([0.01] + [0.5] * 19, 1.5) > 0.3


def _take(motion: str, seconds: float = 1.2, rest: float = 0.6, dt: float = 0.02,
          scale: float = 1.0) -> Trajectory:
    """A take that rests, performs ``motion`` (``"stroke"``: the hand moves 0.4 m in a line
    while the wrist turns a little; ``"turn"``: the forearm turns by 90° about its own axis, the
    tracker 4 cm off it), its lengths times ``scale``, with a minimum-jerk profile, and rests
    again."""
    n_rest, n_move = round(rest / dt), round(seconds / dt)
    x = np.linspace(0.0, 1.0, n_move)
    x = 10 * x**3 - 15 * x**4 + 6 * x**5
    x = np.concatenate([np.zeros(n_rest), x, np.ones(n_rest)])
    poses = np.tile(np.eye(4), (x.size, 1, 1))
    axis = np.array([1.0, 0.0, 0.0])
    if motion == "stroke":
        poses[:, :3, 3] = x[:, None] * np.array([0.0, 0.4 * scale, 0.0])
        poses[:, :3, :3] = se3.rotation_from_vector(axis[None] * 0.2 * x[:, None])
    else:
        R = se3.rotation_from_vector(axis[None] * 0.5 * math.pi * x[:, None])
        poses[:, :3, :3] = R
        poses[:, :3, 3] = R @ np.array([0.0, 0.04 * scale, 0.0])
    poses[:, :3, 3] += 2e-4 * RNG.standard_normal((x.size, 3))
    return Trajectory.from_poses(dt * np.arange(x.size), poses)


def test_a_stroke_moves_the_hand_and_a_forearm_turn_turns_it():
    """The share of the screw path that is the hand's path: about 1 for a stroke, small for a
    forearm turn, whatever the world frame."""
    takes = [_take("stroke"), _take("stroke", seconds=0.9), _take("turn"), _take("turn", 0.8)]
    labels = ["swipe", "swipe", "turn", "turn"]
    shares = travel_shares(takes, labels, SpeedLevels(0.02, 0.03), 0.1)
    moving_share = SpottingConstants().moving_share
    assert min(shares["swipe"]) > 0.8
    assert max(shares["turn"]) < moving_share
    G = np.eye(4)
    G[:3, :3] = se3.rotation_from_vector(np.array([0.3, -1.1, 0.4]))
    G[:3, 3] = [1.0, -2.0, 0.5]
    moved = [Trajectory.from_poses(t.t, G @ t.poses()) for t in takes]
    again = travel_shares(moved, labels, SpeedLevels(0.02, 0.03), 0.1)
    for g in shares:
        assert again[g] == pytest.approx(shares[g], rel=1e-6)


def test_a_gesture_that_moves_the_hand_must_travel_as_far_as_a_typical_take():
    percentiles = travel_percentiles({"swipe": [0.9, 1.0, 1.1], "turn": [0.3, 0.35, 0.6],
                                      "none": []}, 50.0, 0.5)
    assert percentiles == {"swipe": 50.0, "turn": TURNING_PERCENTILE, "none": TURNING_PERCENTILE}
    travels = [0.25, 0.3, 0.35, 0.4, 0.5]
    assert travel_limit(travels, 1.5, percentiles["swipe"]) == pytest.approx(0.35 / 1.5)
    # the median take sets it: a small free stroke of 0.2 m is no longer a swipe
    assert travel_limit(travels, 1.5, 50.0) > 0.2 > travel_limit(travels, 1.5, 10.0)


def test_the_recognizer_learns_each_gestures_limit_by_its_share():
    scales = (0.5, 0.75, 1.0, 1.25, 1.5)  # takes of different sizes: the percentiles differ
    takes = [_take("stroke", seconds=0.8 + 0.1 * k, scale=x) for k, x in enumerate(scales)]
    takes += [_take("turn", seconds=0.8 + 0.1 * k, scale=x) for k, x in enumerate(scales)]
    labels = ["swipe"] * 5 + ["turn"] * 5
    rec = Recognizer.from_trajectories(takes, labels)
    levels = SpeedLevels(rec.learned_.rest_speed, rec.learned_.move_speed)
    k = rec.config.constants
    travels = gesture_travels(takes, labels, levels, 0.1, k.dt)
    limits = rec.learned_.travel_limits
    factors = (k.size_factor, k.size_reach)  # the size limit's factor, or its reach further down
    assert any(limits["swipe"] == pytest.approx(np.median(travels["swipe"]) / f) for f in factors)
    assert any(limits["turn"] == pytest.approx(np.percentile(travels["turn"], TURNING_PERCENTILE)
                                               / f) for f in factors)
    # and not the other way round: with these sizes no factor makes the two percentiles agree
    assert not any(limits["swipe"] == pytest.approx(
        np.percentile(travels["swipe"], TURNING_PERCENTILE) / f) for f in factors)
    assert not any(limits["turn"] == pytest.approx(np.median(travels["turn"]) / f) for f in factors)


@pytest.fixture(scope="module")
def vive():
    """The right controller of the shipped real Vive recordings."""
    people = load_people("tests/data/machete_vive")
    return [(r.person, r.gesture, r.sample.trackers[0]) for r in people]


def test_other_people_travel_farther_than_one_persons_limit(vive):
    """Real people: the limit learned from one person's takes admits the other person's whole
    gestures (the same rule the recognizer learns with, measured on the live cut): every one of
    these gestures moves the hand, so each limit is the median take over the size factor."""
    persons = sorted({p for p, _, _ in vive})
    assert len(persons) == 2
    rec = Recognizer.from_trajectories([t for _, _, t in vive], [g for _, g, _ in vive])
    levels = SpeedLevels(rec.learned_.rest_speed, rec.learned_.move_speed)
    k = rec.config.constants
    refused = total = 0
    for me, other in (persons, persons[::-1]):
        mine = [(g, t) for p, g, t in vive if p == me]
        theirs = [(g, t) for p, g, t in vive if p == other]
        trajectories, labels = [t for _, t in mine], [g for g, _ in mine]
        percentiles = travel_percentiles(travel_shares(trajectories, labels, levels, 0.1, k.dt),
                                         k.travel_percentile, k.moving_share)
        assert set(percentiles.values()) == {k.travel_percentile}
        limits = {g: travel_limit(v, k.size_factor, percentiles[g]) for g, v in gesture_travels(
            trajectories, labels, levels, 0.1, k.dt).items()}
        measured = gesture_travels([t for _, t in theirs], [g for g, _ in theirs], levels, 0.1, k.dt)
        for g, values in measured.items():
            refused += sum(v < limits.get(g, 0.0) for v in values)
            total += len(values)
    assert total >= 20
    assert refused <= 0.05 * total


def test_the_spotter_refuses_a_candidate_that_only_turns(vive):
    rec = Recognizer.from_trajectories([t for _, _, t in vive], [g for _, g, _ in vive])
    sp = rec.spotter
    assert np.all(sp.travel_limits > 0)
    j = 0
    lo, hi = sp.size_limits[j]
    size = 0.5 * (lo + min(hi, 4 * lo))
    ok = sp.admissible(j, np.array([0.5, 0.5]), np.array([size, size]),
                       travels=np.array([0.5 * sp.travel_limits[j], 2 * sp.travel_limits[j]]))
    closes = sp.admissible(j, np.array([0.5, 0.5]), np.array([size, size]))
    assert list(ok) == [False, bool(closes[1])]
    # switched off with the size limit
    off = Recognizer.from_trajectories([t for _, _, t in vive], [g for _, g, _ in vive], size=False)
    assert np.all(off.spotter.travel_limits == 0)


@pytest.mark.parametrize("share", [-0.1, math.inf, math.nan])
def test_a_moving_share_must_be_a_finite_number_at_least_zero(share):
    with pytest.raises(ValueError, match="moving_share"):
        SpottingConstants(moving_share=share)
