"""The main job end to end on a short script: person → recognizer → planner → simulated Panda."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("mujoco")

from framefree.datasets import StreamItem
from framefree.demo import demo_script, run_demo
from framefree.robot.scenario import PAPER_TIMELINE


def test_demo_script_is_the_papers_timeline():
    script = demo_script(lead_in=6.0)
    assert [s.label for s in script] == [performed for _, performed, _ in PAPER_TIMELINE]
    assert len(script) == 21
    assert script[0].start_t == 6.0 and script[-1].start_t == 6.0 + 185 - 31


def test_short_session_runs_end_to_end(tmp_path, monkeypatch):
    monkeypatch.setenv("FRAMEFREE_CACHE", str(tmp_path / "cache"))
    script = [StreamItem("go_home", start_t=4.0), StreamItem("go_left", start_t=14.0)]
    lines: list[str] = []
    result = run_demo(
        tmp_path / "out", seed=3, render=False, echo=lines.append, progress=False, script=script
    )
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    rec = summary["recognition"]
    # every scripted gesture is either detected or reported missed; every event has a verdict
    assert rec["tp"] + rec["fn"] == 2
    assert len(summary["events"]) == rec["tp"] + rec["fp"]
    assert all(e["verdict"] in ("tp", "fp", "fp-repeat") for e in summary["events"])
    assert all(e["robot"] != "not reached" for e in summary["events"])
    assert (tmp_path / "out" / "recognition_timeline.png").stat().st_size > 10_000
    assert (tmp_path / "out" / "robot_session.png").stat().st_size > 10_000
    assert set(summary["task"]) >= {"horizontal_offset_m", "height_difference_m", "moved_m"}
    assert result.recognition == rec
    assert any("2-gesture session" in line for line in lines)
