"""The main job end to end on short sessions: held-out person → recognizer → planner → simulated Panda."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

import framefree.robot.sim  # noqa: F401  (chooses MuJoCo's offscreen GL backend before mujoco loads)

pytest.importorskip("mujoco")

from framefree.cli import cli
from framefree.replica.people import DEV_PEOPLE, HELDOUT_PEOPLE, person
from framefree.robot.demo import DEMO_PEOPLE, PersonPolicy, demo_commands, demo_person, run_demo
from framefree.robot.scenario import PAPER_TIMELINE

GESTURES = {"go_home", "go_left", "go_right", "go_up", "go_down", "open_gripper", "close_gripper"}


@pytest.fixture(scope="module")
def replica_cache(tmp_path_factory):
    """One replica for the whole module (generated on first use, in a private cache)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("FRAMEFREE_CACHE", str(tmp_path_factory.mktemp("cache")))
        yield


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


def test_demo_people_are_the_heldout_people():
    assert DEMO_PEOPLE == HELDOUT_PEOPLE
    assert not set(DEMO_PEOPLE) & set(DEV_PEOPLE)
    assert demo_person(0) == person(1000) and demo_person(7) == person(1007)
    assert demo_person(23) == person(1003)  # wraps around the 20 held-out people
    performers = [demo_person(k) for k in range(10)]
    assert len({p.seed for p in performers}) == 10
    assert len({(p.tempo, p.size) for p in performers}) == 10  # people differ, not just seeds
    with pytest.raises(ValueError, match="non-negative"):
        demo_person(-1)


def test_short_session_of_a_heldout_person_runs_end_to_end(tmp_path, replica_cache):
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
    # the default recognizer, and the held-out person of seed 3 with their style
    assert summary["method"] == result.method == "segments"
    assert summary["person"]["seed"] == result.person_seed == 1003
    style = summary["person"]["style"]
    assert style["tempo"] == pytest.approx(person(1003).tempo)
    assert style["size"] == pytest.approx(person(1003).size)
    assert set(style) >= {"tempo", "size", "skew", "pause_s", "rest_s", "tremor", "grip"}
    assert set(summary["gesture_thresholds"]) == GESTURES
    assert summary["commands"] == 2 and 2 <= summary["gestures_performed"] <= 4
    # every performed gesture is either detected or reported missed; every event has a verdict
    assert rec["tp"] + rec["fn"] == summary["gestures_performed"]
    assert len(summary["missed"]) == rec["fn"]
    for miss in summary["missed"]:  # with what the recognizer saw of each missed gesture
        assert miss["threshold"] == summary["gesture_thresholds"][miss["label"]]
        assert miss["closest"] is None or miss["closest"] > 0
    assert len(summary["events"]) == rec["tp"] + rec["fp"]
    assert all(e["verdict"] in ("tp", "fp", "fp-repeat") for e in summary["events"])
    assert all(e["robot"] != "not reached" for e in summary["events"])
    # the per-command log accounts for every attempt; a command is repeated exactly when the
    # robot did not receive it
    log = summary["command_log"]
    assert [c["label"] for c in log] == ["go_home", "go_left"]
    assert result.obeyed == summary["obeyed"] == sum(c["obeyed"] for c in log)
    assert sum(c["attempts"] for c in log) == summary["gestures_performed"]
    repeats = sum("again" in line for line in lines)
    assert repeats == summary["gestures_performed"] - 2
    assert result.obeyed >= 1  # the held-out person gets through to the robot
    assert (tmp_path / "out" / "recognition_timeline.png").stat().st_size > 10_000
    assert (tmp_path / "out" / "robot_session.png").stat().st_size > 10_000
    assert set(summary["task"]) >= {"horizontal_offset_m", "height_difference_m", "moved_m"}


def test_paper_method_runs_the_same_session(tmp_path, replica_cache):
    result = run_demo(
        tmp_path / "out",
        seed=1,
        render=False,
        echo=None,
        progress=False,
        commands=[(4.0, "go_home")],
        policy=PersonPolicy(watch=1.5, max_repeats=0),
        method="paper",
    )
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["method"] == result.method == "paper"
    assert summary["person"]["seed"] == 1001
    assert set(summary["gesture_thresholds"]) == GESTURES
    assert summary["gestures_performed"] == 1 and summary["command_log"][0]["attempts"] == 1
    assert summary["recognition"]["tp"] + summary["recognition"]["fn"] == 1


@pytest.mark.parametrize("args", [["--method", "spring"], ["--seed", "-1"]])
def test_cli_rejects_bad_options(args, tmp_path):
    res = CliRunner().invoke(cli, ["demo", "--out", str(tmp_path / "o"), "--no-render", *args])
    assert res.exit_code == 2
    assert "Invalid value" in res.output and "Traceback" not in res.output
    assert not (tmp_path / "o").exists()
