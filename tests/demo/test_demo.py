"""The main job end to end on a short session: person → recognizer → planner → simulated Panda."""

from __future__ import annotations

import json

import pytest

import framefree.robot.sim  # noqa: F401  (chooses MuJoCo's offscreen GL backend before mujoco loads)

pytest.importorskip("mujoco")

from framefree.demo import PersonPolicy, demo_commands, run_demo
from framefree.robot.scenario import PAPER_TIMELINE


def test_demo_commands_are_the_papers_session():
    commands = demo_commands(lead_in=6.0)
    # 21 performed gestures, three of them repeats of a command the robot had not obeyed
    assert len(commands) == 18
    assert commands[0] == (6.0, "go_home") and commands[-1] == (6.0 + 185 - 31, "go_home")
    assert [label for _, label in commands] == [
        "go_home", "go_left", "go_down", "close_gripper", "go_up", "go_right", "go_down",
        "open_gripper", "go_up", "go_left", "go_down", "close_gripper", "go_up", "go_right",
        "go_down", "open_gripper", "go_up", "go_home",
    ]  # fmt: skip
    assert len(PAPER_TIMELINE) == 21
    assert (6.0 + 92 - 31, "go_right") in commands  # first attempt's time, not the repeat's


def test_short_session_runs_end_to_end(tmp_path, monkeypatch):
    monkeypatch.setenv("FRAMEFREE_CACHE", str(tmp_path / "cache"))
    lines: list[str] = []
    result = run_demo(
        tmp_path / "out",
        seed=3,
        render=False,
        echo=lines.append,
        progress=False,
        commands=[(4.0, "go_home"), (14.0, "go_left")],
        policy=PersonPolicy(watch=1.5, max_repeats=1),
    )
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    rec = summary["recognition"]
    assert summary["commands"] == 2 and 2 <= summary["gestures_performed"] <= 4
    # every performed gesture is either detected or reported missed; every event has a verdict
    assert rec["tp"] + rec["fn"] == summary["gestures_performed"]
    assert len(summary["events"]) == rec["tp"] + rec["fp"]
    assert all(e["verdict"] in ("tp", "fp", "fp-repeat") for e in summary["events"])
    assert all(e["robot"] != "not reached" for e in summary["events"])
    assert result.obeyed == summary["obeyed"] <= 2
    # a command is repeated exactly when the robot did not receive it
    repeats = sum("again" in line for line in lines)
    assert repeats == summary["gestures_performed"] - 2
    assert (tmp_path / "out" / "recognition_timeline.png").stat().st_size > 10_000
    assert (tmp_path / "out" / "robot_session.png").stat().st_size > 10_000
    assert set(summary["task"]) >= {"horizontal_offset_m", "height_difference_m", "moved_m"}
