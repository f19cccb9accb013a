"""Progress measures (golden values), reparameterization, streaming Algorithm 1, Gaussian smoothing."""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree import DegenerateMotionError, Trajectory
from framefree.core import se3
from framefree.core.progress import (
    StreamingReparameterizer,
    cumulative_progress,
    progress_increments,
    reparameterize,
    screw_path_increment,
)
from framefree.core.smoothing import gaussian_offsets, gaussian_smooth


def _screw_step():
    # rotation 0.2 rad about z through (0.1, 0, 0) (body coordinates) with 0.03 m along the axis
    phi = np.array([0.0, 0.0, 0.2])
    r = np.array([0.1, 0.0, 0.0])
    rho = -np.cross(phi, r) + np.array([0.0, 0.0, 0.03])
    return se3.pose_from_twist(np.concatenate([phi, rho]))


def test_screw_path_golden_values_with_and_without_clamp():
    A = se3.pose_from_twist(np.array([0.3, -0.2, 0.1, 1.0, 2.0, -1.0]))
    B = A @ _screw_step()
    # axis 0.1 m from the body origin: inside L = 0.3 -> translation along the axis (0.03 m)
    assert math.isclose(
        screw_path_increment(A, B, 0.3), math.sqrt(0.3**2 * 0.2**2 + 0.03**2), rel_tol=1e-12
    )
    # outside L = 0.05: the point at 0.05 m towards the axis moves by (0, -0.01, 0.03)
    assert math.isclose(
        screw_path_increment(A, B, 0.05), math.sqrt(0.05**2 * 0.2**2 + 0.001), rel_tol=1e-12
    )


def test_pure_translation_and_pure_rotation_progress():
    T0 = np.eye(4)
    T1 = np.eye(4)
    T1[:3, 3] = [0.3, 0.4, 0.0]
    assert math.isclose(screw_path_increment(T0, T1, 0.5), 0.5, rel_tol=1e-12)
    poses = np.stack([T0, T1])
    assert np.allclose(progress_increments(poses, "arclength"), [0.5])
    assert np.allclose(progress_increments(poses, "angle"), [0.0])
    R = np.eye(4)
    R[:3, :3] = se3.rotation_from_vector(np.array([0, 0.7, 0]))
    assert np.allclose(progress_increments(np.stack([T0, R]), "angle"), [0.7])
    assert np.allclose(progress_increments(np.stack([T0, R]), "screw", L=0.2), [0.14])


def test_reparameterization_is_equidistant_in_progress():
    t = np.linspace(0, 2, 101)
    s = 0.5 * (1 - np.cos(np.pi * t / 2))  # bell-shaped speed
    p = np.column_stack([0.4 * s, 0.1 * np.sin(3 * s), 0 * s])
    q = np.column_stack([np.cos(s), 0 * s, np.sin(s), 0 * s])
    traj = Trajectory(t, p, q)
    rep = reparameterize(traj, "screw", L=0.3, n=50)
    assert rep.poses.shape == (50, 4, 4)
    inc = progress_increments(rep.poses, "screw", 0.3)
    np.testing.assert_allclose(inc, rep.ds, rtol=2e-3)
    assert math.isclose(rep.ds * 49, rep.total)
    np.testing.assert_allclose(rep.poses[0], traj.poses()[0], atol=1e-12)
    np.testing.assert_allclose(rep.poses[-1], traj.poses()[-1], atol=1e-12)


def test_motionless_recording_is_a_clear_error():
    t = np.linspace(0, 1, 20)
    traj = Trajectory(t, np.zeros((20, 3)), np.tile([1.0, 0, 0, 0], (20, 1)), source="still.csv")
    with pytest.raises(
        DegenerateMotionError, match=r"still\.csv: the motion has no screw progress"
    ):
        reparameterize(traj, "screw", 0.3)


def test_streaming_reparameterizer_keeps_samples_past_the_resolution():
    t = np.linspace(0, 2, 201)
    p = np.column_stack([0.5 * t, 0 * t, 0 * t])
    q = np.tile([1.0, 0, 0, 0], (201, 1))
    poses = Trajectory(t, p, q).poses()
    rep = StreamingReparameterizer(resolution=0.0495, L=0.3)
    kept = [k for k, T in enumerate(poses) if rep.push(T)]
    assert kept[0] == 0
    np.testing.assert_array_equal(np.diff(kept), 10)  # 0.005 m per sample -> every 10th sample
    rep2 = StreamingReparameterizer(resolution=0.0495, L=0.3)
    np.testing.assert_array_equal(rep2.run(poses), kept)
    s = cumulative_progress(poses[kept], "screw", 0.3)
    assert np.all(np.diff(s) > 0.0495)


def test_gaussian_window_convention_even_and_odd():
    assert gaussian_offsets(10) == (5, 4)
    assert gaussian_offsets(20) == (10, 9)
    assert gaussian_offsets(5) == (2, 2)
    y = np.zeros(21)
    y[10] = 1.0
    out = gaussian_smooth(y, 10)
    # the sample 5 before the current one is in the window, the one 5 after is not
    g = np.exp(-0.5 * (np.arange(-5, 5) / 2.0) ** 2)
    assert math.isclose(out[15], g[0] / g.sum(), rel_tol=1e-12)
    assert out[5] == 0.0
    assert math.isclose(out[10], 1.0 / g.sum(), rel_tol=1e-12)
    odd = gaussian_smooth(y, 5)
    assert math.isclose(odd[10], 1.0 / (1 + 2 * math.exp(-0.5) + 2 * math.exp(-2.0)), rel_tol=1e-12)


def test_gaussian_smoothing_renormalizes_at_the_ends():
    y = np.full((12, 2), 3.5)
    np.testing.assert_allclose(gaussian_smooth(y, 10), y)
    ramp = np.arange(12.0)
    g = np.exp(-0.5 * (np.arange(0, 5) / 2.0) ** 2)  # at k = 0 only offsets 0..4 exist
    assert math.isclose(
        gaussian_smooth(ramp, 10)[0], (g * np.arange(5)).sum() / g.sum(), rel_tol=1e-12
    )
