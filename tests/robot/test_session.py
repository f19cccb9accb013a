"""End to end: scripted events → planner → controller → MuJoCo Panda moves and stacks blocks."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

from framefree.online.events import Event
from framefree.robot.scenario import (
    STACKING_PLANNER,
    STACKING_SCENE,
    STACKING_START,
    evaluate_stacking,
    paper_events,
)
from framefree.robot.session import RobotSim, run_events


def events(*pairs):
    return [Event(label, t, 0.1, 0) for t, label in pairs]


def test_scripted_session_picks_up_a_block_and_moves_it():
    log = run_events(
        events(
            (0.2, "go_left"), (3.2, "go_down"), (6.0, "close_gripper"), (7.0, "go_up"),
            (9.2, "go_right"),
        ),
        duration=12.5,
    )
    a = log.block("block_a")
    assert np.linalg.norm(a[-1, :3] - a[0, :3] - [0.0, -0.15, 0.10]) < 5e-3
    assert np.abs(log.block("block_b")[-1, :3] - log.block("block_b")[0, :3]).max() < 2e-3
    assert 0.035 < log.gripper[-1] < 0.042  # fingers closed on the 4 cm block
    assert [d.reason for d in log.decisions] == ["started"] * 5


def test_compressed_paper_timeline_stacks_a_block():
    """The paper's detected events (stop included), with the gaps shortened to 3–3.5 s."""
    paper = paper_events(start=0.5)
    t, out = 0.5, []
    for i, e in enumerate(paper):
        out.append(Event(e.label, t, e.dissimilarity, e.model))
        t += 4.0 if i == 0 else (3.0 if e.label in ("go_up", "go_down", "go_left", "go_right")
                                  else 1.6)
    log = run_events(out, planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START,
                     settle=3.0, log_rate=20)
    result = evaluate_stacking(log)
    assert result.success, result
    assert result.moved["block_c"] < 1e-3


def test_robot_sim_handles_events_live_and_orders_stop_first():
    seen = []
    robot = RobotSim(on_event=seen.append)
    robot.handle(Event("go_up", 0.1, 0.1, 0))
    robot.advance_to(0.6)
    robot.handle(Event("go_left", 0.6, 0.1, 0))
    robot.handle(Event("stop", 0.6, -1.0, -1))
    robot.advance_to(1.2)
    assert [d.reason for d in seen] == ["started", "stopping", "ignored while stopping"]
    log = robot.log()
    assert log.state[-1] == "idle"
    assert np.linalg.norm(log.v_cmd[-1]) == 0
    assert log.t[-1] == pytest.approx(1.2, abs=0.03)
