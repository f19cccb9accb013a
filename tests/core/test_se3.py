"""SE(3) maths: round trips, closed forms near 0 and π, ScLERP, quaternions."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.linalg import expm, logm

from framefree.core import se3

finite = st.floats(-3.0, 3.0, allow_nan=False)
vec3 = arrays(np.float64, 3, elements=finite)
vec6 = arrays(np.float64, 6, elements=finite)


def _rot_vec_in_ball(v):
    """Map an arbitrary 3-vector into the open ball of radius π (principal logarithms)."""
    n = np.linalg.norm(v)
    return v if n < np.pi - 1e-6 else v * (np.pi - 1e-6) / n


@given(vec3)
def test_so3_exp_log_round_trip(v):
    phi = _rot_vec_in_ball(v)
    R = se3.rotation_from_vector(phi)
    assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert np.isclose(np.linalg.det(R), 1.0)
    np.testing.assert_allclose(se3.vector_from_rotation(R), phi, atol=1e-9)


@given(vec6)
def test_se3_exp_log_round_trip(xi):
    xi = xi.copy()
    xi[:3] = _rot_vec_in_ball(xi[:3])
    T = se3.pose_from_twist(xi)
    np.testing.assert_allclose(se3.twist_from_pose(T), xi, atol=1e-8)


@given(vec6)
def test_se3_exp_matches_matrix_exponential(xi):
    X = np.zeros((4, 4))
    X[:3, :3] = se3.hat(xi[:3])
    X[:3, 3] = xi[3:]
    np.testing.assert_allclose(se3.pose_from_twist(xi), expm(X), atol=1e-10)


@pytest.mark.parametrize(
    "angle", [0.0, 1e-12, 1e-8, 1e-5, 1e-3, 0.5, np.pi - 1e-3, np.pi - 1e-7, np.pi]
)
def test_log_is_accurate_near_zero_and_pi(angle):
    axis = np.array([0.3, -0.5, 0.81])
    axis /= np.linalg.norm(axis)
    R = se3.rotation_from_vector(angle * axis)
    phi = se3.vector_from_rotation(R)
    assert np.isclose(np.linalg.norm(phi), angle, atol=1e-9)
    if angle > 0:
        # near π the axis sign is ambiguous only at exactly π
        assert np.allclose(se3.rotation_from_vector(phi), R, atol=1e-9)
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = [0.1, -0.2, 0.3]
    np.testing.assert_allclose(se3.pose_from_twist(se3.twist_from_pose(T)), T, atol=1e-9)


def test_log_matches_scipy_logm_for_generic_pose():
    rng = np.random.default_rng(0)
    for _ in range(20):
        xi = rng.normal(size=6)
        xi[:3] = _rot_vec_in_ball(xi[:3])
        T = se3.pose_from_twist(xi)
        X = np.real(logm(T))
        ref = np.concatenate([se3.vee(X[:3, :3]), X[:3, 3]])
        np.testing.assert_allclose(se3.twist_from_pose(T), ref, atol=1e-9)


def test_batched_shapes_are_preserved():
    xi = np.random.default_rng(1).normal(size=(2, 5, 6)) * 0.5
    T = se3.pose_from_twist(xi)
    assert T.shape == (2, 5, 4, 4)
    assert se3.twist_from_pose(T).shape == (2, 5, 6)
    with pytest.raises(ValueError, match=r"\(\.\.\., 6\)"):
        se3.pose_from_twist(np.zeros((3, 5)))


@given(arrays(np.float64, 4, elements=finite))
def test_quaternion_matrix_round_trip(q):
    if np.linalg.norm(q) < 1e-3:
        return
    q = q / np.linalg.norm(q)
    R = se3.matrix_from_quaternion(q)
    q2 = se3.quaternion_from_matrix(R, continuous=False)
    assert q2[0] >= 0
    assert np.isclose(abs(q2 @ q), 1.0, atol=1e-9)


def test_quaternion_product_matches_rotation_product():
    rng = np.random.default_rng(2)
    a, b = rng.normal(size=(2, 4))
    a /= np.linalg.norm(a)
    b /= np.linalg.norm(b)
    Rab = se3.matrix_from_quaternion(se3.quaternion_multiply(a, b))
    np.testing.assert_allclose(
        Rab, se3.matrix_from_quaternion(a) @ se3.matrix_from_quaternion(b), atol=1e-12
    )
    np.testing.assert_allclose(
        se3.quaternion_multiply(a, se3.quaternion_conjugate(a)), [1, 0, 0, 0], atol=1e-12
    )


def test_quaternion_continuity_removes_flips():
    t = np.linspace(0, 3, 200)
    q = np.column_stack([np.cos(t), np.sin(t), 0 * t, 0 * t])
    flipped = q.copy()
    flipped[50:80] *= -1
    flipped[120] *= -1
    fixed = se3.quaternion_continuity(flipped)
    np.testing.assert_allclose(fixed, q)


quat = arrays(np.float64, 4, elements=st.floats(-1.0, 1.0, allow_nan=False))


@given(quat, quat)
def test_sign_rule_keeps_the_nearer_representative(q, ref):
    """The streaming rule (NEAREST_SIGN) negates exactly when q · ref < 0 (unit quaternions)."""
    if np.linalg.norm(q) < 1e-3 or np.linalg.norm(ref) < 1e-3:
        return
    q, ref = q / np.linalg.norm(q), ref / np.linalg.norm(ref)
    d = float(q @ ref)
    aligned = se3.align_quaternion_sign(q, ref)
    if abs(d) > 1e-12:
        np.testing.assert_array_equal(aligned, -q if d < 0 else q)
    assert float(aligned @ ref) >= -1e-12
    # the reference rule (distance 0.5) negates whenever q is farther than 0.5 from ref
    far = np.linalg.norm(q - ref) > se3.REFERENCE_SIGN_THRESHOLD
    assert se3.quaternion_sign(q, ref, se3.REFERENCE_SIGN_THRESHOLD) == (-1.0 if far else 1.0)


def test_sequence_rule_is_the_single_sample_rule():
    rng = np.random.default_rng(8)
    q = rng.normal(size=(300, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    for threshold in (se3.REFERENCE_SIGN_THRESHOLD, se3.NEAREST_SIGN):
        fixed = se3.quaternion_continuity(q, threshold)
        expect = q.copy()
        for k in range(1, len(q)):
            expect[k] = se3.align_quaternion_sign(q[k], expect[k - 1], threshold)
        np.testing.assert_array_equal(fixed, expect)


def test_sclerp_endpoints_and_constant_twist():
    rng = np.random.default_rng(3)
    xi = rng.normal(size=6) * 0.4
    A = se3.pose_from_twist(rng.normal(size=6) * 0.4)
    B = A @ se3.pose_from_twist(xi)
    np.testing.assert_allclose(se3.sclerp(A, B, 0.0), A, atol=1e-12)
    np.testing.assert_allclose(se3.sclerp(A, B, 1.0), B, atol=1e-10)
    mid = se3.sclerp(A, B, 0.25)
    np.testing.assert_allclose(mid, A @ se3.pose_from_twist(0.25 * xi), atol=1e-10)


def test_interpolate_poses_equal_knots_take_left_pose_and_rejects_out_of_range():
    T = se3.pose_from_twist(np.random.default_rng(4).normal(size=(3, 6)) * 0.3)
    x = np.array([0.0, 1.0, 1.0])
    out = se3.interpolate_poses(x, T, np.array([0.0, 0.5, 1.0]))
    np.testing.assert_allclose(out[0], T[0])
    np.testing.assert_allclose(out[2], T[1], atol=1e-12)
    with pytest.raises(ValueError, match="outside"):
        se3.interpolate_poses(x, T, np.array([1.5]))


def test_central_spatial_twists_of_constant_screw_motion_and_boundary_quirk():
    xi_s = np.array([0.2, -0.1, 0.4, 0.05, 0.3, -0.2])  # spatial twist per unit progress
    ds = 0.1
    T0 = se3.pose_from_twist(np.array([0.1, 0.2, 0.3, 1.0, 2.0, 3.0]))
    T = np.array([se3.pose_from_twist(k * ds * xi_s) @ T0 for k in range(10)])
    tw = se3.central_spatial_twists(T, ds)
    np.testing.assert_allclose(tw[1:-1], np.tile(xi_s, (8, 1)), atol=1e-12)
    # one-sided differences divided by 2 ds: half the rate at both ends (reference quirk)
    np.testing.assert_allclose(tw[0], xi_s / 2, atol=1e-12)
    np.testing.assert_allclose(tw[-1], xi_s / 2, atol=1e-12)


def test_screw_axis_of_known_twist():
    # rotation about z through the point (1, 0, 0) with pitch 0.5
    w = np.array([0.0, 0.0, 2.0])
    point = np.array([1.0, 0.0, 0.0])
    v = -np.cross(w, point) + 0.5 * w
    d, p, h = se3.screw_axis(np.concatenate([w, v]))
    np.testing.assert_allclose(d, [0, 0, 1])
    np.testing.assert_allclose(p, point, atol=1e-12)
    assert np.isclose(h, 0.5)
