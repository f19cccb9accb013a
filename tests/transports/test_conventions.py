"""Coordinate conventions: every conversion is a change of basis that keeps rotations proper and a
motion's physical handedness (the sign of its screw pitch)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree.core import se3
from framefree.errors import TrajectoryError
from framefree.io.conventions import CONVENTIONS, get_convention, poses_to_framefree

unit_quats = st.lists(st.floats(-1, 1), min_size=4, max_size=4).filter(
    lambda v: np.linalg.norm(v) > 0.1).map(lambda v: np.asarray(v) / np.linalg.norm(v))


def _as_source(p: np.ndarray, q_wxyz: np.ndarray, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Poses given in framefree's frame, written as the tracking system ``name`` would."""
    conv = CONVENTIONS[name]
    P = conv.basis
    R = P.T @ se3.matrix_from_quaternion(q_wxyz[None])[0] @ P
    q = se3.quaternion_from_matrix(R[None])[0]
    if conv.quat_order == "xyzw":
        q = q[[1, 2, 3, 0]]
    return (P.T @ p)[None], q[None]


def _pitch(T0: np.ndarray, T1: np.ndarray) -> float:
    """Screw pitch [m/rad] of the relative motion from pose T0 to pose T1 (in T0's frame)."""
    xi = se3.twist_from_pose((se3.transform_inverse(T0) @ T1)[None])[0]
    w, v = xi[:3], xi[3:]
    return float(w @ v / (w @ w))


@pytest.mark.parametrize("name", sorted(CONVENTIONS))
@given(q=unit_quats, p=st.lists(st.floats(-3, 3), min_size=3, max_size=3))
def test_round_trip_through_every_convention(name, q, p):
    p = np.asarray(p)
    ps, qs = _as_source(p, q, name)
    p2, q2 = poses_to_framefree(ps, qs, name)
    assert np.allclose(p2[0], p, atol=1e-12)
    R, R2 = se3.matrix_from_quaternion(q[None])[0], se3.matrix_from_quaternion(q2)[0]
    # _as_source writes the source quaternion with the reference extraction, which takes w from
    # the trace: near a half turn w is only known to about sqrt(machine epsilon) (w = 5.3e-9
    # instead of 0 for a half turn about z tilted by 0.005, which moves R by 1.05e-8)
    assert np.allclose(R2, R, atol=1e-7)
    assert np.isclose(np.linalg.det(R2), 1.0)


def test_a_half_turn_written_by_the_reference_extraction_comes_back():
    """The case Hypothesis found: a half turn about an axis 0.005 rad off z."""
    q = np.array([0.0, 0.0, 1.0, 0.005]) / np.linalg.norm([0.0, 0.0, 1.0, 0.005])
    ps, qs = _as_source(np.zeros(3), q, "ros")
    _, q2 = poses_to_framefree(ps, qs, "ros")
    R, R2 = se3.matrix_from_quaternion(q[None])[0], se3.matrix_from_quaternion(q2)[0]
    assert np.abs(R2 - R).max() < 1e-7


@pytest.mark.parametrize("name", sorted(CONVENTIONS))
def test_screw_pitch_sign_is_physical(name):
    """A right-handed screw in the room stays right-handed after reading it from any system; read
    from a left-handed system as if it were right-handed, it turns left-handed."""
    T0 = np.eye(4)
    T1 = np.eye(4)
    T1[:3, :3] = se3.rotation_from_vector(np.array([[0.3, -0.2, 0.9]]))[0]
    T1[:3, 3] = 0.05 * np.array([0.3, -0.2, 0.9])  # translation along the axis: positive pitch
    assert _pitch(T0, T1) > 0
    back = []
    for T in (T0, T1):
        p, q = _as_source(T[:3, 3], se3.quaternion_from_matrix(T[None, :3, :3])[0], name)
        back.append(poses_to_framefree(p, q, name))
    T0b, T1b = (se3.poses_from_pq(p, q)[0] for p, q in back)
    assert _pitch(T0b, T1b) > 0
    if CONVENTIONS[name].handedness == "left":
        # the same numbers read as a right-handed frame (only the quaternion order fixed)
        wrong = []
        for T in (T0, T1):
            p, q = _as_source(T[:3, 3], se3.quaternion_from_matrix(T[None, :3, :3])[0], name)
            wrong.append(se3.poses_from_pq(p, q[:, [3, 0, 1, 2]])[0])
        assert _pitch(*wrong) < 0


def test_unknown_convention_names_the_choices():
    with pytest.raises(TrajectoryError, match="unity"):
        get_convention("vicon")


def test_zero_quaternion_is_refused():
    with pytest.raises(TrajectoryError, match="quaternion"):
        poses_to_framefree(np.zeros((1, 3)), np.zeros((1, 4)), "unity")
