"""Recordings of several people: <person>/<gesture>/<recording>, any supported format."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from framefree.datasets.people_layout import load_people
from framefree.errors import DatasetError, TrajectoryError
from framefree.io.multicsv import write_multi_csv
from real_data import SHIPPED_MACHETE


def test_loads_the_shipped_vive_recordings():
    ds = load_people(SHIPPED_MACHETE)
    assert ds.people == ["Sub_U001", "Sub_U002"]
    assert len(ds.gestures) == 7 and len(ds) == 28
    assert all(r.sample.n_trackers == 2 for r in ds)


def test_csv_recordings_and_skipped_notes(tmp_path: Path):
    src = load_people(SHIPPED_MACHETE)
    for r in src.of(["Sub_U001"]):
        write_multi_csv(tmp_path / "alice" / r.gesture / f"{r.name}.csv", r.sample)
    (tmp_path / "alice" / "README.md").write_text("notes")
    (tmp_path / "alice" / "hook_left" / ".DS_Store").write_text("")
    ds = load_people(tmp_path)
    assert ds.people == ["alice"] and len(ds) == 14


def test_a_file_out_of_place_or_unreadable_is_named(tmp_path: Path):
    (tmp_path / "bob").mkdir()
    (tmp_path / "bob" / "stray.csv").write_text("x")
    with pytest.raises(DatasetError, match=r"stray\.csv: expected a gesture folder"):
        load_people(tmp_path)
    shutil.rmtree(tmp_path / "bob")
    (tmp_path / "bob" / "wave").mkdir(parents=True)
    (tmp_path / "bob" / "wave" / "take").write_bytes(b"\x03abc")
    with pytest.raises(TrajectoryError, match="take"):
        load_people(tmp_path)
    with pytest.raises(DatasetError, match="not a folder"):
        load_people(tmp_path / "nobody")
