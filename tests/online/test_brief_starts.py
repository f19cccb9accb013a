"""Candidates after a brief dip (v21): real hands seldom hold 0.2 s of rest before a swipe, but
their speed often dips below the rest level for a frame or two. Such a candidate is found, yet a
candidate after a full rest wins over it, and it fires only once the hand rests: a golf swing's
downswing, which starts after the brief stop at the top of the swing, must not fire before the
whole swing is over. And the tail of a candidate that starts after a full rest is no gesture of
its own (v22): the rest of a letter M after its first corner is an N, a zigzag turned."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from drawing import (
    DT,
    circle_positions,
    drawn_positions,
    drawn_takes,
    min_jerk,
    swipe_and_circle_takes,
    tracker_poses,
)

from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer, spotting
from framefree.online.candidate import Candidate, refuse_tails
from framefree.online.segmentation import Unit
from framefree.online.spotting import Spotter

GESTURES = ["swing", "circle"]


def _spotter() -> Spotter:
    classifier = SimpleNamespace(models=[np.zeros((5, 1))] * len(GESTURES))
    return Spotter(classifier, np.ones(len(GESTURES)), confirm=0.2, max_wait=1.0,
                   fire_on_motion=False, model_gestures=GESTURES, rest_before=0.2,
                   brief_starts=True)


def _candidate(start: int, end: int, model: int, ratio: float, after_rest: bool) -> Candidate:
    return Candidate(start, end, start * 0.02, end * 0.02, model, ratio, ratio, 1, accepted=True,
                     after_rest=after_rest)


def _unit(start: int, end: int) -> Unit:
    return Unit(start, end, start * 0.02, end * 0.02, 0.5, False)


def _classify(spotter: Spotter, batch: list[Candidate]) -> None:
    spotter.candidates = lambda buffer: batch  # type: ignore[method-assign]
    assert spotter.on_unit(_unit(0, 100), buffer=None) is None


def test_a_candidate_after_a_full_rest_wins_over_one_after_a_dip():
    spotter = _spotter()
    whole = _candidate(0, 100, model=0, ratio=0.8, after_rest=True)
    _classify(spotter, [_candidate(60, 100, model=1, ratio=0.3, after_rest=False), whole])
    assert spotter.pending is whole


def test_a_candidate_after_a_dip_is_taken_when_nothing_else_is():
    spotter = _spotter()
    part = _candidate(60, 100, model=1, ratio=0.3, after_rest=False)
    _classify(spotter, [part])
    assert spotter.pending is part


def test_a_candidate_after_a_dip_fires_only_once_the_hand_rests():
    spotter = _spotter()
    part = _candidate(60, 100, model=1, ratio=0.3, after_rest=False)
    _classify(spotter, [part])
    assert spotter.poll(part.end_t + 1.5, resting=False) is None  # still moving: it waits
    assert spotter.poll(part.end_t + 1.6, resting=True) is part


def test_a_candidate_after_a_full_rest_still_fires_after_its_longest_wait():
    spotter = _spotter()
    whole = _candidate(0, 100, model=0, ratio=0.3, after_rest=True)
    _classify(spotter, [whole])
    assert spotter.poll(whole.end_t + 1.0, resting=False) is whole


A = np.array([0.0, 0.0, 0.0])
B = np.array([0.35, 0.0, 0.0])


@pytest.fixture(scope="module")
def takes() -> tuple[list[Trajectory], list[str]]:
    """Takes of a straight swipe and of a circle."""
    return swipe_and_circle_takes(7, np.array([A, B]))


def _events(takes: list[Trajectory], labels: list[str], brief: bool) -> list[str]:
    """A circle, then at once (the hand stopping for an instant) a swipe, then rest."""
    rec = Recognizer.from_trajectories(takes, labels, brief_starts=brief)
    rec.background = False
    circle = circle_positions(radius=0.12, duration=2.0)
    rest = round(1.0 / DT)
    circle = circle[: len(circle) - rest]  # no rest after it
    start = circle[-1]
    swipe = start + min_jerk(round(0.6 / DT))[:, None] * (B - A)
    P = np.concatenate([circle, swipe, np.repeat(swipe[-1:], rest, axis=0)])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    out = []
    for k, p in enumerate(P):
        out += [e.label for e in rec.push(DT * k, p, q)]
    return out + [e.label for e in rec.finish()]


def test_a_swipe_right_after_another_motion_is_found(takes):
    assert _events(*takes, brief=True) == ["swipe"]
    # without brief starts its candidates begin at the rest before the circle: it is missed
    assert "swipe" not in _events(*takes, brief=False)


def _tail_case(part_rest: bool = False, whole_rest: bool = True, whole_model: int = 0,
               extra: int = 1) -> list[Candidate]:
    part = Candidate(60, 100, 1.2, 2.0, 0, 0.3, 0.5, 3, accepted=True, after_rest=part_rest)
    whole = Candidate(30, 100, 0.6, 2.0, whole_model, 0.6, 1.3, 3 + extra, after_rest=whole_rest)
    return refuse_tails([part, whole], lambda model: model)


def test_the_tail_of_a_candidate_from_a_rest_is_refused():
    part, whole = _tail_case()
    assert part.tail and not part.accepted
    assert whole == _tail_case()[1]
    spotter = _spotter()
    assert spotter.refusals(part) == ["tail"]


@pytest.mark.parametrize("case", [
    {"part_rest": True},  # the part starts after a full rest itself
    {"whole_rest": False},  # the longer one starts after a dip too
    {"whole_model": 1},  # the whole is nearest another gesture
    {"extra": 2},  # the whole reaches two units further back: the part follows ongoing motion
])
def test_a_part_stays_unless_it_is_the_tail_of_the_same_gesture_from_a_rest(case):
    part, _ = _tail_case(**case)
    assert part.accepted and not part.tail


Z = np.array([[0.0, 0.3, 0.0], [0.3, 0.3, 0.0], [0.0, 0.0, 0.0], [0.3, 0.0, 0.0]])


@pytest.fixture(scope="module")
def zigzag_takes() -> tuple[list[Trajectory], list[str]]:
    """Six takes of a zigzag (a Z) and six of a circle."""
    takes = drawn_takes(Z, 6, np.random.default_rng(1))
    for k in range(6):
        P = circle_positions(radius=0.1 + 0.01 * k, duration=1.8 + 0.1 * k)
        takes.append(Trajectory.from_poses(DT * np.arange(len(P)), tracker_poses(P, np.eye(4))))
    return takes, ["zigzag"] * 6 + ["circle"] * 6


def _shape_events(takes: list[Trajectory], labels: list[str]) -> list[str]:
    """From a rest, a stroke to the left, then at once an N (a zigzag turned by 90°), then rest:
    the hand stops only for an instant at each corner."""
    rec = Recognizer.from_trajectories(takes, labels)
    rec.background = False
    P = drawn_positions(np.array([[0.3, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.3, 0.0],
                                  [0.3, 0.0, 0.0], [0.3, 0.3, 0.0]]), stroke_s=0.6)
    q = np.array([1.0, 0.0, 0.0, 0.0])
    out = []
    for k, p in enumerate(P):
        out += [e.label for e in rec.push(DT * k, p, q)]
    return out + [e.label for e in rec.finish()]


def test_the_rest_of_a_shape_after_its_first_corner_fires_nothing(zigzag_takes, monkeypatch):
    assert _shape_events(*zigzag_takes) == []
    # without the rule the N after the first corner fires the zigzag
    monkeypatch.setattr(spotting, "refuse_tails", lambda batch, gesture: list(batch))
    assert _shape_events(*zigzag_takes) == ["zigzag"]
