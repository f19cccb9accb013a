"""The Machete binary reader, on real Vive recordings and on broken copies of them."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from framefree.errors import TrajectoryError
from framefree.io.machete import read_machete
from real_data import SHIPPED_MACHETE

FILE = SHIPPED_MACHETE / "Sub_U001" / "hook_right" / "ex_0_moderate"


def test_reads_two_controllers_in_framefree_frame():
    sample = read_machete(FILE)
    assert sample.names == ("controller_0", "controller_1")
    assert sample.t[0] == 0.0 and np.all(np.diff(sample.t) > 0)
    assert 1.0 < sample.t[-1] < 6.0 and 80 < len(sample) / sample.t[-1] < 100  # ~90 Hz
    right, left = sample.trackers
    # z is up after the conversion: hands at about chest height, and the punching hand moves most
    assert 0.8 < np.median(right.p[:, 2]) < 1.8
    assert np.ptp(right.p, axis=0).max() > 3 * np.ptp(left.p, axis=0).max()
    assert np.allclose(np.linalg.norm(right.q, axis=1), 1.0)


def test_a_dropout_frame_is_left_out(tmp_path: Path):
    data = bytearray(FILE.read_bytes())
    name_len = data[0]
    n = struct.unpack_from("<i", data, 1 + name_len + 4)[0]
    first_frame = 1 + name_len + 12
    data[first_frame + 5 * 56:first_frame + 6 * 56] = bytes(56)  # frame 6: all zero
    bad = tmp_path / "dropout"
    bad.write_bytes(bytes(data))
    assert len(read_machete(bad)) == len(read_machete(FILE)) - 1 == n - 1


@pytest.mark.parametrize(("cut", "message"), [
    (lambda b: b[:40], "file ends inside the frames"),
    (lambda b: b + b"\x00\x00", "bytes after the last time stamp"),
    (lambda b: b[:1] + b"\xff\xfe" + b[3:], "not UTF-8|values per frame|file ends"),
])
def test_broken_files_give_one_line(tmp_path: Path, cut, message):
    path = tmp_path / "broken"
    path.write_bytes(cut(FILE.read_bytes()))
    with pytest.raises(TrajectoryError, match=message) as info:
        read_machete(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_a_folder_or_a_csv_is_not_a_recording(tmp_path: Path):
    with pytest.raises(TrajectoryError, match="folder"):
        read_machete(tmp_path)
    csv = tmp_path / "x.csv"
    csv.write_text("0,0,0,0,1,0,0,0\n")
    with pytest.raises(TrajectoryError):
        read_machete(csv)
