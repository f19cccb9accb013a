"""The end of a recording is the end of its motion (v29, ``run_stream(end_rest=...)``): a
gesture that a recording ends with, before the hand has rested, is decided as a rest would
decide it. SFINGE3D's sequences end within 0.2 s of their last gesture."""

from __future__ import annotations

import numpy as np
import pytest
from drawing import DT, drawn_positions, drawn_takes, tracker_poses

from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.evaluation import run_stream

SWIPE = np.array([[0.0, 0.0, 0.0], [0.35, 0.0, 0.0]])


@pytest.fixture(scope="module")
def recognizer() -> Recognizer:
    return Recognizer.from_trajectories(drawn_takes(SWIPE, 6, np.random.default_rng(2)),
                                        ["swipe"] * 6)


def _cut(after_s: float) -> Trajectory:
    """A swipe after a second of rest, the recording cut ``after_s`` after the hand stops."""
    P = drawn_positions(SWIPE, stroke_s=0.6)
    stop = round(1.0 / DT) + round(0.6 / DT)
    P = P[: stop + round(after_s / DT)]
    return Trajectory.from_poses(DT * np.arange(len(P)), tracker_poses(P, np.eye(4)))


def test_a_recording_that_ends_with_a_gesture_decides_it(recognizer):
    traj = _cut(0.0)
    assert run_stream(recognizer, traj, end_rest=0.0)[0] == []  # no rest ever came
    events, _ = run_stream(recognizer, traj)
    assert [e.label for e in events] == ["swipe"]
    assert traj.t[-1] < events[0].time <= traj.t[-1] + recognizer.config.max_wait


def test_a_recording_that_ends_at_rest_is_decided_the_same_either_way(recognizer):
    traj = _cut(1.0)
    held = [e.label for e in run_stream(recognizer, traj)[0]]
    assert held == [e.label for e in run_stream(recognizer, traj, end_rest=0.0)[0]] == ["swipe"]
