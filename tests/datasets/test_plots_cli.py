"""Figures and the ``dataset`` / ``plot`` commands."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner
from matplotlib.figure import Figure

from framefree.cli import cli
from framefree.plots import plot_gallery, plot_trajectory


def test_plot_trajectory_png(replica, tmp_path: Path) -> None:
    traj = replica.select("go_up", "original_1")[0].trajectory
    fig = plot_trajectory(traj, path=tmp_path / "t.png")
    assert isinstance(fig, Figure)
    assert (tmp_path / "t.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_gallery_has_seven_panels(replica, tmp_path: Path) -> None:
    fig = plot_gallery(replica, tmp_path / "g.png")
    assert len([ax for ax in fig.axes if ax.name == "3d"]) == 7
    assert any(ax.get_ylabel() == "speed [m/s]" for ax in fig.axes)  # the colour bar
    assert (tmp_path / "g.png").stat().st_size > 10_000


def test_cli_info_and_plot(replica_root: Path, tmp_path: Path) -> None:
    runner = CliRunner()
    res = runner.invoke(cli, ["dataset", "info", str(replica_root)])
    assert res.exit_code == 0, res.output
    assert "560 trials" in res.output and "go_home" in res.output and "combination" in res.output
    res = runner.invoke(cli, ["plot", str(replica_root), "-o", str(tmp_path / "g.png")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "g.png").is_file()
    trial = replica_root / "go_left" / "slower" / "trial_2.csv"
    res = runner.invoke(cli, ["plot", str(trial), "-o", str(tmp_path / "t.png")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "t.png").is_file()


def test_cli_make_and_errors(tmp_path: Path, monkeypatch) -> None:
    runner = CliRunner()
    monkeypatch.setenv("FRAMEFREE_CACHE", str(tmp_path / "cache"))
    args = ["dataset", "make", "--out", str(tmp_path / "r"), "--seed", "2", "--streams", "1"]
    res = runner.invoke(cli, args)
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r" / "streams" / "stream_1_labels.csv").is_file()
    (tmp_path / "r" / "junk.txt").write_text("x")
    res = runner.invoke(cli, ["dataset", "info", str(tmp_path / "r")])
    assert res.exit_code == 0, res.output
    assert "junk.txt: skipped: not a .csv recording" in res.output
    (tmp_path / "r" / "loose.csv").write_text("0,0,0,0,1,0,0,0\n")
    res = runner.invoke(cli, ["dataset", "info", str(tmp_path / "r")])
    assert res.exit_code == 2
    assert "loose.csv: unexpected file" in res.output and "Traceback" not in res.output
