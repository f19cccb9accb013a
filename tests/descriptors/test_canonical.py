"""Canonical paths (docs/real-people.md): exactly the invariances each level promises, and no more."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree import NearestNeighborClassifier, Trajectory
from framefree.core import se3
from framefree.core.multitrajectory import MultiTrajectory
from framefree.descriptors.canonical import CanonicalPath, canonical_frame, start_orientation
from framefree.errors import DegenerateMotionError
from framefree.io.machete import read_machete
from real_data import SHIPPED_MACHETE

angles = st.floats(-np.pi, np.pi)
shifts = st.lists(st.floats(-5, 5), min_size=3, max_size=3)
rotvecs = st.lists(st.floats(-3, 3), min_size=3, max_size=3)


@pytest.fixture(scope="module")
def punch() -> MultiTrajectory:
    return read_machete(SHIPPED_MACHETE / "Sub_U001" / "uppercut_right" / "ex_0_moderate")


def _world(R: np.ndarray, shift) -> np.ndarray:
    W = np.eye(4)
    W[:3, :3] = R
    W[:3, 3] = shift
    return W


def _keep_up(moved: MultiTrajectory, up: np.ndarray) -> MultiTrajectory:
    """A tracking system that does not know it was tilted still says +z is up."""
    return MultiTrajectory(moved.trackers, moved.names, up, moved.source)


@given(angle=angles, shift=shifts)
def test_gravity_is_invariant_to_turns_about_the_vertical(punch, angle, shift):
    W = _world(se3.rotation_from_vector(np.array([[0.0, 0.0, angle]]))[0], shift)
    cp = CanonicalPath("gravity")
    assert np.allclose(cp.compute(punch.transformed(W)), cp.compute(punch), atol=1e-9)


@given(rotvec=rotvecs, shift=shifts, grip=rotvecs)
def test_full_is_invariant_to_any_world_change_and_to_the_grip(punch, rotvec, shift, grip):
    W = _world(se3.rotation_from_vector(np.asarray(rotvec)[None])[0], shift)
    B = _world(se3.rotation_from_vector(np.asarray(grip)[None])[0], [0, 0, 0])
    regripped = MultiTrajectory(tuple(tr.transformed(body=B) for tr in punch.trackers), punch.names)
    cp = CanonicalPath("full")
    assert np.allclose(cp.compute(regripped.transformed(W)), cp.compute(punch), atol=1e-9)


def test_gravity_is_not_invariant_to_a_tilt(punch):
    """Keeping the vertical is the point: a tilted tracking system changes the path."""
    W = _world(se3.rotation_from_vector(np.array([[1.2, 0.0, 0.0]]))[0], [0, 0, 0])
    cp = CanonicalPath("gravity")
    tilted = _keep_up(punch.transformed(W), punch.up)
    assert np.abs(cp.compute(tilted) - cp.compute(punch)).max() > 0.1


def test_gravity_tells_an_upward_stroke_from_a_sideways_one():
    t = np.linspace(0.0, 1.0, 51)
    q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    up = Trajectory(t, np.column_stack([0 * t, 0 * t, 0.3 * t]), q)
    side = Trajectory(t, np.column_stack([0.3 * t, 0 * t, 0 * t]), q)
    other_up = Trajectory(t, np.column_stack([0 * t, 0 * t, 0.25 * t + 0.01 * t**2]), q)
    clf = NearestNeighborClassifier(invariance="gravity").fit([up, side], ["up", "side"])
    assert list(clf.predict([other_up])) == ["up"]


def test_full_needs_two_trackers_and_a_motion():
    t = np.linspace(0.0, 1.0, 20)
    still = Trajectory(t, np.zeros((20, 3)), np.tile([1.0, 0, 0, 0], (20, 1)))
    with pytest.raises(DegenerateMotionError, match="two or more trackers"):
        canonical_frame(MultiTrajectory((still,)), "full")
    with pytest.raises(DegenerateMotionError, match="start at one place"):
        canonical_frame(MultiTrajectory((still, still), ("a", "b")), "full")


def test_classifier_takes_multi_tracker_samples(punch):
    other = read_machete(SHIPPED_MACHETE / "Sub_U001" / "hook_right" / "ex_0_moderate")
    query = read_machete(SHIPPED_MACHETE / "Sub_U002" / "uppercut_right" / "ex_1_moderate")
    for invariance in ("full", "gravity"):
        clf = NearestNeighborClassifier(invariance=invariance).fit([punch, other], ["uppercut", "hook"])
        assert clf.path_ is not None and clf.distance_matrix([query]).shape == (1, 2)
    with pytest.raises(ValueError, match="invariance"):
        NearestNeighborClassifier(invariance="tilt").fit([punch], ["uppercut"])


def test_orientations_and_relative_motion_by_hand():
    """Two trackers, the path at start and end. Tracker 0 rises 1 m, unturned; tracker 1 starts 1 m along x,
    rises too and turns 90° about z. Canonical frame (full): e1 = x, e2 = z (the displacement),
    e3 = e1 × e2 = −y. A turn about z is a turn about e2 that takes e1 to −e3 and e3 to e1. Tracker 1
    as seen from tracker 0: (1, 0, 0) throughout; tracker 0 from tracker 1: (−1, 0, 0), then, turned
    by −90° about z, (0, 1, 0)."""
    t = np.linspace(0.0, 1.0, 5)
    zero = np.zeros_like(t)
    still = np.tile([1.0, 0.0, 0.0, 0.0], (5, 1))
    turn = np.column_stack([np.cos(np.pi / 4 * t), zero, zero, np.sin(np.pi / 4 * t)])
    a = Trajectory(t, np.column_stack([zero, zero, t]), still)
    b = Trajectory(t, np.column_stack([zero + 1.0, zero, t]), turn)
    path = CanonicalPath("full", n_samples=2, orientation_scale=0.5, relative=True)
    out = path.compute(MultiTrajectory((a, b), ("a", "b")))
    eye = 0.5 * np.eye(3).ravel()
    turned = 0.5 * np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]]).ravel()
    expected = np.array([
        [0, 0, 0, 0, 0, 0, *eye, *eye, 1, 0, 0, -1, 0, 0],
        [0, 1, 0, 0, 1, 0, *eye, *turned, 1, 0, 0, 0, 1, 0],
    ])
    assert out.shape == (2, 30)
    assert np.allclose(out, expected, atol=1e-12)
    # both start unturned: the start frame is the world's, and both rise along its z
    started = CanonicalPath("full", n_samples=2, start_frame=True).compute(MultiTrajectory((a, b)))
    assert np.allclose(started[:, 6:], [[0, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 1]], atol=1e-12)


def test_the_start_frame_is_the_mean_of_the_starting_orientations(punch):
    """Two trackers turned ±0.4 rad about one axis from a common orientation average to it."""
    t = np.linspace(0.0, 1.0, 5)
    base = se3.rotation_from_vector(np.array([[0.3, -1.1, 0.5]]))[0]
    axis = np.array([0.0, 0.6, 0.8])
    quats = [se3.quaternion_from_matrix((base @ se3.rotation_from_vector(sign * 0.4 * axis[None])[0])[None])
             for sign in (1.0, -1.0)]
    trackers = tuple(Trajectory(t, np.column_stack([t, k + 0 * t, 0 * t]), np.repeat(q, 5, axis=0))
                     for k, q in enumerate(quats))
    assert np.allclose(start_orientation(MultiTrajectory(trackers)), base, atol=1e-12)


@given(rotvec=rotvecs, shift=shifts)
def test_orientations_and_relative_motion_ignore_the_world_frame(punch, rotvec, shift):
    """Both trackers moved by one random rigid change of world frame: the path is unchanged."""
    W = _world(se3.rotation_from_vector(np.asarray(rotvec)[None])[0], shift)
    cp = CanonicalPath("full", orientation_scale=0.3, relative=True, start_frame=True)
    assert np.allclose(cp.compute(punch.transformed(W)), cp.compute(punch), atol=1e-9)


@given(angle=angles, shift=shifts, grip=rotvecs)
def test_gravity_orientations_ignore_turns_about_the_vertical_and_the_grip(punch, angle, shift, grip):
    W = _world(se3.rotation_from_vector(np.array([[0.0, 0.0, angle]]))[0], shift)
    B = _world(se3.rotation_from_vector(np.asarray(grip)[None])[0], [0, 0, 0])
    regripped = MultiTrajectory(tuple(tr.transformed(body=B) for tr in punch.trackers), punch.names)
    cp = CanonicalPath("gravity", orientation_scale=0.3)
    assert np.allclose(cp.compute(regripped.transformed(W)), cp.compute(punch), atol=1e-9)
    with_relative = CanonicalPath("gravity", orientation_scale=0.3, relative=True)
    assert np.allclose(with_relative.compute(punch.transformed(W)), with_relative.compute(punch), atol=1e-9)


def test_relative_motion_needs_two_trackers_and_a_positive_scale(punch):
    with pytest.raises(DegenerateMotionError, match="two or more trackers"):
        CanonicalPath("gravity", relative=True).compute(punch.trackers[0])
    with pytest.raises(ValueError, match="orientation_scale"):
        CanonicalPath("full", orientation_scale=0.0)


def test_several_trackers_get_the_chosen_paths_and_one_tracker_keeps_positions(punch):
    """Golden distances of the multi-tracker defaults (benchmarks/real_people_protocol.py) on two
    shipped people: ``full`` adds the start frame, ``gravity`` keeps positions, and so does a
    single tracker under ``gravity``."""
    hook = read_machete(SHIPPED_MACHETE / "Sub_U001" / "hook_right" / "ex_0_moderate")
    query = read_machete(SHIPPED_MACHETE / "Sub_U002" / "uppercut_right" / "ex_1_moderate")
    golden = {"full": [0.148823302328, 0.292287401723], "gravity": [0.114671109737, 0.156083899489]}
    for invariance, expected in golden.items():
        clf = NearestNeighborClassifier(invariance=invariance).fit([punch, hook], ["uppercut", "hook"])
        assert clf.path_.start_frame == (invariance == "full")
        assert np.allclose(clf.distance_matrix([query])[0], expected, rtol=1e-9)
    single = NearestNeighborClassifier(invariance="gravity").fit([punch.trackers[0], hook.trackers[0]],
                                                                  ["uppercut", "hook"])
    assert repr(single.path_) == "CanonicalPath(invariance='gravity', n_samples=64)"


def test_all_columns_golden(punch):
    """Every option at once (round 2's P + O + H + S) on shipped recordings, pinned."""
    hook = read_machete(SHIPPED_MACHETE / "Sub_U001" / "hook_right" / "ex_0_moderate")
    query = read_machete(SHIPPED_MACHETE / "Sub_U002" / "uppercut_right" / "ex_1_moderate")
    path = CanonicalPath("gravity", orientation_scale=0.3, relative=True, start_frame=True)
    D = path.distance_matrix([path.compute(query)], [path.compute(punch), path.compute(hook)])
    assert np.allclose(D[0], [0.29721619391, 0.395198946788], rtol=1e-9)
