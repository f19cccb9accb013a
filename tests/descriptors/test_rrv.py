"""RRV (docs/algorithms/descriptors.md) and the docs/algorithms/progress.md normalization shared
with DSRF: golden screw motion, the literal normalize-then-reparameterize pipeline, SVD sign rule,
invariances, degenerate motions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree import get_descriptor
from framefree.core import se3
from framefree.core.dtw import dtw_distance
from framefree.core.progress import reparameterize, reparameterize_poses, uniform_time_poses
from framefree.core.smoothing import smooth_poses
from framefree.descriptors.families import normalized_step, rates_kernel, total_arclength
from framefree.descriptors.rrv import RRV, rrv_from_rates
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
)

GENERIC = generic_trajectory()
THETA, SHIFT = 1.5, 0.3  # total rotation about z [rad], total translation along z [m]
SCREW = screw_trajectory(THETA, SHIFT)
OFF = 1e-10


def _expected_rows(omega: float, speed: float) -> np.ndarray:
    """RRV row of a screw about z with the body origin on the axis: ω = omega ẑ, u = speed ẑ.

    U₁ = ẑ (sign rule), Uᵀa = (ω/(ω+1e-10), 0, 0), S = (cos(ω/2), sin(ω/2)·that, 0, 0);
    R(S) turns about U₁, which leaves Uᵀu = (speed, 0, 0) unchanged: ν = speed/sqrt(speed+1e-10).
    """
    a = omega / (omega + OFF)
    return np.array(
        [math.cos(omega / 2), math.sin(omega / 2) * a, 0, 0, speed / math.sqrt(speed + OFF), 0, 0]
    )


@pytest.mark.parametrize("progress", ["arclength", "angle", "screw"])
def test_golden_screw_motion(progress):
    L = 0.5
    # normalized positions: the total arclength is SHIFT; per unit normalized progress
    # arclength: ω = Θ, |u| = 1; angle: ω = 1, |u| = 1/Θ;
    # screw: path sqrt(L²Θ² + SHIFT²) / SHIFT, so ω = Θ·SHIFT/path, |u| = SHIFT/path
    path = math.hypot(L * THETA, SHIFT)
    omega, speed = {
        "arclength": (THETA, 1.0),
        "angle": (1.0, 1.0 / THETA),
        "screw": (THETA * SHIFT / path, SHIFT / path),
    }[progress]
    out = RRV(progress=progress, L=L).compute(SCREW)
    assert out.shape == (49, 7)
    # window-3 smoothing is exact in the interior for this motion, not at the two ends
    np.testing.assert_allclose(out[1:-1], np.tile(_expected_rows(omega, speed), (47, 1)), atol=1e-9)


@pytest.mark.parametrize("progress", ["arclength", "angle"])
def test_normalization_equals_the_literal_pipeline(progress):
    """docs/algorithms/progress.md literally: divide the 50 Hz positions by ℓ, then reparameterize;
    Δs of that."""
    T50 = uniform_time_poses(GENERIC)
    ell = total_arclength(T50)
    lit = T50.copy()
    lit[:, :3, 3] /= ell
    rep = reparameterize_poses(lit, progress)
    if progress == "arclength":
        assert rep.ds == pytest.approx(1 / 49, rel=1e-12)
    w, u = rates_kernel(smooth_poses(rep.poses, 3), rep.ds)
    np.testing.assert_allclose(
        RRV(progress=progress).compute(GENERIC), rrv_from_rates(w, u), atol=1e-9
    )


def test_normalized_step():
    assert normalized_step("arclength", 0.3, 2.0, 50) == 1 / 49
    assert normalized_step("angle", 0.3, 2.0, 50) == 0.3
    assert normalized_step("screw", 0.3, 2.0, 50) == 0.15


def test_from_reparameterized_reuses_a_cached_reparameterization():
    ell = total_arclength(uniform_time_poses(GENERIC))
    d = RRV(progress="screw", L=0.7)
    rep = reparameterize(GENERIC, "screw", 0.7)
    np.testing.assert_array_equal(
        d.from_reparameterized(rep.poses, rep.ds, ell), d.compute(GENERIC)
    )


def test_svd_sign_rule():
    rng = np.random.default_rng(4)
    omega = np.array([1.0, 0.3, -0.2]) + 0.2 * rng.normal(size=(30, 3))
    u = rng.normal(size=(30, 3))
    out = rrv_from_rates(omega, u)
    # recover Uᵀa_k = S_vec / sin(β_k/2); their mean Uᵀā has non-negative first two components
    beta = np.linalg.norm(omega, axis=1)
    mean_in_U = (out[:, 1:4] / np.sin(beta / 2)[:, None]).mean(axis=0)
    assert mean_in_U[0] > 0 and mean_in_U[1] >= 0
    # and U is orthonormal: |Uᵀa_k| = |a_k|
    np.testing.assert_allclose(
        np.linalg.norm(out[:, 1:4] / np.sin(beta / 2)[:, None], axis=1), beta / (beta + 1e-10)
    )
    # a world rotation of the rates leaves the descriptor unchanged
    R = se3.rotation_from_vector(np.array([2.0, -1.0, 0.5]))
    np.testing.assert_allclose(rrv_from_rates(omega @ R.T, u @ R.T), out, atol=1e-10)


def test_not_body_invariant():
    d = RRV(progress="arclength")
    a = d.compute(GENERIC)
    assert rel(d.compute(body_changed(GENERIC, pose([0, 0, 0], [0.3, 0, 0]))), a) > 0.05


def test_real_recordings():
    for progress in ("arclength", "angle", "screw"):
        d = RRV(progress=progress, L=0.5)
        for name in ("ip_pouring_motion", "seg_Trial1_coffee_kettle_ref_CoM"):
            a = d.compute(real(name))
            assert np.abs(d.compute(real(name + "__tfworld")) - a).max() < 1e-8
            assert rel(d.compute(real(name + "__tfbody")), a) > 0.02


def test_degenerate_motions():
    with pytest.raises(DegenerateMotionError):  # ℓ = 0: positions cannot be normalized
        RRV(progress="angle").compute(pure_rotation_trajectory())
    with pytest.raises(DegenerateMotionError):
        RRV(progress="arclength").compute(pure_rotation_trajectory())
    with pytest.raises(DegenerateMotionError):  # screw progress exists, ℓ does not
        RRV(progress="screw").compute(pure_rotation_trajectory())
    with pytest.raises(DegenerateMotionError):
        RRV(progress="screw").compute(standstill_trajectory())
    with pytest.raises(DegenerateMotionError):
        RRV(progress="angle").compute(pure_translation_trajectory())
    # no rotation: S = (1, 0, 0, 0), finite
    out = RRV(progress="arclength").compute(pure_translation_trajectory())
    np.testing.assert_allclose(out[:, :4], np.tile([1.0, 0, 0, 0], (49, 1)), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(out[:, 4:], axis=1)[1:-1], 1.0, atol=1e-9)
    for name in ("syn_line_translation", "syn_circle_translation", "syn_helix_screw_wobble"):
        assert np.isfinite(RRV(progress="screw").compute(real(name))).all()


def test_distance_is_generic_dtw_over_seven_columns():
    d = get_descriptor("rrv", progress="angle")
    a, b = d.compute(GENERIC), d.compute(real("ip_scooping_motion"))
    D = d.distance_matrix([a, b], [b])
    np.testing.assert_allclose(D[:, 0], [dtw_distance(b, a) / 97, 0.0], atol=1e-14)
    assert d.params == {"progress": "angle", "L": 0.5, "n_samples": 50}
