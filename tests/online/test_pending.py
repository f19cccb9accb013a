"""The pending candidate when the hand moves on (v19): a longer candidate of the same gesture that
contains the pending one and fits worse does not replace it. On real continuous motion
(SFINGE3D) the hand rarely rests after a swipe; the candidate that ran on into the next motion
fired too late, or never."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from framefree.online.candidate import Candidate
from framefree.online.segmentation import Unit
from framefree.online.spotting import Spotter

GESTURES = ["circle", "circle", "swipe"]  # the gesture of each of three models


def _spotter(model_gestures: list[str] | None, fire_on_motion: bool = False) -> Spotter:
    classifier = SimpleNamespace(models=[np.zeros((5, 1))] * len(GESTURES))
    return Spotter(classifier, np.ones(len(GESTURES)), confirm=0.2, max_wait=1.0,
                   fire_on_motion=fire_on_motion, model_gestures=model_gestures)


def _candidate(start: int, end: int, model: int, ratio: float) -> Candidate:
    return Candidate(start, end, start * 0.02, end * 0.02, model, ratio, ratio, 1, accepted=True)


def _unit(start: int, end: int) -> Unit:
    return Unit(start, end, start * 0.02, end * 0.02, 0.5, False)


def _feed(spotter: Spotter, *batches: list[Candidate]) -> None:
    """Each batch: the candidates classified when one more unit ends."""
    for k, batch in enumerate(batches):
        spotter.candidates = lambda buffer, batch=batch: batch  # type: ignore[method-assign]
        assert spotter.on_unit(_unit(100 * k, 100 * k + 50), buffer=None) is None


def test_the_same_gesture_carried_on_keeps_the_pending_candidate():
    spotter = _spotter(GESTURES)
    first = _candidate(0, 50, model=0, ratio=0.3)
    _feed(spotter, [first], [_candidate(0, 150, model=1, ratio=0.6)])
    assert spotter.pending is first
    # it fires after its longest wait even though the hand never rested
    assert spotter.poll(first.end_t + 0.5, resting=False) is None
    assert spotter.poll(first.end_t + 1.0, resting=False) is first


@pytest.mark.parametrize("longer", [
    _candidate(0, 150, model=2, ratio=0.6),   # another gesture
    _candidate(20, 150, model=1, ratio=0.6),  # starts later: it does not contain the pending one
])
def test_anything_else_replaces_the_pending_candidate(longer):
    spotter = _spotter(GESTURES)
    _feed(spotter, [_candidate(0, 50, model=0, ratio=0.3)], [longer])
    assert spotter.pending is longer


def test_a_better_longer_candidate_wins_as_before():
    spotter = _spotter(GESTURES)
    better = _candidate(0, 150, model=1, ratio=0.2)
    _feed(spotter, [_candidate(0, 50, model=0, ratio=0.3)], [better])
    assert spotter.pending is better


def test_without_the_models_gestures_the_longer_candidate_replaces_it():
    spotter = _spotter(None)
    longer = _candidate(0, 150, model=1, ratio=0.6)
    _feed(spotter, [_candidate(0, 50, model=0, ratio=0.3)], [longer])
    assert spotter.pending is longer


def test_firing_on_motion_is_unchanged():
    """A spotter that fires when the motion goes on fires the pending candidate at once."""
    spotter = _spotter(GESTURES, fire_on_motion=True)
    first = _candidate(0, 50, model=0, ratio=0.3)
    _feed(spotter, [first])
    spotter.candidates = lambda buffer: [_candidate(0, 150, model=1, ratio=0.6)]  # type: ignore[method-assign]
    assert spotter.on_unit(_unit(100, 150), buffer=None) is first
