"""What a new user meets in the first hour: a mistyped command, two trials with one file name, a
failed describe, the replica's trial count."""

from __future__ import annotations

import os
from pathlib import Path

from click.testing import CliRunner

from framefree.cli import cli
from framefree.replica import replica_path


def test_a_mistyped_command_gets_a_suggestion():
    res = CliRunner().invoke(cli, ["lve"])
    assert res.exit_code == 2
    assert "Did you mean 'live'?" in res.output
    res = CliRunner().invoke(cli, ["zzz"])
    assert res.exit_code == 2 and "Did you mean" not in res.output and "--help" in res.output


def test_plots_of_two_trial_1_files_do_not_overwrite_each_other(tmp_path: Path):
    replica_root = replica_path()
    runner = CliRunner()
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for gesture in ("go_up", "open_gripper"):
            res = runner.invoke(cli, ["plot", str(replica_root / gesture / "original_1" / "trial_1.csv")])
            assert res.exit_code == 0, res.output
    finally:
        os.chdir(cwd)
    assert sorted(p.name for p in tmp_path.glob("*.png")) == [
        "go_up_original_1_trial_1.png", "open_gripper_original_1_trial_1.png"]


def test_a_failed_describe_leaves_no_output_folder(tmp_path: Path):
    replica_root = replica_path()
    bad = tmp_path / "bad.csv"
    bad.write_text("not,a,pose\n")
    out = tmp_path / "descriptors"
    good = replica_root / "go_up" / "original_1" / "trial_1.csv"
    res = CliRunner().invoke(cli, ["describe", str(good), str(bad), "--out", str(out)])
    assert res.exit_code == 2 and "bad.csv" in res.output
    assert not out.exists()


def test_dataset_make_says_how_many_trials_it_wrote(tmp_path: Path):
    res = CliRunner().invoke(cli, ["dataset", "make", "--out", str(tmp_path / "r"), "--streams", "1"])
    assert res.exit_code == 0, res.output
    written = len(list((tmp_path / "r").glob("*/*/trial_*.csv")))
    assert f"wrote {written} trials" in res.output and written == 7 * 16 * 5


def test_the_live_view_fits_the_terminal(monkeypatch):
    from framefree.commands.online import _view_line

    gestures = {g: 0.1 for g in ("go_left", "go_right", "go_up", "go_down", "open", "close", "home")}
    short = {g: g[:6] for g in gestures}
    taus = dict.fromkeys(gestures, 0.2)
    for columns in (50, 80, 200):
        monkeypatch.setenv("COLUMNS", str(columns))
        assert len(_view_line(12.3, gestures, short, taus)) < columns
