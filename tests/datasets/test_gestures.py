"""Geometry of every synthetic gesture, measured on the recorded (noisy) *Original 1* trials.

Each test fails if a gesture drifts from its description in docs/dataset.md (*Gesture geometry*).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.datasets import GESTURES
from framefree.replica import synthesize_gesture
from framefree.replica.motion import minimum_jerk
from framefree.replica.recording import sample_times, stored_quaternions

TRIALS = [f"trial_{k}" for k in range(1, 6)]


def _originals(ds, gesture):
    return [t.trajectory for t in ds.select(gesture, "original_1")]


def _rest_pose(traj, first: bool = True) -> np.ndarray:
    """Average pose over the first (or last) 10 samples (the hand is at rest there)."""
    T = traj.poses()[:10] if first else traj.poses()[-10:]
    out = T[0].copy()
    out[:3, 3] = T[:, :3, 3].mean(axis=0)
    return out


def _angles(traj, ref: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] of each sample relative to the pose ``ref``."""
    return np.linalg.norm(se3.vector_from_rotation(ref[:3, :3].T @ traj.rotations()), axis=1)


def _screw_to_farthest(traj) -> tuple[float, float, float]:
    """Displacement from the start rest pose to the most rotated pose: (angle [rad], pitch [m/rad],
    distance of the screw axis from the tracker origin [m])."""
    T0 = _rest_pose(traj)
    k = int(np.argmax(_angles(traj, T0)))
    xi = se3.twist_from_pose(se3.transform_inverse(T0) @ traj.poses()[k])
    phi, rho = xi[:3], xi[3:]
    th = float(np.linalg.norm(phi))
    pitch = float(phi @ rho) / th**2
    axis_dist = float(np.linalg.norm(np.cross(phi, rho))) / th**2
    return th, pitch, axis_dist


def _straightness(traj) -> tuple[float, float]:
    """(chord [m] from the start to the farthest point, max deviation of the outward path from
    that chord / chord)."""
    p = traj.p - _rest_pose(traj)[:3, 3]
    d = np.linalg.norm(p, axis=1)
    k = int(np.argmax(d))
    u = p[k] / d[k]
    out = p[: k + 1]
    dev = np.linalg.norm(out - np.outer(out @ u, u), axis=1)
    return float(d[k]), float(dev.max() / d[k])


@pytest.mark.parametrize("gesture", GESTURES)
def test_returns_to_start(replica, gesture: str) -> None:
    for traj in _originals(replica, gesture):
        a, b = _rest_pose(traj, True), _rest_pose(traj, False)
        assert np.linalg.norm(a[:3, 3] - b[:3, 3]) < 0.06
        assert np.degrees(np.linalg.norm(se3.vector_from_rotation(a[:3, :3].T @ b[:3, :3]))) < 20


@pytest.mark.parametrize("gesture", GESTURES)
def test_rest_before_and_after(replica, gesture: str) -> None:
    for traj in _originals(replica, gesture):
        for ends in (traj.p[:20], traj.p[-20:]):  # 0.4 s of rest at both ends
            assert np.linalg.norm(ends - ends.mean(axis=0), axis=1).max() < 0.015
        moving = np.linalg.norm(traj.p - traj.p[:20].mean(axis=0), axis=1).max()
        assert moving > 0.05
        assert 2.0 < traj.duration < 8.0


def test_go_left_is_a_straight_line(replica) -> None:
    for traj in _originals(replica, "go_left"):
        chord, dev = _straightness(traj)
        assert 0.18 < chord < 0.5
        assert dev < 0.15
        assert np.degrees(_angles(traj, _rest_pose(traj)).max()) < 20  # (nearly) pure translation


def test_go_home_is_an_arc(replica) -> None:
    for traj in _originals(replica, "go_home"):
        chord, dev = _straightness(traj)
        assert 0.12 < chord < 0.5
        assert dev > 0.2
        assert np.degrees(_angles(traj, _rest_pose(traj)).max()) < 20


def test_go_right_is_a_circle_with_slight_rotation(replica) -> None:
    for traj in _originals(replica, "go_right"):
        v = np.linalg.norm(np.diff(traj.p, axis=0), axis=1) / np.diff(traj.t)
        moving = np.flatnonzero(v > 0.1)
        p = traj.p[moving[0] : moving[-1] + 1]
        c = p.mean(axis=0)
        _, _, Vt = np.linalg.svd(p - c)
        xy = (p - c) @ Vt[:2].T  # best-fit plane
        # algebraic circle fit: x² + y² = 2ax + 2by + c0
        A = np.column_stack([2 * xy, np.ones(len(xy))])
        sol = np.linalg.lstsq(A, (xy**2).sum(axis=1), rcond=None)[0]
        r = math.sqrt(sol[2] + sol[0] ** 2 + sol[1] ** 2)
        res = np.linalg.norm(xy - sol[:2], axis=1) - r
        assert 0.07 < r < 0.2
        assert np.sqrt(np.mean(res**2)) / r < 0.15
        # the whole circle is traversed: polar angle covers (almost) 2π
        ang = np.unwrap(np.arctan2(xy[:, 1] - sol[1], xy[:, 0] - sol[0]))
        assert abs(ang[-1] - ang[0]) > np.radians(300)
        rot = np.degrees(_angles(traj, _rest_pose(traj)).max())
        assert 4 < rot < 50  # slight forearm rotation


def test_go_down_is_a_large_rotation_about_a_near_axis(replica) -> None:
    for traj in _originals(replica, "go_down"):
        th, pitch, axis = _screw_to_farthest(traj)
        assert 130 < np.degrees(th) < 190
        assert abs(pitch) < 0.02
        assert axis < 0.12


def test_go_up_is_a_rotation_about_a_far_axis(replica) -> None:
    for traj in _originals(replica, "go_up"):
        th, pitch, axis = _screw_to_farthest(traj)
        assert 25 < np.degrees(th) < 85
        assert abs(pitch) < 0.04
        assert axis > 0.2
        chord, _ = _straightness(traj)
        assert chord > 0.12  # the hand rises


@pytest.mark.parametrize(("gesture", "sign"), [("open_gripper", 1.0), ("close_gripper", -1.0)])
def test_gripper_gestures_are_screws_of_opposite_pitch(replica, gesture: str, sign: float) -> None:
    for traj in _originals(replica, gesture):
        th, pitch, axis = _screw_to_farthest(traj)
        assert 130 < np.degrees(th) < 190
        assert sign * pitch > 0.03  # ≈ 0.2 m over ≈ π rad
        assert axis < 0.12
        chord, _ = _straightness(traj)
        assert 0.1 < chord < 0.4


def test_trials_differ_and_grip_changes(replica) -> None:
    for g in GESTURES:
        trajs = _originals(replica, g)
        durations = {round(t.duration, 3) for t in trajs}
        assert len(durations) == 5
        starts = [t.q[0] for t in trajs]
        # a differently mounted tracker in every trial: start orientations far apart
        dots = [abs(float(a @ b)) for i, a in enumerate(starts) for b in starts[i + 1 :]]
        assert min(dots) < 0.99


def test_sampling_is_50hz_with_jitter(replica) -> None:
    traj = replica.select("go_left", "original_1")[0].trajectory
    dt = np.diff(traj.t)
    assert traj.t[0] == 0.0
    assert 0.019 < np.median(dt) < 0.021
    assert dt.std() > 1e-4  # jitter
    assert dt.min() > 0.01


def test_stored_files_have_sign_flips(replica_root) -> None:
    flips = 0
    for f in sorted(replica_root.glob("*/*/trial_*.csv")):
        q = np.loadtxt(f, delimiter=",")[:, 4:]
        flips += int((np.sum(q[1:] * q[:-1], axis=1) < 0).sum())
    assert flips > 20


def test_deterministic_from_seed() -> None:
    a = synthesize_gesture("go_home", np.random.default_rng(3))
    b = synthesize_gesture("go_home", np.random.default_rng(3))
    c = synthesize_gesture("go_home", np.random.default_rng(4))
    np.testing.assert_array_equal(a.to_array(), b.to_array())
    assert len(a) != len(c) or not np.array_equal(a.p, c.p)


def test_unknown_gesture() -> None:
    with pytest.raises(ValueError, match="unknown gesture"):
        synthesize_gesture("moonwalk", np.random.default_rng(0))


def test_minimum_jerk_profile() -> None:
    tau = np.linspace(0, 1, 1001)
    s = minimum_jerk(tau)
    assert s[0] == 0 and s[-1] == 1 and np.all(np.diff(s) >= 0)
    v = np.gradient(s, tau)
    assert abs(v.max() - 1.875) < 1e-3 and abs(tau[np.argmax(v)] - 0.5) < 1e-3
    assert v[0] < 1e-3 and v[-1] < 1e-3


@settings(max_examples=20)
@given(duration=st.floats(0.2, 30.0), seed=st.integers(0, 2**32 - 1))
def test_sample_times(duration: float, seed: int) -> None:
    t = sample_times(duration, np.random.default_rng(seed))
    assert t[0] == 0 and t[-1] <= duration and np.all(np.diff(t) > 0)
    assert abs(len(t) - (duration / 0.02 + 1)) <= 0.05 * duration / 0.02 + 2


@settings(max_examples=10)
@given(seed=st.integers(0, 2**32 - 1))
def test_stored_quaternions_same_rotations(seed: int) -> None:
    rng = np.random.default_rng(seed)
    q = rng.standard_normal((300, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    s = stored_quaternions(q, rng)
    assert np.allclose(np.abs(np.sum(q * s, axis=1)), 1.0)
