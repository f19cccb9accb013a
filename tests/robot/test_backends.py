"""Robot backends behind the one planner: the dry run logs what it would send and moves the TCP
as the planner asks; the Franka backend's command mapping; the MuJoCo backend is the simulation."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree.errors import FramefreeError
from framefree.online import Event
from framefree.robot.backends import DryRunBackend, RobotSession, franka_velocity
from framefree.robot.planner import Command, PlannerParams


def _start() -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = [0.45, 0.0, 0.35]
    return T


def test_dry_run_follows_the_planner_and_logs_commands(tmp_path):
    log = tmp_path / "commands.jsonl"
    backend = DryRunBackend(_start(), log=log)
    session = RobotSession(backend, PlannerParams())
    travel = PlannerParams().travel["go_left"]
    direction = np.asarray(PlannerParams().directions["go_left"])
    session.handle(Event("go_left", 0.5, 0.01, 0))
    session.advance_to(6.0)
    backend.close()
    moved = backend.ee_pose()[:3, 3] - _start()[:3, 3]
    # the TCP moved the planner's travel along the gesture's direction, and came to rest
    assert moved @ direction == pytest.approx(travel, abs=2e-3)
    assert np.linalg.norm(moved - (moved @ direction) * direction) < 1e-9
    assert session.planner.state == "idle" and not np.any(session.command.velocity)
    lines = [json.loads(s) for s in log.read_text().splitlines()]
    assert lines == backend.commands
    assert lines[0]["state"] == "idle" and any(c["label"] == "go_left" for c in lines)
    assert lines[-1]["velocity"] == [0.0, 0.0, 0.0]
    # nothing happens before the event's time
    first_move = next(c for c in lines if any(c["velocity"]))
    assert first_move["time"] >= 0.5 - 1e-9


def test_dry_run_stop_brakes(tmp_path):
    backend = DryRunBackend(_start())
    session = RobotSession(backend, PlannerParams())
    session.handle(Event("go_up", 0.1, 0.01, 0))
    session.handle(Event("stop", 0.6, -1.0))
    session.advance_to(0.6)
    v_before = np.linalg.norm(session.command.velocity)
    session.advance_to(2.0)
    assert v_before > 0 and not np.any(session.command.velocity)
    assert any(d.event.label == "stop" and d.accepted for d in session.planner.decisions)


def _command(v) -> Command:
    twist = np.zeros(6)
    twist[3:] = v
    return Command(twist=twist, orientation=np.eye(3), gripper_width=0.04, gripper_velocity=0.0,
                   state="move", label="go_left")


@given(st.lists(st.floats(-2, 2), min_size=3, max_size=3), st.floats(0.01, 1.0))
def test_franka_mapping_keeps_direction_and_clamps_speed(v, max_speed):
    lin, ang = franka_velocity(_command(v), max_speed)
    assert not np.any(ang)
    assert np.linalg.norm(lin) <= max_speed * (1 + 1e-12)
    v = np.asarray(v)
    if np.linalg.norm(v) <= max_speed:
        np.testing.assert_array_equal(lin, v)
    else:
        np.testing.assert_allclose(np.cross(lin, v), 0.0, atol=1e-12)
        assert lin @ v > 0


def test_franka_mapping_refuses_nan():
    with pytest.raises(FramefreeError):
        franka_velocity(_command([np.nan, 0, 0]))


def test_franka_mapping_builds_franky_motions():
    franky = pytest.importorskip("franky", reason="pip install 'framefree[franka]'")
    lin, ang = franka_velocity(_command([0.1, -0.05, 0.0]))
    twist = franky.Twist(lin.tolist(), ang.tolist())
    franky.CartesianVelocityMotion(twist, duration=franky.Duration(100))
    assert "0.1" in repr(twist) and "-0.05" in repr(twist)


def test_live_drives_the_dry_run_robot(tmp_path):
    """``framefree live --robot dry-run``: events go to the planner, its commands to stderr."""
    from click.testing import CliRunner

    from framefree.cli import cli
    from framefree.replica import make_stream, save_stream, synthesize_gesture

    rng = np.random.default_rng(7)
    for g in ("go_left", "open_gripper"):
        d = tmp_path / "models" / g / "original_1"
        d.mkdir(parents=True)
        for k in range(3):
            synthesize_gesture(g, rng).to_csv(d / f"trial_{k + 1}.csv")
    stream = save_stream(tmp_path / "s.csv", *make_stream(101, sequence=["go_left"]))
    res = CliRunner().invoke(cli, ["live", "--models", str(tmp_path / "models"), "--source",
                                   str(stream), "--speed", "0", "--no-view", "--robot", "dry-run",
                                   "--emit", f"jsonl:{tmp_path / 'ev.jsonl'}"])
    assert res.exit_code == 0, res.output
    events = [json.loads(s) for s in (tmp_path / "ev.jsonl").read_text().splitlines()]
    commands = [json.loads(s) for s in res.output.splitlines() if s.startswith('{"time"')]
    assert "commands logged" in res.output
    assert any(e["label"] == "go_left" for e in events)
    assert any(c["label"] == "go_left" and any(c["velocity"]) for c in commands)
    assert commands and commands[0]["state"] == "idle"


def test_mujoco_backend_moves_the_simulated_arm_like_the_dry_run():
    """The same planner and events against the MuJoCo Panda: the TCP goes the gesture's way."""
    pytest.importorskip("mujoco", reason="pip install 'framefree[robot]'")
    from framefree.robot.backends import MujocoBackend
    from framefree.robot.scenario import STACKING_START

    backend = MujocoBackend(q0=STACKING_START)
    p0 = backend.ee_pose()[:3, 3].copy()
    session = RobotSession(backend, PlannerParams())
    session.handle(Event("go_left", 0.2, 0.01, 0))
    session.advance_to(2.5)
    moved = backend.ee_pose()[:3, 3] - p0
    direction = np.asarray(PlannerParams().directions["go_left"])
    assert moved @ direction > 0.5 * PlannerParams().travel["go_left"]
    assert np.linalg.norm(moved - (moved @ direction) * direction) < 0.02
