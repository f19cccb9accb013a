"""Canonical paths (docs/real-people.md): exactly the invariances each level promises, and no more."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree import NearestNeighborClassifier, Trajectory
from framefree.core import se3
from framefree.core.multitrajectory import MultiTrajectory
from framefree.descriptors.canonical import CanonicalPath, canonical_frame
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
