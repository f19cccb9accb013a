"""The descriptor contract, checked once for every registered descriptor and progress type.

What every descriptor must do (``framefree.descriptors.base``): declare its metadata
consistently, be invariant to world-frame changes (through its distance), change under a time
rescaling only by resampling error, either refuse a singular motion with a clear
:class:`DegenerateMotionError` or return finite values, give the benchmark's entry point
(:meth:`from_reparameterized`) the same result as :meth:`compute`, and have a distance matrix
that agrees with its pairwise distance. A new descriptor registered in
``framefree.descriptors`` is picked up here without any edit.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree import Trajectory
from framefree.core.progress import cumulative_progress, reparameterize_poses, uniform_time_poses
from framefree.descriptors import available_descriptors, get_descriptor
from framefree.descriptors.base import L_GRID, SCOPES, descriptor_class
from framefree.errors import DegenerateMotionError

from .conftest import (
    generic_trajectory,
    pose,
    pure_rotation_trajectory,
    pure_translation_trajectory,
    real,
    standstill_trajectory,
    world_changed,
)

GENERIC = generic_trajectory()
OTHER = real("ip_pouring_motion")

#: every (descriptor, progress) pair the registry offers
PAIRS = [
    (name, progress)
    for name in available_descriptors()
    for progress in descriptor_class(name).progress_types
]
#: names of the registered descriptors
NAMES = available_descriptors()


def _make(name: str, progress: str):
    return get_descriptor(name, progress=progress, L=0.4)


def _distance(name: str, progress: str, a: Trajectory, b: Trajectory) -> float:
    d = _make(name, progress)
    return float(d.distance_matrix([d.compute(b)], [d.compute(a)])[0, 0])


@pytest.mark.parametrize("name", NAMES)
def test_metadata_is_consistent(name: str) -> None:
    cls = descriptor_class(name)
    assert cls.name == name and cls.label()
    assert cls.scope in SCOPES
    assert cls.progress_types and set(cls.progress_types) <= {"arclength", "angle", "screw"}
    d = get_descriptor(name)
    assert set(d.params) == set(cls.param_names)
    assert d.with_params(L=0.3).params == {**d.params, "L": 0.3}
    for progress in cls.progress_types:
        grid = cls.parameter_grid(progress)
        if cls.trained_parameter is None:
            assert grid == ()
        else:
            assert cls.trained_parameter in cls.param_names
            assert len(grid) > 0 and list(grid) == sorted(grid) and min(grid) > 0
        assert cls.scale_length_grid(progress) in ((), L_GRID)
        assert cls.trains_scale_length(progress) == bool(cls.scale_length_grid(progress))
    if cls.supports_open_end:
        assert "open_end" in cls.param_names


@pytest.mark.parametrize(("name", "progress"), PAIRS)
def test_reparameterized_entry_point_equals_compute(name: str, progress: str) -> None:
    """The benchmark's cached path (50 Hz poses, one reparameterization, the 50 Hz arclength)
    gives exactly what :meth:`compute` gives."""
    d = _make(name, progress)
    poses50 = uniform_time_poses(GENERIC)
    rep = reparameterize_poses(poses50, progress, 0.4, 50)
    ell = float(cumulative_progress(poses50, "arclength")[-1])
    np.testing.assert_allclose(
        d.from_reparameterized(rep.poses, rep.ds, ell), d.compute(GENERIC), rtol=1e-12, atol=1e-12
    )
    if d.shares_representation:
        np.testing.assert_allclose(
            d.weight(d.representation(rep.poses, rep.ds, ell)),
            d.from_reparameterized(rep.poses, rep.ds, ell),
            rtol=1e-12,
        )


@settings(max_examples=10, deadline=None)
@given(
    rotvec=st.tuples(*[st.floats(-3, 3)] * 3),
    trans=st.tuples(*[st.floats(-2, 2)] * 3),
)
@pytest.mark.parametrize(("name", "progress"), PAIRS)
def test_world_frame_invariance(name: str, progress: str, rotvec, trans) -> None:
    """A world-frame change leaves the classifier distance at (numerically) zero, far below the
    distance to a different motion."""
    moved = world_changed(GENERIC, pose(rotvec, trans))
    same = _distance(name, progress, GENERIC, moved)
    other = _distance(name, progress, GENERIC, OTHER)
    assert same <= 1e-6 * other, (same, other)


@pytest.mark.parametrize(("name", "progress"), PAIRS)
@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_time_rescaling_changes_only_through_resampling(
    name: str, progress: str, factor: float
) -> None:
    """The same motion executed twice as fast or slow: descriptors differ by resampling error
    only, and the distance stays a small fraction of the distance to a different motion."""
    d = _make(name, progress)
    a = d.compute(GENERIC)
    b = d.compute(GENERIC.time_scaled(factor))
    assert a.shape == b.shape
    assert np.linalg.norm(a - b) / np.linalg.norm(a) < 0.02
    assert _distance(name, progress, GENERIC, GENERIC.time_scaled(factor)) < 0.02 * _distance(
        name, progress, GENERIC, OTHER
    )


@pytest.mark.parametrize(
    "motion",
    [pure_rotation_trajectory, pure_translation_trajectory, standstill_trajectory],
    ids=["pure_rotation", "pure_translation", "standstill"],
)
@pytest.mark.parametrize(("name", "progress"), PAIRS)
def test_singular_motion_raises_clearly_or_is_finite(name: str, progress: str, motion) -> None:
    traj = motion()
    try:
        out = _make(name, progress).compute(traj)
    except DegenerateMotionError as exc:
        assert str(exc)  # a message the command line can print as one line
        assert "\n" not in str(exc)
    else:
        assert np.isfinite(out).all()
    if motion is standstill_trajectory:  # no progress of any kind: always refused
        with pytest.raises(DegenerateMotionError):
            _make(name, progress).compute(traj)


@pytest.mark.parametrize(("name", "progress"), PAIRS)
def test_distance_matrix(name: str, progress: str) -> None:
    """Shape (n_queries, n_models), zero for identical sequences, non-negative, equal to the
    pairwise distance (model first)."""
    d = _make(name, progress)
    a, b = d.compute(GENERIC), d.compute(OTHER)
    D = d.distance_matrix([a, b, a], [a, b])
    assert D.shape == (3, 2)
    assert (D >= 0).all() and np.isfinite(D).all()
    np.testing.assert_allclose([D[0, 0], D[1, 1]], 0.0, atol=1e-12)
    assert D[1, 0] > 0 and D[0, 1] > 0
    np.testing.assert_array_equal(D[0], D[2])
    assert d.distance(b, a) == pytest.approx(D[0, 1], rel=1e-12)
