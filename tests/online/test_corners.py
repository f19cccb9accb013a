"""Corners: a square drawn in the air is not a circle, whatever the frame and however hesitant.

A corner is a turn of the hand's heading of more than ``corner_angle`` between two movement units.
The tests draw polylines and circles stroke by stroke (minimum-jerk strokes, the hand slowing
down at every corner), cut them with the live segmenter and count corners, in random world
frames; then check the recognizer's corner limits and admissibility rule, and on real Vive
recordings that other people stay within a limit set from one person's takes.
"""

from __future__ import annotations

import numpy as np
import pytest
from drawing import (
    DT,
    LEVELS,
    circle_positions,
    drawn_positions,
    drawn_takes,
    fluent_positions,
    tracker_poses,
)
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.benchmark.take_geometry import other_peoples, take_geometry
from framefree.core import se3
from framefree.datasets.layout import load_model_recordings
from framefree.online import Recognizer, RecognizerConfig, SpottingConstants
from framefree.online.limits import corner_limit, recording_units
from framefree.online.rest_levels import speed_levels
from framefree.online.segmentation import MotionSegmenter, SpeedLevels, Unit, heading
from framefree.online.span_shape import corner_count, is_corner, turn_angle
from framefree.replica import replica_path
from framefree.replica.people import person
from framefree.replica.people_streams import take_session
from real_data import MACHETE, SHIPPED_MACHETE
from replica_recognizer import replica_recognizer


def _corners(positions: np.ndarray, X: np.ndarray | None = None, angle: float = 60.0) -> int:
    X = np.eye(4) if X is None else X
    seg = MotionSegmenter(LEVELS, L=0.1, dt=DT)
    poses = tracker_poses(positions, X)
    units = [u for k, T in enumerate(poses) if (u := seg.push(DT * k, T)) is not None]
    return corner_count(units, angle)


SQUARE = np.array([[0, 0, 0], [0.18, 0, 0], [0.18, -0.18, 0], [0, -0.18, 0], [0, 0, 0]], float)
ZIGZAG = np.array([[0, 0, 0], [0.24, 0, 0], [0, -0.18, 0], [0.24, -0.18, 0]], float)
TRIANGLE = np.array([[0, 0, 0], [0.24, 0, 0], [0.12, 0.2, 0], [0, 0, 0]], float)
OUT_AND_BACK = np.array([[0, 0, 0], [0.3, 0, 0], [0, 0, 0]], float)

frames = st.builds(lambda xi: se3.pose_from_twist(np.asarray(xi)),
                   st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6))


@settings(max_examples=25, deadline=None)
@given(X=frames)
def test_headings_turn_with_the_world_frame_and_their_angles_do_not(X):
    rng = np.random.default_rng(0)
    A, B, C = (se3.pose_from_twist(rng.normal(0, 0.3, 6)) for _ in range(3))
    R = X[:3, :3]
    h = heading(A, B, 0.1)
    assert heading(X @ A, X @ B, 0.1) == pytest.approx(np.concatenate([R @ h[:3], R @ h[3:]]), abs=1e-9)
    assert turn_angle(heading(X @ A, X @ B, 0.1), heading(X @ B, X @ C, 0.1)) == pytest.approx(
        turn_angle(h, heading(B, C, 0.1)), abs=1e-6)


def test_turn_angle_of_going_on_reversing_and_turning_square():
    east, north = np.array([0, 0, 0, 1.0, 0, 0]), np.array([0, 0, 0, 0, 1.0, 0])
    assert turn_angle(east, 2 * east) == pytest.approx(0.0, abs=1e-6)
    assert turn_angle(east, -east) == pytest.approx(180.0)
    assert turn_angle(east, north) == pytest.approx(90.0)
    assert turn_angle(None, east) == 0.0 and turn_angle(east, np.zeros(6)) == 0.0


@settings(max_examples=15, deadline=None)
@given(X=frames, hold=st.sampled_from([0.0, 0.06, 0.3]))
def test_drawn_polylines_have_their_corners_in_any_world_frame(X, hold):
    assert _corners(drawn_positions(SQUARE, hold_s=hold), X) == 3  # the fourth corner is the end
    assert _corners(drawn_positions(ZIGZAG, hold_s=hold), X) == 2
    assert _corners(drawn_positions(OUT_AND_BACK, hold_s=hold), X) == 1  # a reversal is a corner too


@settings(max_examples=15, deadline=None)
@given(X=frames, overlap=st.floats(0.1, 0.3))
def test_a_polygon_drawn_fluently_has_its_corners_in_any_world_frame(X, overlap):
    """The hand slows at each corner without stopping, and the units meet at the speed minimum
    inside the rounded corner (clean synthetic strokes: the headings there still turn sharply;
    a person's do not always, next test)."""
    square = fluent_positions(SQUARE, overlap)
    seg = MotionSegmenter(LEVELS, L=0.1, dt=DT)
    units = [u for k, T in enumerate(tracker_poses(square, X)) if (u := seg.push(DT * k, T))]
    assert len(units) == 4
    assert corner_count(units, 60.0) == 3
    assert _corners(fluent_positions(ZIGZAG, overlap), X) == 2
    assert _corners(fluent_positions(TRIANGLE, overlap), X) == 2


@pytest.mark.parametrize("who", [2, 7, 13])
def test_a_person_drawing_a_square_fluently_has_its_three_corners(models, who):
    """Development people who draw fluently (replica, strokes overlapping by about a quarter): at
    the speed minimum inside a rounded corner their headings have partly turned (40-145° for a
    90° corner, one or two of three corners below 60° in most of these takes), the sides' chords
    turn by about 90°. Every take counts its three corners (v16, :func:`is_corner`)."""
    c, L = SpottingConstants(), RecognizerConfig().descriptor.L
    lv = speed_levels(models[0], L, c.dt, c.speed_lag, c.noise_factor, c.peak_fraction,
                      c.move_factor)
    drawer = person(who)
    assert drawer.coarticulation > 0.2
    session = take_session("square", drawer, 3, seed=who)
    for take in session.segments:
        _, units = recording_units(session.traj.slice_time(take.start_t - 0.3, take.end_t + 0.3),
                                   SpeedLevels(lv.rest, lv.move), L, c.dt)
        assert corner_count(units, c.corner_angle) == 3


def test_the_chords_confirm_a_corner_only_where_the_heading_turns_too():
    """A unit pair whose chords turn sharply is a corner only if the heading at their meeting
    turns by more than half the corner angle: two arcs of a circle cut by a near-stop turn,
    chord to chord, by half their sum, while the hand there goes on the same way."""
    east, north = np.array([0, 0, 0, 1.0, 0, 0]), np.array([0, 0, 0, 0, 1.0, 0])
    half = np.array([0, 0, 0, 1.0, 1.0, 0])  # 45° from east

    def unit(h_in, h_out, chord):
        return Unit(0, 1, 0.0, 1.0, 1.0, False, h_in, h_out, chord)

    side_a, side_b = unit(east, east, east), unit(north, north, north)
    assert is_corner(side_a, side_b, 60.0)  # a sharp corner: the headings turn by 90°
    fluent_a, fluent_b = unit(east, east, east), unit(half, north, north)  # 45° at the meeting
    assert is_corner(fluent_a, fluent_b, 60.0)
    arc_a, arc_b = unit(east, half, east), unit(half, north, north)  # on the same way there
    assert not is_corner(arc_a, arc_b, 60.0)
    assert not is_corner(fluent_a, unit(half, east, east), 60.0)  # chords do not turn


@pytest.mark.parametrize("pause_at", [None, 0.3, 0.5, 0.7])
def test_a_circle_has_no_corner_even_when_the_hand_nearly_stops_on_it(pause_at):
    positions = circle_positions(pause_at=pause_at)
    seg = MotionSegmenter(LEVELS, L=0.1, dt=DT)
    units = [u for k, T in enumerate(tracker_poses(positions, np.eye(4))) if (u := seg.push(DT * k, T))]
    assert len(units) == (1 if pause_at is None else 2)  # the near-stop does cut it
    assert corner_count(units, 60.0) == 0


def test_a_sharper_corner_angle_counts_fewer_corners():
    square = drawn_positions(SQUARE)
    assert _corners(square, angle=80.0) == 3
    assert _corners(square, angle=100.0) == 0


@pytest.fixture(scope="module")
def models():
    return load_model_recordings(replica_path(0), "original_1")


def test_corner_limits_come_from_the_demonstrations(models):
    rec = replica_recognizer()
    limits = rec.learned_.corner_limits
    assert limits["go_right"] == 2  # one turn of a circle, and two corners' slack
    assert all(limits[g] == 3 for g in limits if g != "go_right")  # out, reverse, back
    sp = rec.spotter
    j = rec.labels.index("go_right")
    lo, hi = sp.size_limits[j]
    size = 0.5 * (lo + hi)
    closes = np.full(4, 0.5 * (sp.opening_limits[j] + sp.closure_limits[j]))
    ok = sp.admissible(j, closes, np.full(4, size), np.arange(4))
    assert list(ok) == [True, True, True, False]  # a square (3) is no circle
    off = Recognizer.from_trajectories(*models, corners=False).spotter
    assert off.admissible(j, closes, np.full(4, size), np.arange(4)).all()


def test_corner_angle_is_checked():
    with pytest.raises(ValueError, match="corner_angle"):
        SpottingConstants(corner_angle=200.0)
    with pytest.raises(ValueError, match="corner_slack"):
        RecognizerConfig().replace(corner_slack=-1)


def test_a_corner_limit_only_where_the_demonstrations_agree():
    assert corner_limit([3, 3, 3, 3, 3], slack=0) == 3
    assert corner_limit([3, 3, 3, 3, 3]) == 4  # another person may break one stroke more
    assert corner_limit([0, 0]) == 1
    assert corner_limit([0, 0, 1, 0, 0]) is None  # a curve that slows where it bends most
    assert corner_limit([2]) is None  # one take says nothing about how others vary
    assert corner_limit([]) is None


def test_only_a_smooth_gesture_gets_the_slack():
    """v15: a gesture of at most ``smooth`` agreed corners may get one more; a drawn polygon or a
    Z, whose corners are its shape, may not."""
    assert corner_limit([0, 0, 0], 1, smooth=1) == 1
    assert corner_limit([1, 1, 1], 1, smooth=1) == 2  # an out-and-back move another person hooks
    assert corner_limit([2, 2, 2], 1, smooth=1) == 2  # a triangle admits no square
    assert corner_limit([3, 3, 3], 1, smooth=1) == 3
    assert corner_limit([2, 2, 2], 1, smooth=None) == 3  # v9-v14


def test_a_triangle_admits_no_square_and_a_zigzag_no_letter_m():
    rng = np.random.default_rng(3)
    takes = drawn_takes(ZIGZAG, 5, rng) + drawn_takes(TRIANGLE, 5, rng)
    labels = ["zigzag"] * 5 + ["triangle"] * 5
    strict, loose = (Recognizer.from_trajectories(takes, labels, corner_slack=1, slack_corners=k)
                     for k in (1, None))
    assert strict.learned_.corner_limits == {"zigzag": 2, "triangle": 2}
    assert loose.learned_.corner_limits == {"zigzag": 3, "triangle": 3}
    for rec, admitted in ((strict, [True, False]), (loose, [True, True])):
        sp = rec.spotter
        for g in ("zigzag", "triangle"):
            j = rec.labels.index(g)
            size = float(np.mean(sp.size_limits[j]))
            closes = np.full(2, 0.5 * (sp.opening_limits[j] + sp.closure_limits[j]))
            assert list(sp.admissible(j, closes, np.full(2, size), np.array([2, 3]))) == admitted


def _real_corner_counts(angle: float) -> dict:
    """{(controller, person, gesture): [corners of each take]} of the real Vive recordings."""
    config = RecognizerConfig().replace(corner_angle=angle)
    return {key: [n for _, _, n, _ in takes] for key, takes in take_geometry(MACHETE, config).items()}


def _exceeding(counts: dict, slack: int, smooth: int | None = None) -> float:
    over = checked = 0
    for key, own in counts.items():
        limit = corner_limit(own, slack, smooth)
        if limit is None:
            continue
        others = other_peoples(counts, key)
        checked += len(others)
        over += sum(c > limit for c in others)
    assert checked > 0
    return over / checked


def test_real_people_stay_within_a_corner_limit_from_another_persons_takes():
    """Real Vive recordings: one person's agreeing takes set a limit; the other people's
    performances of the gesture must stay within it with the default slack (all six people,
    v17: 0.17 % exceed it). Without slack they do not (25.8 %: real people break strokes where
    others did not)."""
    config = SpottingConstants()
    counts = _real_corner_counts(config.corner_angle)
    assert _exceeding(counts, config.corner_slack, config.slack_corners) <= 0.02
    assert _exceeding(counts, 0) > 0.05


def test_real_people_add_corners_to_gestures_of_several_too():
    """Why every gesture gets the slack (v17, ``slack_corners=None``): on the real Vive
    recordings, with takes cut at v17's rest level, where one person's takes agree on two corners
    or more, other people's performances have more (v16's level had shown none, which is why v15
    gave such gestures no slack). The shipped two-takes subset has no such case."""
    assert SpottingConstants().slack_corners is None
    if MACHETE == SHIPPED_MACHETE:
        pytest.skip("the shipped subset has no gesture of several agreed corners; needs the six people")
    counts = _real_corner_counts(SpottingConstants().corner_angle)
    several = {k: v for k, v in counts.items() if corner_limit(v, 0) is not None and v[0] >= 2}
    others = [c for key, own in several.items() for c in other_peoples(counts, key) if c > own[0]]
    assert others
