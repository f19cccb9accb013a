"""Trajectory: CSV round trip, validation and bad input, transformations."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree import Trajectory, TrajectoryError
from framefree.core import se3


def _helix(n=60, dt=0.02, t0=0.0):
    t = t0 + dt * np.arange(n)
    s = np.linspace(0, 1, n)
    p = np.column_stack([0.2 * np.cos(3 * s), 0.2 * np.sin(3 * s), 0.3 * s])
    q = np.column_stack([np.cos(s), np.sin(s) * 0.6, np.sin(s) * 0.8, 0 * s])
    return Trajectory(t, p, q, source="helix")


def _write(tmp_path: Path, text: str, name="bad.csv") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


GOOD_ROW = "0.{k},0.1,0.2,0.3,1,0,0,0"


def _rows(n):
    return "\n".join(f"{0.02 * k:.2f},{0.01 * k},0.2,0.3,1,0,0,0" for k in range(n)) + "\n"


def test_csv_round_trip_both_quaternion_orders(tmp_path):
    traj = _helix()
    for order in ("wxyz", "xyzw"):
        path = tmp_path / f"h_{order}.csv"
        traj.to_csv(path, quat_order=order)
        back = Trajectory.from_csv(path, quat_order=order)
        np.testing.assert_array_equal(back.t, traj.t)
        np.testing.assert_allclose(back.p, traj.p)
        np.testing.assert_allclose(back.q, traj.q)
    raw = np.loadtxt(tmp_path / "h_xyzw.csv", delimiter=",")
    np.testing.assert_allclose(raw[:, 7], traj.q[:, 0])


def test_exact_duplicate_rows_are_dropped(tmp_path):
    lines = _rows(8).splitlines()
    lines.insert(3, lines[2])
    traj = Trajectory.from_csv(_write(tmp_path, "\n".join(lines)))
    assert len(traj) == 8


def test_quaternions_are_renormalized_and_made_continuous():
    traj = _helix()
    q = traj.q * 3.0
    q[10:20] *= -1
    t2 = Trajectory(traj.t, traj.p, q)
    np.testing.assert_allclose(np.linalg.norm(t2.q, axis=1), 1.0)
    np.testing.assert_allclose(t2.q, traj.q, atol=1e-12)


@pytest.mark.parametrize(
    ("text", "row", "fragment"),
    [
        ("0,1,2,3,1,0,0\n", 1, "expected 8"),
        (_rows(3) + "0.06,abc,0,0,1,0,0,0\n", 4, "'abc' is not a number"),
        (_rows(3) + "0.06,nan,0,0,1,0,0,0\n" + _rows(2), 4, "not finite"),
        (_rows(3) + "0.06,inf,0,0,1,0,0,0\n", 4, "not finite"),
        (_rows(6) + "0.01,0,0,0,1,0,0,0\n", 7, "goes backwards"),
        (_rows(6) + "0.10,9,0,0,1,0,0,0\n", 7, "repeats the previous time"),
        (_rows(6) + "0.12,0,0,0,0,0,0,0\n", 7, "zero norm"),
    ],
)
def test_bad_rows_name_file_row_and_problem(tmp_path, text, row, fragment):
    path = _write(tmp_path, text)
    with pytest.raises(TrajectoryError) as info:
        Trajectory.from_csv(path)
    msg = str(info.value)
    assert str(path) in msg
    assert f"row {row}" in msg
    assert fragment in msg
    assert info.value.row == row


def test_too_few_samples_and_empty_file(tmp_path):
    with pytest.raises(TrajectoryError, match="only 3 samples"):
        Trajectory.from_csv(_write(tmp_path, _rows(3)))
    with pytest.raises(TrajectoryError, match="empty"):
        Trajectory.from_csv(_write(tmp_path, "\n\n", "empty.csv"))
    with pytest.raises(TrajectoryError, match="cannot read"):
        Trajectory.from_csv(tmp_path / "missing.csv")


def test_transformed_applies_world_left_and_body_right():
    traj = _helix()
    rng = np.random.default_rng(0)
    Tw = se3.pose_from_twist(rng.normal(size=6))
    Tb = se3.pose_from_twist(rng.normal(size=6) * 0.3)
    out = traj.transformed(world=Tw, body=Tb)
    np.testing.assert_allclose(out.poses(), Tw @ traj.poses() @ Tb, atol=1e-12)


def test_time_scaling_resampling_and_head():
    traj = _helix(n=101, t0=5.0)
    slow = traj.time_scaled(2.0)
    assert np.isclose(slow.duration, 2 * traj.duration)
    np.testing.assert_array_equal(slow.p, traj.p)
    rs = slow.resampled(0.02)
    assert len(rs) == 201
    assert rs.t[0] == traj.t[0] and np.isclose(rs.t[-1], slow.t[-1])
    # every original sample is reproduced at its own (scaled) time
    np.testing.assert_allclose(rs.p[::2], traj.p, atol=1e-12)
    assert len(traj.head(0.5)) == 51
    with pytest.raises(ValueError):
        traj.head(0.0)


@given(st.floats(0.25, 4.0))
def test_path_scaling_scales_displacements_and_keeps_orientations(factor):
    traj = _helix()
    big = traj.path_scaled(factor)
    np.testing.assert_allclose(big.p - big.p[0], factor * (traj.p - traj.p[0]), atol=1e-12)
    np.testing.assert_array_equal(big.q, traj.q)
    np.testing.assert_array_equal(big.t, traj.t)
    with pytest.raises(ValueError):
        traj.path_scaled(0.0)


@given(st.floats(0.25, 4.0))
def test_resampling_keeps_the_path(k):
    traj = _helix(n=80)
    rs = traj.time_scaled(k).resampled(0.02)
    # positions stay on the original polyline within the chord error of ScLERP
    d = np.min(np.linalg.norm(rs.p[:, None, :] - traj.p[None, :, :], axis=2), axis=1)
    assert d.max() < 0.01


def test_large_absolute_clock_costs_no_precision():
    # a Unix-like clock where the samples are still exactly representable (steps of 2^-6 s)
    a = _helix(dt=2.0**-6, t0=0.0).resampled(0.01)
    b = _helix(dt=2.0**-6, t0=2.0**30).resampled(0.01)
    np.testing.assert_allclose(a.p, b.p, atol=1e-12)
