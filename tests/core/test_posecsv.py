"""The pose CSV reader: one clear error for every malformed file, whatever its bytes, and
warnings for implausible units and quaternion orders."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from framefree import Trajectory
from framefree.core.posecsv import (
    PlausibilityWarning,
    header_kind,
    plausibility_problems,
    read_pose_csv,
)
from framefree.errors import FramefreeError, TrajectoryError


def _rows(n: int = 20) -> np.ndarray:
    t = np.arange(n) * 0.02
    angle = np.linspace(0, 1, n)
    return np.column_stack(
        [t, 0.3 * t, 0.1 * np.sin(t), np.zeros(n), np.cos(angle / 2), np.sin(angle / 2),
         np.zeros(n), np.zeros(n)]
    )


def _write(path: Path, rows: np.ndarray, sep: str = ",") -> Path:
    path.write_text("".join(sep.join(f"{v:.9g}" for v in r) + "\n" for r in rows))
    return path


def test_a_png_image(tmp_path):
    png = tmp_path / "gallery.csv"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)))
    with pytest.raises(TrajectoryError, match=r"gallery.csv: this is a PNG image, not a pose CSV"):
        read_pose_csv(png)


def test_binary_and_non_utf8_files(tmp_path):
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"0,1,2\x00\x01\x02")
    with pytest.raises(TrajectoryError, match=r"b.csv: binary data \(NUL bytes\)"):
        read_pose_csv(binary)
    latin = tmp_path / "l.csv"
    latin.write_bytes("0,1,2,3,4,5,6,7 \u00e9\n".encode("latin-1"))
    with pytest.raises(TrajectoryError, match=r"l.csv: not UTF-8 text \(byte 0xe9 at offset 16\)"):
        read_pose_csv(latin)


def test_a_folder(tmp_path):
    with pytest.raises(TrajectoryError, match=r"is a folder, not a pose CSV file"):
        read_pose_csv(tmp_path)


def test_a_header_row_is_named_and_can_be_skipped(tmp_path):
    """A header of other names than the pose columns is named in the error and skipped on
    request; the flag never drops a first line of numbers."""
    rows = _rows()
    plain = _write(tmp_path / "plain.csv", rows)
    path = tmp_path / "h.csv"
    path.write_text("time,px,py,pz,w,i,j,k\n" + plain.read_text())
    with pytest.raises(
        TrajectoryError,
        match=r"h.csv, row 1: 'time,px,py,pz,w,i,j,k' looks like a header row; drop the header "
        r"line \(command line: --skip-header",
    ):
        read_pose_csv(path)
    np.testing.assert_array_equal(read_pose_csv(path, skip_header=True), read_pose_csv(plain))
    np.testing.assert_array_equal(read_pose_csv(plain, skip_header=True), read_pose_csv(plain))


@pytest.mark.parametrize("skip", [False, True])
def test_the_pose_column_header_is_read_by_its_names(tmp_path, skip):
    """``t,x,y,z,qw,qx,qy,qz`` is a single-tracker header, with or without ``skip_header``; a
    scalar-last header must agree with the quaternion order given."""
    plain = _write(tmp_path / "plain.csv", _rows())
    path = tmp_path / "h.csv"
    path.write_text("t,x,y,z,qw,qx,qy,qz\n" + plain.read_text())
    np.testing.assert_array_equal(read_pose_csv(path, skip_header=skip), read_pose_csv(plain))
    last = tmp_path / "xyzw.csv"
    last.write_text("t,x,y,z,qx,qy,qz,qw\n" + plain.read_text())
    with pytest.raises(TrajectoryError, match=r"xyzw.csv, row 1: the header names the quaternion "
                       r"columns qx,qy,qz,qw \(xyzw\).*--quat-order xyzw"):
        read_pose_csv(last, skip_header=skip)
    assert read_pose_csv(last, "xyzw", skip_header=skip).shape == read_pose_csv(plain).shape


@pytest.mark.parametrize(("line", "kind"), [
    ("t,x,y,z,qw,qx,qy,qz", "wxyz"), ("T, X, Y, Z, QX, QY, QZ, QW", "xyzw"),
    ("t,right.x,right.y,right.z,right.qw,right.qx,right.qy,right.qz", "multi"),
    ("0.0,1,2,3,1,0,0,0", None), ("time,x,y,z,qw,qx,qy,qz", None)])
def test_header_kind(line, kind):
    assert header_kind(line) == kind


@pytest.mark.parametrize(("sep", "name"), [(";", "semicolons"), ("\t", "tabs"), (" ", "spaces")])
def test_another_separator_is_named(tmp_path, sep, name):
    path = _write(tmp_path / "s.csv", _rows(), sep)
    with pytest.raises(TrajectoryError, match=rf"s.csv, row 1: columns are separated by {name}"):
        read_pose_csv(path)


def test_decimal_commas_with_semicolons_are_named(tmp_path):
    path = tmp_path / "eu.csv"
    path.write_text("0;0,5;0;0;1;0;0;0\n")
    with pytest.raises(TrajectoryError, match=r"row 1: columns are separated by semicolons"):
        read_pose_csv(path)


def test_units_convert_to_metres_and_millimetres_are_detected(tmp_path):
    rows = _rows()
    metres = _write(tmp_path / "m.csv", rows)
    mm_rows = rows.copy()
    mm_rows[:, 1:4] *= 1000
    mm = _write(tmp_path / "mm.csv", mm_rows)
    with pytest.warns(PlausibilityWarning, match=r"mm.csv: positions look like millimetres.*"
                      r"use --units mm"):
        Trajectory.from_csv(mm)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = Trajectory.from_csv(mm, units="mm")
        b = Trajectory.from_csv(metres)
    np.testing.assert_allclose(a.p, b.p, rtol=1e-9, atol=1e-12)
    cm_rows = rows.copy()
    cm_rows[:, 1:4] *= 100
    problems = plausibility_problems(cm_rows)
    assert len(problems) == 1 and "centimetres" in problems[0] and "--units cm" in problems[0]


def test_a_real_whole_arm_stroke_cut_to_its_motion_is_no_unit_mistake():
    """A Machete person's uppercut (shipped, MIT), cut where the hand moves faster than a fifth of
    its peak: 95 % of its speeds lie below 10.3 m/s, faster than a hand-held tracker usually
    moves but no unit mistake; the same numbers in centimetres are one."""
    from framefree.datasets.people_layout import load_people
    from real_data import SHIPPED_FAST_MACHETE

    take = next(r for r in load_people(SHIPPED_FAST_MACHETE) if r.gesture == "uppercut_right")
    tr = take.sample.trackers[0]
    speed = np.linalg.norm(np.diff(tr.p, axis=0), axis=1) / np.diff(tr.t)
    moving = np.flatnonzero(speed > 0.2 * speed.max())
    rows = tr.to_array()[moving[0]:moving[-1] + 2]
    stroke = np.linalg.norm(np.diff(rows[:, 1:4], axis=0), axis=1) / np.diff(rows[:, 0])
    assert np.percentile(stroke, 95) > 10.0
    assert plausibility_problems(rows) == []
    in_cm = rows.copy()
    in_cm[:, 1:4] *= 100
    assert "centimetres" in plausibility_problems(in_cm)[0]


def test_real_recordings_look_plausible(real_dir):
    files = sorted(real_dir.rglob("*.csv"))
    assert files
    for f in files:
        assert plausibility_problems(read_pose_csv(f)) == [], f


def test_scalar_last_file_of_an_sdk_that_keeps_the_scalar_positive(tmp_path):
    # a rotation about a tilted axis from 150° to 210°: the scalar crosses zero, so an SDK that
    # keeps it non-negative flips the quaternion's sign there
    n = 60
    angle = np.radians(np.linspace(150, 210, n))
    s = np.sin(angle / 2) / np.sqrt(2)
    q = np.column_stack([np.cos(angle / 2), s, np.zeros(n), s])
    q[q[:, 0] < 0] *= -1
    t = np.arange(n) * 0.02
    p = np.column_stack([0.2 * t, np.zeros(n), np.zeros(n)])
    xyzw = _write(tmp_path / "xyzw.csv", np.column_stack([t, p, q[:, 1:], q[:, :1]]))
    with pytest.warns(PlausibilityWarning, match=r"looks scalar-last.*--quat-order xyzw"):
        Trajectory.from_csv(xyzw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        right = Trajectory.from_csv(xyzw, quat_order="xyzw")
    np.testing.assert_allclose(np.abs(right.q[:, 0]), np.abs(np.cos(angle / 2)), atol=1e-9)
    # the same file scalar first is fine
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Trajectory.from_csv(_write(tmp_path / "wxyz.csv", np.column_stack([t, p, q])))


_NUMBERISH = st.lists(
    st.one_of(
        st.sampled_from(["0", "1", "-1", "0.5", "1e3", "nan", "inf", "", " ", "x", "t", "\u00e9"]),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
    ),
    min_size=0,
    max_size=10,
).map(",".join)


@settings(max_examples=300, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    content=st.one_of(
        st.binary(max_size=400),
        st.lists(_NUMBERISH, max_size=12).map(lambda lines: "\n".join(lines).encode()),
        st.text(max_size=300).map(lambda s: s.encode("utf-8", "surrogatepass")),
    )
)
def test_arbitrary_bytes_raise_only_framefree_errors(tmp_path, content):
    path = tmp_path / "any.csv"
    path.write_bytes(content)
    for reader in (read_pose_csv, Trajectory.from_csv):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", PlausibilityWarning)
                reader(path)
        except FramefreeError as exc:
            assert str(exc).startswith(str(path)), exc
            assert "\n" not in str(exc)
