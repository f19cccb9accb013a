"""DSRF (docs/algorithms/descriptors.md) and its rotation-aligned distance (docs/algorithms/dtw.md):
golden screw motion, Kabsch rule, world-frame invariance of the distance (not of the descriptor),
degenerate motions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree import get_descriptor
from framefree.core import se3
from framefree.core.dtw import dtw_distance
from framefree.core.kabsch import kabsch_rotation
from framefree.descriptors.dsrf import DSRF, dsrf_alignment, dsrf_distance, dsrf_from_rates
from framefree.errors import DegenerateMotionError

from .conftest import (
    body_changed,
    generic_trajectory,
    pose,
    pure_rotation_trajectory,
    pure_translation_trajectory,
    real,
    rel,
    screw_trajectory,
    standstill_trajectory,
    world_changed,
)

GENERIC = generic_trajectory()
THETA, SHIFT = 1.5, 0.3
SCREW = screw_trajectory(THETA, SHIFT)


def test_golden_values_by_hand():
    # ω = (0, 0, 4): σω = ω / (√4 + 1e-10) = (0, 0, 2 - 1e-10 + ...); u = (3, 4, 0): |u| = 5
    out = dsrf_from_rates(np.array([[0.0, 0, 4]]), np.array([[3.0, 4, 0]]))
    np.testing.assert_allclose(
        out[0], [0, 0, 4 / (2 + 1e-10), 3 / (math.sqrt(5) + 1e-10), 4 / (math.sqrt(5) + 1e-10), 0]
    )


def test_golden_screw_motion_arclength():
    """Normalized arclength: ω = Θ ẑ, u = ẑ per unit progress (interior rows; smoothing is exact)."""
    out = DSRF(progress="arclength").compute(SCREW)
    assert out.shape == (49, 6)
    row = [0, 0, THETA / (math.sqrt(THETA) + 1e-10), 0, 0, 1 / (1 + 1e-10)]
    np.testing.assert_allclose(out[1:-1], np.tile(row, (47, 1)), atol=1e-9)


def test_alignment_is_the_kabsch_rule():
    rng = np.random.default_rng(8)
    M, Q = rng.normal(size=(2, 49, 6))
    A = np.hstack([M[:, :3].T, M[:, 3:].T])  # 3 × 98
    B = np.hstack([Q[:, :3].T, Q[:, 3:].T])
    np.testing.assert_allclose(dsrf_alignment(M, Q), kabsch_rotation(A, B), atol=1e-12)
    R = dsrf_alignment(M, Q)
    assert np.linalg.det(R) == pytest.approx(1.0)
    Mr = np.hstack([M[:, :3] @ R.T, M[:, 3:] @ R.T])
    np.testing.assert_allclose(dsrf_distance(M, Q), dtw_distance(Mr, Q) / 97, rtol=1e-12)
    D = DSRF().distance_matrix([Q, M], [M, Q])
    np.testing.assert_allclose(D[0, 0], dsrf_distance(M, Q), rtol=1e-12)
    np.testing.assert_allclose(D[0, 1], 0.0, atol=1e-12)


def test_rotated_descriptor_is_recovered():
    rng = np.random.default_rng(9)
    M = rng.normal(size=(49, 6))
    R = se3.rotation_from_vector(np.array([0.4, 2.5, -1.0]))
    Q = np.hstack([M[:, :3] @ R.T, M[:, 3:] @ R.T])
    np.testing.assert_allclose(dsrf_alignment(M, Q), R, atol=1e-12)
    assert dsrf_distance(M, Q) < 1e-12


def test_unequal_lengths_are_refused():
    with pytest.raises(ValueError):
        DSRF().distance_matrix([np.zeros((49, 6))], [np.zeros((48, 6))])


@given(
    st.tuples(*[st.floats(-3, 3)] * 3),
    st.tuples(*[st.floats(-2, 2)] * 3),
    st.sampled_from(["arclength", "angle", "screw"]),
)
def test_descriptor_rotates_with_the_world_and_the_distance_removes_it(rotvec, trans, progress):
    """DSRF-specific: the invariance lives in the distance, not the descriptor (the distance
    part for every descriptor is in test_contract.py)."""
    d = DSRF(progress=progress, L=0.4)
    a = d.compute(GENERIC)
    W = pose(rotvec, trans)
    b = d.compute(world_changed(GENERIC, W))
    # the descriptor itself rotates with the world (and ignores the world translation) ...
    R = W[:3, :3]
    np.testing.assert_allclose(b, np.hstack([a[:, :3] @ R.T, a[:, 3:] @ R.T]), atol=1e-8)
    # ... and the aligned distance removes it
    assert d.distance_matrix([b], [a])[0, 0] < 1e-8


def test_descriptor_alone_is_not_world_invariant():
    d = DSRF(progress="angle")
    a = d.compute(GENERIC)
    b = d.compute(world_changed(GENERIC, pose([0.0, 0.0, 1.0], [0, 0, 0])))
    assert rel(b, a) > 0.1


def test_not_body_invariant():
    d = DSRF(progress="arclength")
    a = d.compute(GENERIC)
    b = d.compute(body_changed(GENERIC, pose([0, 0, 0], [0.3, 0, 0])))
    assert d.distance(a, b) > 0.05


def test_real_recordings():
    for progress in ("arclength", "angle", "screw"):
        d = get_descriptor("dsrf", progress=progress, L=0.5)
        for name in ("ip_pouring_motion", "seg_Trial1_coffee_kettle_ref_CoM"):
            a = d.compute(real(name))
            w = d.compute(real(name + "__tfworld"))
            bd = d.compute(real(name + "__tfbody"))
            D = d.distance_matrix([w, bd], [a])
            assert D[0, 0] < 1e-10 and D[1, 0] > 1e-3


def test_degenerate_motions():
    with pytest.raises(DegenerateMotionError):
        DSRF(progress="angle").compute(pure_rotation_trajectory())
    with pytest.raises(DegenerateMotionError):
        DSRF(progress="screw").compute(standstill_trajectory())
    out = DSRF(progress="arclength").compute(pure_translation_trajectory())
    # no rotation (up to round-off, which the square root amplifies to ~1e-8)
    assert np.abs(out[:, :3]).max() < 1e-6 and np.isfinite(out).all()
    for name in ("syn_line_translation", "syn_circle_translation", "syn_pure_rotation_fixed_axis"):
        for progress in ("arclength", "angle", "screw"):
            try:
                assert np.isfinite(DSRF(progress=progress).compute(real(name))).all()
            except DegenerateMotionError:
                pass
