"""eFS (docs/algorithms/descriptors.md): golden values by hand, the circle, offsets, weighting,
invariances, singularities."""

from __future__ import annotations

import numpy as np
import pytest

from framefree import get_descriptor
from framefree.core.kalman import smooth_pose_kinematics
from framefree.core.progress import reparameterize
from framefree.descriptors.efs import EFS, efs_representation
from framefree.errors import DegenerateMotionError

from .conftest import (
    body_changed,
    circle_trajectory,
    generic_trajectory,
    pose,
    real,
    rel,
)

GENERIC = generic_trajectory()


def test_golden_values_by_hand():
    # x = (1,0,0), ẋ = (0,2,0), ẍ = (0,0,3):
    #   r1 = 1; x × ẋ = (0,0,2): r2 = 2/1 = 2
    #   x × ẍ = (0,-3,0); (x×ẋ) × (x×ẍ) = (6,0,0); · x/|x| = 6; / |x×ẋ|² = 6/4 = 1.5
    tw = np.zeros((1, 3, 6))
    tw[0, :, :3] = [[1, 0, 0], [0, 2, 0], [0, 0, 3]]
    # x = (0,0,2), ẋ = (1,0,0), ẍ = (0,1,0): r1 = 2; x × ẋ = (0,2,0): r2 = 2/4 = 0.5;
    #   x × ẍ = (-2,0,0); (0,2,0) × (-2,0,0) = (0,0,4); · x/|x| = 4; / |x×ẋ|² = 4/4 = 1
    tw[0, :, 3:] = [[0, 0, 2], [1, 0, 0], [0, 1, 0]]
    out = efs_representation(tw, offset=0.0)
    np.testing.assert_allclose(out[0], [1, 2, 1.5, 2, 0.5, 1.0], atol=1e-15)


def test_reference_offset_on_twist_and_first_derivative_only():
    rng = np.random.default_rng(2)
    tw = rng.normal(size=(5, 3, 6))
    shifted = tw.copy()
    shifted[:, :2, :] += 1e-3
    np.testing.assert_allclose(efs_representation(tw, 1e-3), efs_representation(shifted, 0.0))
    # default offset is the reference's 1e-12
    np.testing.assert_allclose(efs_representation(tw), efs_representation(tw, 1e-12))


def test_circle_curvature():
    """Arclength progress on a circle of radius R: r1 = 1, r2 = 1/R, r3 = 0 (translation block)."""
    R = 0.5
    traj = circle_trajectory(R, arc=2.0)
    rep = reparameterize(traj, "arclength")
    kin = smooth_pose_kinematics(rep.poses, rep.ds)
    out = efs_representation(kin.pose_twists)
    inner = slice(8, -8)
    np.testing.assert_allclose(out[inner, 3], 1.0, atol=1e-2)
    np.testing.assert_allclose(out[inner, 4], 1.0 / R, rtol=3e-2)
    np.testing.assert_allclose(out[inner, 5], 0.0, atol=1e-6)
    # no rotation at all: the rotational torsion is 0/0 (NaN in the reference) -> refused
    with pytest.raises(DegenerateMotionError):
        EFS(progress="arclength").compute(traj)


def test_row_weights():
    d = get_descriptor("efs", progress="angle", L=0.7, lam=0.01)
    np.testing.assert_allclose(d.row_weights(), [0.7, 0.007, 0.007, 1.0, 0.007, 0.007])
    rep = reparameterize(GENERIC, "angle")
    np.testing.assert_allclose(
        d.from_reparameterized(rep.poses, rep.ds),
        d.representation(rep.poses, rep.ds) * d.row_weights(),
    )
    assert d.compute(GENERIC).shape == (50, 6)


def test_not_body_invariant():
    d = EFS(progress="arclength", L=0.5, lam=0.1)
    a = d.compute(GENERIC)
    b = d.compute(body_changed(GENERIC, pose([0, 0, 0], [0.3, 0, 0])))
    assert rel(b, a) > 0.1
    # with angle progress the rotational block is body-invariant, the translational one is not
    d = EFS(progress="angle", L=0.5, lam=0.1)
    a = d.compute(GENERIC)
    b = d.compute(body_changed(GENERIC, pose([1.0, 0.5, -2.0], [0.05, -0.1, 0.2])))
    np.testing.assert_allclose(b[:, :3], a[:, :3], atol=1e-7 * np.abs(a[:, :3]).max())
    assert rel(b[:, 3:], a[:, 3:]) > 0.05


@pytest.mark.parametrize("progress", ["arclength", "angle", "screw"])
def test_real_recording_world_change(progress):
    d = EFS(progress=progress, L=0.5, lam=0.1)
    for name in ("ip_scooping_motion", "seg_Trial1_coffee_kettle_ref_CoM"):
        a = d.compute(real(name))
        assert rel(d.compute(real(name + "__tfworld")), a) < 1e-8
        assert rel(d.compute(real(name + "__tfbody")), a) > 0.05
