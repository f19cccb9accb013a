"""``plot``, ``describe`` and ``benchmark`` leave their input folders byte-identical, with their
default outputs (the working folder), run from inside the dataset too."""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from framefree.cli import cli


def snapshot(folder: Path) -> dict[str, str]:
    """Relative path -> SHA-256 of every file and folder below ``folder``."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = str(p.relative_to(folder))
        out[rel] = hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else "<dir>"
    return out


@pytest.fixture
def small_dataset(replica_root: Path, tmp_path: Path) -> Path:
    """Two gestures × three contexts of the replica (the benchmark needs every fold)."""
    root = tmp_path / "data"
    for g in ("go_up", "open_gripper"):
        for c in ("original_1", "original_2", "world_frame_1"):
            shutil.copytree(replica_root / g / c, root / g / c)
    return root


def test_plot_describe_and_benchmark_leave_inputs_byte_identical(small_dataset, tmp_path,
                                                                  monkeypatch):
    before = snapshot(small_dataset)
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    runner = CliRunner()
    trial = small_dataset / "go_up" / "original_1" / "trial_1.csv"
    for args in (
        ["plot", str(small_dataset)],
        ["plot", str(trial)],
        ["describe", str(trial)],
        ["benchmark", "--data", str(small_dataset), "--methods", "bilts+:screw", "--jobs", "1",
         "--no-figures"],
    ):
        res = runner.invoke(cli, args)
        assert res.exit_code == 0, (args, res.output)
        if args[0] == "benchmark":  # the progress bar does not share the status lines
            status = [ln for ln in res.output.split("\n") if "running 1 row(s)" in ln]
            assert status and all(ln.startswith("running 1 row(s)") for ln in status), res.output
    assert snapshot(small_dataset) == before
    made = {p.name for p in work.iterdir()}
    assert {"data_gallery.png", "go_up_original_1_trial_1.png", "trial_1_biltsplus.csv",
            "benchmark-results"} <= made
    # a relative input from inside the dataset, with --out elsewhere: nothing lands beside it
    monkeypatch.chdir(trial.parent)
    res = runner.invoke(cli, ["describe", trial.name, "-o", str(work / "inner")])
    assert res.exit_code == 0, res.output
    assert snapshot(small_dataset) == before


def test_describe_refuses_to_overwrite_an_input(tmp_path, kettle_files):
    src = tmp_path / "k.csv"
    shutil.copy(kettle_files[0], src)
    clash = tmp_path / "k_biltsplus.csv"
    shutil.copy(kettle_files[1], clash)
    before = snapshot(tmp_path)
    res = CliRunner().invoke(cli, ["describe", str(src), str(clash), "-o", str(tmp_path)])
    assert res.exit_code == 2 and "would overwrite an input file" in res.output
    assert snapshot(tmp_path) == before


def test_a_dataset_with_a_stray_gallery_still_loads(small_dataset, tmp_path):
    (small_dataset / "gallery.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    res = CliRunner().invoke(cli, ["dataset", "info", str(small_dataset)])
    assert res.exit_code == 0, res.output
    assert "gallery.png: skipped: not a .csv recording" in res.output
