"""DHB (docs/algorithms/descriptors.md): golden values by hand, reference quirks, weighting,
invariances, degenerate input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree import get_descriptor
from framefree.core.dtw import dtw_distance
from framefree.core.kalman import smooth_pose_kinematics
from framefree.core.progress import reparameterize
from framefree.descriptors.dhb import DHB, dhb_representation
from framefree.errors import DegenerateMotionError

from .conftest import (
    body_changed,
    circle_trajectory,
    generic_trajectory,
    pose,
    pure_rotation_trajectory,
    pure_translation_trajectory,
    real,
    rel,
    standstill_trajectory,
)

GENERIC = generic_trajectory()


def test_golden_vector_sequence_by_hand():
    # x1 = (1,0,0), x2 = (1,1,0), x3 = (0,1,1):
    #   |x| = 1, √2, √2
    #   θ¹_1 = atan(|x1×x2| / x1·x2) = atan(1/1) = π/4
    #   θ¹_2 = atan(|x2×x3| / x2·x3) = atan(√3/1) = π/3, θ¹_3 = 0 (padding)
    #   θ²_1: x2×x1 = (0,0,-1), x2×x3 = (1,-1,1): c = -1; |x2| x2·(x1×x3) = √2·(1,1,0)·(0,-1,1) = -√2
    #         θ²_1 = atan(-√2/-1) = atan(√2); θ²_2 = θ²_3 = 0 (padding)
    x = np.array([[1.0, 0, 0], [1, 1, 0], [0, 1, 1]])
    out = dhb_representation(np.hstack([x, 2 * x]))
    expected_rot = np.array(
        [
            [1, math.pi / 4, math.atan(math.sqrt(2))],
            [math.sqrt(2), math.pi / 3, 0],
            [math.sqrt(2), 0, 0],
        ]
    )
    np.testing.assert_allclose(out[:, :3], expected_rot, atol=1e-15)
    # doubling the vectors doubles the magnitudes, leaves both angles unchanged
    np.testing.assert_allclose(out[:, 3:], expected_rot * [2, 1, 1], atol=1e-15)


def test_single_argument_arctan_folds_obtuse_angles():
    # successive vectors 120° apart in a plane: atan(sin 120° / cos 120°) = atan(-√3) = -π/3
    a = np.deg2rad(120.0) * np.arange(4)
    x = np.column_stack([np.cos(a), np.sin(a), np.zeros(4)])
    out = dhb_representation(np.hstack([x, x]))
    np.testing.assert_allclose(out[:3, 1], -math.pi / 3, atol=1e-12)
    # coplanar: the second angle's numerator is 0 (c = -sin² 120° is not guarded) -> 0
    np.testing.assert_allclose(out[:, 2], 0.0, atol=1e-15)


def test_guards_return_zero_for_perpendicular_vectors():
    x = np.array([[1.0, 0, 0], [0, 1, 0], [0, 0, 1], [1e-6, 0, 0]])
    out = dhb_representation(np.hstack([x, np.zeros_like(x)]))
    assert out[0, 1] == 0.0 and out[1, 1] == 0.0  # x·x' = 0 -> guarded
    assert np.all(out[:, 3:] == 0.0)  # zero vectors: magnitude 0, both angles guarded


def test_circle_with_arclength_progress():
    """Constant orientation, circle of radius R: |ṗ| = 1, θ¹ = Δs/R, θ² = 0, no rotation."""
    R = 0.5
    traj = circle_trajectory(R, arc=2.0)
    rep = reparameterize(traj, "arclength")
    d = DHB(progress="arclength", L=0.5, lam=1.0)
    out = d.representation(rep.poses, rep.ds)
    inner = slice(6, -6)
    assert np.all(out[:, :3] == 0.0)
    # the smoother (σ = 2 mm, jerk model, weak zero-velocity prior) biases the speed by < 1 %
    np.testing.assert_allclose(out[inner, 3], 1.0, atol=1e-2)
    np.testing.assert_allclose(out[inner, 4], rep.ds / R, rtol=2e-2)
    np.testing.assert_allclose(out[:-2, 5], 0.0, atol=1e-6)
    assert out[-1, 4] == 0.0 and out[-1, 5] == 0.0 and out[-2, 5] == 0.0


def test_kinematics_can_be_shared_between_descriptors():
    rep = reparameterize(GENERIC, "angle")
    kin = smooth_pose_kinematics(rep.poses, rep.ds)
    for name in ("dhb", "efs", "isa"):
        d = get_descriptor(name, progress="angle", L=0.3, lam=0.5)
        np.testing.assert_array_equal(d.from_kinematics(kin), d.compute(GENERIC))
        np.testing.assert_array_equal(
            d.from_kinematics(kin, weighted=False), d.representation(rep.poses, rep.ds)
        )


def test_row_weights_are_a_final_step():
    rep = reparameterize(GENERIC, "screw", 0.3)
    d = get_descriptor("dhb", progress="screw", L=0.3, lam=10.0)
    np.testing.assert_allclose(d.row_weights(), [0.3, 3.0, 3.0, 1.0, 3.0, 3.0])
    raw = d.representation(rep.poses, rep.ds)
    np.testing.assert_allclose(d.from_reparameterized(rep.poses, rep.ds), raw * d.row_weights())
    np.testing.assert_allclose(d.compute(GENERIC), raw * d.row_weights())
    assert d.compute(GENERIC).shape == (50, 6)


def test_not_body_invariant_with_arclength_progress():
    """A 30 cm body offset changes the path of the body origin, hence DHB with arclength."""
    d = DHB(progress="arclength", L=0.5, lam=1.0)
    a = d.compute(GENERIC)
    b = d.compute(body_changed(GENERIC, pose([0, 0, 0], [0.3, 0, 0])))
    assert rel(b, a) > 0.1


def test_angle_progress_rotational_block_is_body_invariant_translational_is_not():
    d = DHB(progress="angle", L=0.5, lam=1.0)
    a = d.compute(GENERIC)
    b = d.compute(body_changed(GENERIC, pose([0.4, -1.0, 2.0], [0.05, 0.1, -0.3])))
    np.testing.assert_allclose(b[:, :3], a[:, :3], atol=1e-8)
    assert rel(b[:, 3:], a[:, 3:]) > 0.1


@pytest.mark.parametrize("progress", ["arclength", "angle", "screw"])
def test_real_recording_world_change(progress):
    d = DHB(progress=progress, L=0.5, lam=1.0)
    for name in ("ip_pouring_motion", "seg_Trial1_coffee_kettle_ref_CoM"):
        a = d.compute(real(name))
        b = d.compute(real(name + "__tfworld"))
        assert rel(b, a) < 1e-8
        c = d.compute(real(name + "__tfbody"))
        assert rel(c, a) > 0.05  # body change: not invariant


@pytest.mark.parametrize(
    ("traj", "progress"),
    [
        (pure_rotation_trajectory(), "arclength"),
        (pure_translation_trajectory(), "angle"),
        (standstill_trajectory(), "screw"),
    ],
)
def test_degenerate_motion_raises(traj, progress):
    with pytest.raises(DegenerateMotionError):
        DHB(progress=progress).compute(traj)


@pytest.mark.parametrize(
    ("traj", "progress"),
    [
        (pure_rotation_trajectory(), "angle"),
        (pure_rotation_trajectory(), "screw"),
        (pure_translation_trajectory(), "arclength"),
        (pure_translation_trajectory(), "screw"),
    ],
)
def test_singular_motion_is_finite(traj, progress):
    assert np.isfinite(DHB(progress=progress).compute(traj)).all()


def test_distance_is_normalized_dtw():
    d = DHB(progress="angle", L=0.5, lam=1.0)
    a = d.compute(GENERIC)
    b = d.compute(real("ip_pouring_motion"))
    D = d.distance_matrix([b, a], [a, b])
    assert D.shape == (2, 2)
    assert D[1, 0] == 0.0
    np.testing.assert_allclose(D[0, 0], dtw_distance(a, b) / (len(a) + len(b) - 1), rtol=1e-12)
    np.testing.assert_allclose(d.distance(a, b), D[0, 0], rtol=1e-12)


def test_parameters():
    d = get_descriptor("dhb")
    assert d.params == {"progress": "screw", "L": 0.5, "lam": 1.0, "n_samples": 50}
    assert d.with_params(lam=100.0).lam == 100.0
    with pytest.raises(ValueError):
        DHB(progress="time")
    with pytest.raises(ValueError):
        DHB(L=0.0)
