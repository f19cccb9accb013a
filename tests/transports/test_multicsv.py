"""framefree's multi-tracker CSV: round trip and one-line errors naming the row."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from framefree.errors import TrajectoryError
from framefree.io.machete import read_machete
from framefree.io.multicsv import read_multi_csv, write_multi_csv
from real_data import SHIPPED_MACHETE


@pytest.fixture(scope="module")
def sample():
    return read_machete(SHIPPED_MACHETE / "Sub_U002" / "cartwheel_left" / "ex_1_moderate",
                        names=("right", "left"))


def test_round_trip(tmp_path: Path, sample):
    path = write_multi_csv(tmp_path / "s.csv", sample)
    assert path.read_text().splitlines()[0].startswith("t,right.x,right.y,right.z,right.qw")
    back = read_multi_csv(path)
    assert back.names == ("right", "left")
    for a, b in zip(back.trackers, sample.trackers, strict=True):
        assert np.array_equal(a.t, b.t) and np.allclose(a.p, b.p, atol=0) and np.allclose(a.q, b.q)


def test_scalar_last_header_and_another_convention(tmp_path: Path):
    path = tmp_path / "xyzw.csv"
    rows = ["t,a.x,a.y,a.z,a.qx,a.qy,a.qz,a.qw"] + [f"{0.01 * k},0,{0.01 * k},0,0,0,0,1" for k in range(6)]
    path.write_text("\n".join(rows) + "\n")
    assert np.allclose(read_multi_csv(path)["a"].q, [1, 0, 0, 0])
    # y up in a SteamVR frame is z up in framefree's
    assert np.allclose(read_multi_csv(path, "openvr")["a"].p[-1], [0, 0, 0.05])


@pytest.mark.parametrize(("text", "where"), [
    ("0,0,0,0,1,0,0,0\n", "row 1"),
    ("t,a.x,a.y,a.z,a.qw,a.qx,a.qy\n", "row 1"),
    ("t,a.x,a.y,a.z,a.qw,a.qx,a.qy,a.qz\n" + "0,0,0,0,1,0,0,0\n" * 2 + "1,0,0,0,1,0,0,0\n" * 4,
     "row 3: time does not increase"),
    ("t,a.x,a.y,a.z,a.qw,a.qx,a.qy,a.qz\n" + "".join(f"{k},0,0,0,1,0,0\n" for k in range(6)),
     "row 2: 7 columns"),
    ("t,a.x,a.y,a.z,a.qw,a.qx,a.qy,a.qz\n" + "".join(f"{k},0,x,0,1,0,0,0\n" for k in range(6)),
     "row 2: a value is not a number"),
])
def test_bad_files_name_the_row(tmp_path: Path, text, where):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(TrajectoryError, match=where) as info:
        read_multi_csv(path)
    assert str(path) in str(info.value)
