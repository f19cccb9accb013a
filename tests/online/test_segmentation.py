"""Motion segmentation: uniform grid, bi-invariant motion speed, units, closure."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree import Trajectory
from framefree.core import se3
from framefree.online.segmentation import (
    MotionSegmenter,
    PoseBuffer,
    SpeedLevels,
    UniformResampler,
    motion_speed,
)
from framefree.online.span_shape import closure
from framefree.replica.motion import (
    Motion,
    hold,
    make_pose,
    minimum_jerk,
    rot,
    sclerp_path,
    screw_path,
    stroke,
)

LEVELS = SpeedLevels(rest=0.03, move=0.06)


def _out_and_back(pause: float = 0.3, rest: float = 0.8) -> tuple[np.ndarray, np.ndarray]:
    """Uniform 50 Hz poses of: rest, a 30 cm stroke to the left, a pause, back, rest."""
    A = make_pose(np.eye(3), [0.4, -0.2, 1.1])
    B = make_pose(rot([1, 0, 0], 0.3), [0.4, 0.1, 1.1])
    m = Motion([hold(A, rest), stroke(sclerp_path(A, B), 0.9), hold(B, pause),
                stroke(sclerp_path(B, A), 0.9), hold(A, rest)])
    t = np.arange(0.0, m.duration, 0.02)
    return t, m.at(t)


def _units(t: np.ndarray, poses: np.ndarray, levels: SpeedLevels = LEVELS) -> list:
    seg = MotionSegmenter(levels, L=0.1)
    return [u for k in range(t.size) if (u := seg.push(float(t[k]), poses[k])) is not None]


def test_resampler_puts_jittered_samples_on_the_grid():
    rng = np.random.default_rng(1)
    t = np.arange(200) * 0.02 + rng.uniform(-0.008, 0.008, 200)
    t[0] = 0.0
    A = make_pose(np.eye(3), [0, 0, 0])
    B = make_pose(rot([0, 0, 1], 1.0), [0.2, 0.0, 0.0])
    poses = se3.sclerp(np.broadcast_to(A, (200, 4, 4)), np.broadcast_to(B, (200, 4, 4)), t / t[-1])
    res = UniformResampler(0.02)
    times, out = [], []
    for k in range(t.size):
        tk, Tk = res.push(float(t[k]), poses[k])
        times.extend(tk)
        out.extend(Tk)
    times = np.array(times)
    np.testing.assert_allclose(np.diff(times), 0.02, atol=1e-9)
    # a constant-twist motion is reproduced exactly by ScLERP between its own samples
    expected = se3.sclerp(np.broadcast_to(A, (times.size, 4, 4)), np.broadcast_to(B, (times.size, 4, 4)),
                          times / t[-1])
    np.testing.assert_allclose(np.array(out), expected, atol=1e-9)


def test_resampler_ignores_repeated_and_backwards_times():
    res = UniformResampler(0.02)
    T = np.eye(4)
    res.push(0.0, T)
    assert res.push(0.0, T)[0].size == 0
    assert res.push(-0.1, T)[0].size == 0
    assert res.push(0.05, T)[0].size == 2


def test_buffer_is_bounded_and_addressed_by_running_index():
    buf = PoseBuffer(8)
    for k in range(20):
        T = np.eye(4)
        T[0, 3] = k
        buf.append(0.02 * k, T)
    assert buf.oldest == 12
    t, P = buf.slice(0, 100)
    assert t.size == 8 and P[0, 0, 3] == 12 and P[-1, 0, 3] == 19


def test_out_and_back_with_pause_gives_two_units():
    t, P = _out_and_back(pause=0.3)
    units = _units(t, P)
    assert len(units) == 2
    assert all(u.rest_after for u in units)
    assert units[0].end_t < units[1].start_t


def test_overlapping_strokes_are_split_at_the_speed_minimum():
    """Two strokes that overlap in time (the hand turns a corner without stopping): the speed dips
    but never rests; the valley rule splits them."""
    t = np.arange(0.0, 3.5, 0.02)
    a = minimum_jerk((t - 0.8) / 0.9)
    b = minimum_jerk((t - 1.45) / 0.9)
    P = np.repeat(np.eye(4)[None], t.size, axis=0)
    P[:, :3, 3] = 0.3 * a[:, None] * [1, 0, 0] + 0.3 * b[:, None] * [0, 1, 0]
    units = _units(t, P)
    assert len(units) == 2
    assert not units[0].rest_after
    assert units[0].end == units[1].start
    assert 1.4 < units[0].end_t < 2.0


def test_rest_gives_no_unit():
    t = np.arange(0.0, 3.0, 0.02)
    P = np.repeat(np.eye(4)[None], t.size, axis=0)
    assert _units(t, P) == []


def test_one_circle_is_one_unit():
    A = make_pose(np.eye(3), [0.4, -0.2, 1.1])
    circle = screw_path(A, [1, 0, 0], [0.4, -0.2, 1.22], 2 * math.pi)
    m = Motion([hold(A, 0.8), stroke(circle, 2.0), hold(A, 0.8)])
    t = np.arange(0.0, m.duration, 0.02)
    assert len(_units(t, m.at(t))) == 1


def _random_pose(draw) -> np.ndarray:
    rv = np.array(draw(st.lists(st.floats(-3, 3), min_size=3, max_size=3)))
    p = np.array(draw(st.lists(st.floats(-2, 2), min_size=3, max_size=3)))
    return make_pose(se3.rotation_from_vector(rv), p)


@st.composite
def frames(draw) -> tuple[np.ndarray, np.ndarray]:
    world = _random_pose(draw)
    body = _random_pose(draw)
    body[:3, 3] *= 0.03  # a tracker a few centimetres from the palm
    return world, body


@settings(max_examples=25, deadline=None)
@given(frames())
def test_speed_and_closure_do_not_depend_on_the_world_frame(wb):
    world, _ = wb
    _t, P = _out_and_back()
    Q = world[None] @ P
    np.testing.assert_allclose(motion_speed(Q, 0.02, 0.1, 5)[5:], motion_speed(P, 0.02, 0.1, 5)[5:],
                               rtol=1e-6, atol=1e-9)
    assert closure(Q, 0.1) == pytest.approx(closure(P, 0.1), abs=1e-9)


@settings(max_examples=25, deadline=None)
@given(frames())
def test_units_do_not_depend_on_where_the_tracker_sits(wb):
    world, body = wb
    t, P = _out_and_back()
    a = [(u.start, u.end) for u in _units(t, P)]
    b = [(u.start, u.end) for u in _units(t, world[None] @ P @ body[None])]
    assert len(a) == len(b) == 2
    assert all(abs(x[0] - y[0]) <= 2 and abs(x[1] - y[1]) <= 2 for x, y in zip(a, b, strict=True))


def test_closure_is_zero_back_at_start_and_one_for_a_straight_move():
    _t, P = _out_and_back()
    assert closure(P, 0.1) < 0.01
    half = P[: P.shape[0] // 2]
    assert closure(half, 0.1) > 0.95


def test_closure_of_fewer_than_two_poses_is_that_of_a_motion_that_does_not_return():
    assert closure(np.eye(4)[None], 0.1) == 1.0
    assert closure(np.zeros((0, 4, 4)), 0.1) == 1.0


def test_segmenter_levels_must_make_sense():
    with pytest.raises(ValueError):
        MotionSegmenter(LEVELS, L=0.1, valley_ratio=1.5)


def test_trajectory_helpers_agree_with_uniform_grid():
    t, P = _out_and_back()
    traj = Trajectory.from_poses(t, P)
    _tu, Pu = traj.uniform_poses(0.02)
    np.testing.assert_allclose(Pu, P, atol=1e-9)
