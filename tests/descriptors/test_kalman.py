"""Kalman/RTS smoother (docs/algorithms/smoothing.md) against the batch MAP solution, and the twists
derived from it (docs/algorithms/smoothing.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.kalman import (
    KALMAN_Q,
    P0_DIAGONAL,
    SIGMA_POSITION,
    SIGMA_ROTATION,
    VIRTUAL_VELOCITY_FACTOR,
    rts_smooth,
    rts_smooth_with_covariance,
    smooth_pose_kinematics,
    spatial_from_pose_twists,
)
from framefree.errors import DegenerateMotionError

from .conftest import pose


def batch_map(y: np.ndarray, h: float, sigma: float, q: float = KALMAN_Q):
    """The RTS smoother's answer computed directly: MAP estimate of the linear-Gaussian model.

    Unknowns θ = (x₀, e₁..e_n): the prior state and the scalar white-noise inputs, with
    x_j = F x_{j-1} + q g e_j (Q = q² g gᵀ is rank one, so the noise is a scalar per step).
    Every x_j = A_j θ. Whitened least squares over the prior, the inputs and the two measurements
    per step, solved by an orthogonal factorization (lstsq). Returns means (n, 4), covariances
    (n, 4, 4).
    """
    n = len(y)
    F = np.array([[1, h, h * h / 2, h**3 / 6], [0, 1, h, h * h / 2], [0, 0, 1, h], [0, 0, 0, 1.0]])
    g = np.array([h**4 / 24, h**3 / 6, h * h / 2, h])
    nt = 4 + n
    A = np.zeros((n, 4, nt))
    prev = np.hstack([np.eye(4), np.zeros((4, n))])
    for j in range(n):
        cur = F @ prev
        cur[:, 4 + j] += q * g
        A[j] = cur
        prev = cur
    rows, rhs = [], []
    s0 = np.sqrt(np.array(P0_DIAGONAL))
    for a in range(4):
        r = np.zeros(nt)
        r[a] = 1 / s0[a]
        rows.append(r)
        rhs.append((y[0] if a == 0 else 0.0) / s0[a])
    sv = math.sqrt(VIRTUAL_VELOCITY_FACTOR) * sigma / h
    for j in range(n):
        r = np.zeros(nt)
        r[4 + j] = 1.0
        rows.append(r)
        rhs.append(0.0)
        rows.append(A[j][0] / sigma)
        rhs.append(y[j] / sigma)
        rows.append(A[j][1] / sv)
        rhs.append(0.0)
    W = np.array(rows)
    theta = np.linalg.lstsq(W, np.array(rhs), rcond=None)[0]
    # covariance (WᵀW)⁻¹ = R⁻¹R⁻ᵀ from the triangular factor, better conditioned than the normal matrix
    Rinv = np.linalg.solve(np.linalg.qr(W, mode="r"), np.eye(nt))
    cov = Rinv @ Rinv.T
    return np.einsum("jat,t->ja", A, theta), np.einsum("jat,ts,jbs->jab", A, cov, A)


@pytest.mark.parametrize(
    ("h", "sigma"), [(0.02, SIGMA_POSITION), (0.05, SIGMA_ROTATION), (0.3, 0.002)]
)
def test_rts_equals_batch_least_squares(h, sigma):
    rng = np.random.default_rng(3)
    y = np.cumsum(rng.normal(size=12)) * 0.01 + 0.2
    xs, Ps = rts_smooth_with_covariance(y, h, sigma)
    xb, Pb = batch_map(y, h, sigma)
    scale = np.abs(xb).max(axis=0)
    np.testing.assert_allclose(xs, xb, rtol=0, atol=1e-8 * scale.max())
    for d in range(4):
        np.testing.assert_allclose(xs[:, d], xb[:, d], rtol=0, atol=1e-8 * scale[d])
    np.testing.assert_allclose(Ps, Pb, rtol=1e-6, atol=1e-9 * np.abs(Pb).max())


@given(
    st.lists(st.floats(-1, 1), min_size=3, max_size=15),
    st.floats(0.005, 0.5),
)
def test_rts_equals_batch_property(values, h):
    y = np.asarray(values)
    xs = rts_smooth(y, h, SIGMA_POSITION)
    xb, _ = batch_map(y, h, SIGMA_POSITION)
    scale = np.maximum(np.abs(xb).max(axis=0), 1e-6)
    assert np.all(np.abs(xs - xb) <= 1e-7 * scale + 1e-12)


def test_signals_are_independent_and_grouped_by_sigma():
    rng = np.random.default_rng(0)
    y = rng.normal(size=(20, 7))
    sig = np.array([SIGMA_POSITION] * 3 + [SIGMA_ROTATION] * 4)
    both = rts_smooth(y, 0.04, sig)
    assert both.shape == (20, 7, 4)
    for c in range(7):
        np.testing.assert_allclose(both[:, c], rts_smooth(y[:, c], 0.04, sig[c]), atol=1e-13)


def test_smoother_is_linear_and_shift_equivariant():
    rng = np.random.default_rng(1)
    y1, y2 = rng.normal(size=(2, 25))
    a = rts_smooth(2 * y1 - 3 * y2 + 5.0, 0.1, 0.01)
    b = 2 * rts_smooth(y1, 0.1, 0.01) - 3 * rts_smooth(y2, 0.1, 0.01)
    b[:, 0] += 5.0
    np.testing.assert_allclose(a, b, atol=1e-10)


@pytest.mark.parametrize("h", [0.0, -0.1, np.inf, np.nan])
def test_zero_step_is_degenerate(h):
    with pytest.raises(DegenerateMotionError):
        rts_smooth(np.zeros(10), h, 0.01)


def test_kinematics_of_a_constant_screw():
    """Rotation about z at 2 rad per unit progress, translation (0.1, 0, 0.3) per unit progress."""
    s = np.linspace(0, 1, 50)
    ds = s[1]
    T = np.array([pose([0, 0, 2 * u], [0.1 * u, 0, 0.3 * u]) for u in s])
    kin = smooth_pose_kinematics(T, ds)
    inner = slice(8, -8)
    np.testing.assert_allclose(kin.pose_twists[inner, 0, :3], [[0, 0, 2]] * 34, atol=2e-3)
    np.testing.assert_allclose(kin.pose_twists[inner, 0, 3:], [[0.1, 0, 0.3]] * 34, atol=1e-3)
    np.testing.assert_allclose(kin.pose_twists[inner, 1, :], 0, atol=2e-2)
    np.testing.assert_allclose(kin.pose_twists[inner, 2, :], 0, atol=0.15)
    np.testing.assert_allclose(kin.positions, T[:, :3, 3], atol=1e-4)


def test_constant_orientation_gives_exactly_zero_rotation():
    s = np.linspace(0, 1, 50)
    T = np.array([pose([0.3, -0.2, 0.1], [np.cos(u), np.sin(u), 0]) for u in s])
    kin = smooth_pose_kinematics(T, s[1])
    assert np.all(kin.pose_twists[:, :, :3] == 0.0)


def test_spatial_twists_formula():
    rng = np.random.default_rng(5)
    tw = rng.normal(size=(4, 3, 6))
    p = rng.normal(size=(4, 3))
    out = spatial_from_pose_twists(tw, p)
    w0, w1, w2 = tw[:, 0, :3], tw[:, 1, :3], tw[:, 2, :3]
    pd, pdd, pddd = tw[:, 0, 3:], tw[:, 1, 3:], tw[:, 2, 3:]
    np.testing.assert_allclose(out[:, :, :3], tw[:, :, :3])
    np.testing.assert_allclose(out[:, 0, 3:], pd + np.cross(p, w0))
    np.testing.assert_allclose(out[:, 1, 3:], pdd + np.cross(p, w1) + np.cross(pd, w0))
    np.testing.assert_allclose(
        out[:, 2, 3:], pddd + np.cross(p, w2) + 2 * np.cross(pd, w1) + np.cross(pdd, w0)
    )


def test_angular_velocity_from_quaternion_derivative_is_world_frame():
    """ω = 2 q̇ ⊗ q*: rotation R(u) = exp(u a) R0 has world angular velocity a."""
    a = np.array([0.3, -0.5, 0.8])
    R0 = se3.rotation_from_vector(np.array([1.0, 0.2, -0.4]))
    s = np.linspace(0, 1, 50)
    T = np.array([np.eye(4) for _ in s])
    T[:, :3, :3] = [se3.rotation_from_vector(u * a) @ R0 for u in s]
    kin = smooth_pose_kinematics(T, s[1])
    np.testing.assert_allclose(kin.pose_twists[10:-10, 0, :3], [a] * 30, atol=2e-3)
