"""The way back after a gesture (v21): the stroke that takes the hand back is not the gesture again.
On real continuous motion (SFINGE3D) the hand's way back after a *swipe left* fired a second
*swipe left*; a real repeat goes the same way as the first."""

from __future__ import annotations

import math

import numpy as np
import pytest
from drawing import DT, drawn_positions, swipe_and_circle_takes, tracker_poses
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.returns import ReturnGuard

A = np.array([0.0, 0.0, 0.0])
B = np.array([0.35, 0.0, 0.0])


def _line(n: int, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, 3] = start + np.linspace(0.0, 1.0, n)[:, None] * (end - start)
    return poses


def _guard(closure: float = 0.9) -> ReturnGuard:
    """A guard that saw gesture 0 fire from A to B (running indices 0..49), a unit starting at
    60 held after it."""
    guard = ReturnGuard()
    guard.fired(0, closure, _line(50, A, B), end=49, later_starts=[60])
    return guard


def test_the_next_stroke_back_of_the_same_gesture_is_its_return():
    assert _guard().is_return(0, 60, _line(40, B, A + np.array([0.05, 0.02, 0.0])))


@pytest.mark.parametrize("gesture, start, to", [
    (0, 60, B + (B - A)),   # it goes on the same way: a repeat
    (1, 60, A),             # another gesture
    (0, 90, A),             # not the next stroke
])
def test_anything_else_is_no_return(gesture, start, to):
    assert not _guard().is_return(gesture, start, _line(40, B, to))


def test_a_closed_gesture_has_no_way_back():
    assert not _guard(closure=0.3).is_return(0, 60, _line(40, B, A))


def test_the_next_unit_may_start_after_the_gesture_fired():
    guard = ReturnGuard()
    guard.fired(0, 0.9, _line(50, A, B), end=49, later_starts=[])
    guard.unit_started(30)  # a unit inside the fired gesture is no later stroke
    guard.unit_started(70)
    guard.unit_started(120)
    assert guard.next_start == 70
    assert guard.is_return(0, 70, _line(40, B, A))


@settings(max_examples=25, deadline=None)
@given(st.floats(-math.pi, math.pi), st.floats(0.0, math.pi), st.floats(-3.0, 3.0))
def test_the_return_does_not_depend_on_the_world_frame(a, b, shift):
    """Only distances between positions enter: any rigid change of the world frame keeps it."""
    G = np.eye(4)
    G[:3, :3] = se3.rotation_from_vector(b * np.array([math.cos(a), math.sin(a), 0.5]) / math.hypot(1, 0.5))
    G[:3, 3] = [shift, 0.3 * shift, -shift]
    for to, expected in ((A + np.array([0.02, 0.05, 0.0]), True), (B + (B - A), False)):
        guard = ReturnGuard()
        guard.fired(0, 0.9, G @ _line(50, A, B), end=49, later_starts=[60])
        assert guard.is_return(0, 60, G @ _line(40, B, to)) is expected


@pytest.fixture(scope="module")
def strokes() -> tuple[list[Trajectory], list[str]]:
    """Takes of a straight swipe and of a circle."""
    return swipe_and_circle_takes(5, np.array([A, B]))


def _events(takes: list[Trajectory], labels: list[str], returns: bool) -> list[str]:
    rec = Recognizer.from_trajectories(takes, labels, returns=returns)
    rec.background = False
    # there and back and there again, the hand holding 0.6 s at each end
    P = drawn_positions(np.array([A, B, A, B]), stroke_s=0.6, hold_s=0.6)
    T = tracker_poses(P, np.eye(4))
    q = np.array([1.0, 0.0, 0.0, 0.0])  # the palm does not turn
    out = []
    for k, pose in enumerate(T):
        out += [e.label for e in rec.push(DT * k, pose[:3, 3], q)]
    return out + [e.label for e in rec.finish()]


def test_the_way_back_fires_nothing_and_a_repeat_fires_again(strokes):
    assert _events(*strokes, returns=True) == ["swipe", "swipe"]
    # without the rule the way back is a swipe too: the test can fail
    assert _events(*strokes, returns=False) == ["swipe", "swipe", "swipe"]
