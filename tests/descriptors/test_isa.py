"""ISA (docs/algorithms/descriptors.md): constant invariants recovered, weighting, bi-invariance,
singular motions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree import get_descriptor
from framefree.core.kalman import smooth_pose_kinematics
from framefree.core.progress import reparameterize
from framefree.descriptors.isa import ISA, isa_representation

from .conftest import (
    constant_isa_trajectory,
    finite_or_degenerate,
    generic_trajectory,
    pose,
    real,
    rel,
    screw_trajectory,
)

GENERIC = generic_trajectory()
W1, W2, V1, V2 = 1.2, 0.5, 0.1, 0.05
CONSTANT = constant_isa_trajectory(W1, W2, V1, V2)


def test_golden_frame_formulas_by_hand():
    # Ω = (2,0,0), Ω̇ = (0,3,0), Ω̈ = (1,-2,5), V = (1,2,3), V̇ = (4,5,6), V̈ = (7,8,9):
    #   ω1 = 2, e_x = (1,0,0); Ω×Ω̇ = (0,0,6): e_y = (0,0,1); e_z = e_x × e_y = (0,-1,0)
    #   c = -Ω̇·e_z = 3, ω2 = 3/2, ω3 = Ω̈·e_y / c = 5/3
    #   p_z = -V·e_y/ω1 = -3/2, p_y = V·e_z/ω1 = -1, p_x = -(p_z·0 + V̇·e_y)/c = -6/3 = -2
    #   v1 = V·e_x = 1; v2 = (p_y·0 - V̇·e_z - ω2 v1)/ω1 = (5 - 1.5)/2 = 7/4
    #   v3 = (p_z(Ω̈·e_x) - p_x(Ω̈·e_z) + V̈·e_y)/c - ω3(v2/ω2 + v1/ω1)
    #      = (-3/2·1 + 2·2 + 9)/3 - (5/3)(7/6 + 1/2) = 23/6 - 25/9 = 19/18
    st_ = np.zeros((1, 3, 6))
    st_[0, :, :3] = [[2, 0, 0], [0, 3, 0], [1, -2, 5]]
    st_[0, :, 3:] = [[1, 2, 3], [4, 5, 6], [7, 8, 9]]
    out = isa_representation(st_, offset=0.0)
    np.testing.assert_allclose(out[0], [2, 1.5, 5 / 3, 1, 1.75, 19 / 18], atol=1e-14)


def test_constant_invariants_with_angle_progress():
    """Per radian of rotation the invariants are (1, ω2/ω1, 0, v1/ω1, v2/ω1, 0)."""
    d = ISA(progress="angle", L=0.5, lam=1.0)
    rep = reparameterize(CONSTANT, "angle")
    out = d.representation(rep.poses, rep.ds)
    inner = slice(5, -5)
    expected = np.array([1.0, W2 / W1, 0.0, V1 / W1, V2 / W1, 0.0])
    np.testing.assert_allclose(
        out[inner, [0, 1, 3, 4]], np.tile(expected[[0, 1, 3, 4]], (40, 1)), atol=3e-3
    )
    np.testing.assert_allclose(out[inner, [2, 5]], 0.0, atol=3e-2)


def test_constant_invariants_with_screw_progress():
    """Screw path rate sqrt(L²ω1² + v1²) (ISA within L of the body origin) rescales every row."""
    L = 0.5
    d = ISA(progress="screw", L=L, lam=1.0)
    rep = reparameterize(CONSTANT, "screw", L)
    out = d.representation(rep.poses, rep.ds)
    rate = math.sqrt(L * L * W1 * W1 + V1 * V1)
    np.testing.assert_allclose(out[5:-5, 0], W1 / rate, rtol=2e-3)
    np.testing.assert_allclose(out[5:-5, 3], V1 / rate, rtol=1e-2)


def test_constant_screw_pitch_where_valid():
    """Helical motion: ω1 = 1 per radian and v1 = pitch; the other rows are singular there."""
    traj = screw_trajectory(total_angle=2.0, total_shift=0.3)
    rep = reparameterize(traj, "angle")
    kin = smooth_pose_kinematics(rep.poses, rep.ds)
    with np.errstate(all="ignore"):
        out = isa_representation(kin.spatial_twists())
    np.testing.assert_allclose(out[5:-5, 0], 1.0, atol=1e-3)
    np.testing.assert_allclose(out[5:-5, 3], 0.3 / 2.0, atol=1e-3)
    finite_or_degenerate(lambda: ISA(progress="angle").compute(traj))


def test_row_weights_have_no_L_on_the_last_two_rows():
    d = get_descriptor("isa", progress="screw", L=0.3, lam=0.01)
    np.testing.assert_allclose(d.row_weights(), [0.3, 0.003, 0.003, 1.0, 0.01, 0.01])
    rep = reparameterize(GENERIC, "screw", 0.3)
    np.testing.assert_allclose(
        d.from_reparameterized(rep.poses, rep.ds),
        d.representation(rep.poses, rep.ds) * d.row_weights(),
    )


def test_arclength_progress_is_not_offered():
    with pytest.raises(ValueError):
        ISA(progress="arclength")


@pytest.mark.parametrize("progress", ["angle", "screw"])
def test_body_frame_invariance_up_to_smoothing(progress):
    """Bi-invariant: a body change alters ISA only through smoothing/resampling (and, for screw
    progress, the clamp). Rotational rows are exactly body-invariant with angle progress."""
    d = ISA(progress=progress, L=0.5, lam=1.0)
    a = d.compute(CONSTANT)
    b = d.compute(CONSTANT.transformed(body=pose([0.5, -0.3, 2.0], [0.05, 0.02, -0.03])))
    inner = slice(5, -5)
    assert rel(b[inner], a[inner]) < 0.02
    if progress == "angle":
        np.testing.assert_allclose(b[:, :3], a[:, :3], atol=1e-8 * np.abs(a[:, :3]).max())


def test_real_recordings():
    for progress in ("angle", "screw"):
        d = ISA(progress=progress, L=0.5, lam=0.01)
        for name in ("ip_pouring_motion", "seg_Trial1_coffee_kettle_ref_CoM"):
            a = d.compute(real(name))
            assert rel(d.compute(real(name + "__tfworld")), a) < 1e-8
            # real noise: body change within ~10 % (DHB with arclength changes by 25-65 %)
            assert rel(d.compute(real(name + "__tfbody")), a) < 0.15
