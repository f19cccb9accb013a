"""How long a pending gesture waits for a longer gesture that begins the same way
(``framefree.online.continuations``), and the multi-tracker spotter's firing with those waits."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.core.trajectory import Trajectory
from framefree.datasets.people_layout import load_people
from framefree.online.candidate import Candidate
from framefree.online.config import RecognizerConfig
from framefree.online.continuations import continuation_waits
from framefree.online.evaluation import stream_rows
from framefree.online.multi import MultiRecognizer
from real_data import MACHETE, SHIPPED_MACHETE


class _Spotter:
    log = None


class _Recognizer:
    """Logs, for the take whose first position's x is k, the candidates given for k."""

    labels = ("hook", "hook", "combo", "swing")
    gestures = ("hook", "combo", "swing")
    config = RecognizerConfig()  # confirm 0.2 s

    def __init__(self, candidates):
        self.spotter, self.candidates, self.resets = _Spotter(), candidates, 0

    def reset(self):
        self.resets += 1

    def push(self, t, p, q):
        if t == 0.0:
            self.spotter.log.extend(self.candidates.get(int(p[0]), []))
        return []

    def finish(self):
        return []


def _take(k: int) -> Trajectory:
    t = np.arange(0.0, 1.0, 0.1)
    p = np.zeros((t.size, 3))
    p[:, 0] = k
    q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    return Trajectory(t, p, q)


def _cand(model: int, end_t: float, accepted: bool = True) -> Candidate:
    return Candidate(0, 1, 0.0, end_t, model, 0.1, 0.5, 1, accepted=accepted)


def test_a_gesture_accepted_inside_another_gestures_take_waits_until_that_take_ends():
    candidates = {
        0: [_cand(0, 2.0), _cand(0, 3.0, accepted=False), _cand(2, 4.0)],  # a combo's take
        1: [_cand(1, 1.5), _cand(2, 2.0, accepted=False), _cand(2, 3.5)],  # another one
        2: [_cand(0, 2.0)],  # a hook's take: its own gesture, no wait
        3: [_cand(3, 0.5), _cand(0, 0.9), _cand(3, 2.5)],  # a swing that holds a hook
    }
    rec = _Recognizer(candidates)
    # models 0 and 1 are hooks: in both combos the hook ends 2.0 s before the take's motion
    # does, in the swing 1.6 s before
    waits = continuation_waits(rec, [_take(0), _take(1), _take(2), _take(3)],
                               ["combo", "combo", "hook", "swing"])
    assert waits == {"hook": pytest.approx(2.0 + 0.2), "combo": 0.0, "swing": 0.0}
    assert rec.spotter.log is None and rec.resets == 5  # before every take, and after


def test_an_unaccepted_or_final_candidate_sets_no_wait():
    rec = _Recognizer({0: [_cand(0, 1.0, accepted=False), _cand(0, 4.0)]})
    assert continuation_waits(rec, [_take(0)], ["combo"]) == {"hook": 0.0, "combo": 0.0,
                                                              "swing": 0.0}


def test_stream_rows_of_one_tracker_and_of_several():
    take = _take(2)
    t, p, q = stream_rows(take)
    assert p.shape == (10, 3) and q.shape == (10, 4)
    sample = load_people(SHIPPED_MACHETE).of(["Sub_U001"])[0].sample
    t, p, q = stream_rows(sample)
    assert p.shape == (t.size, 2, 3) and q.shape == (t.size, 2, 4)
    np.testing.assert_array_equal(p[:, 1], sample.trackers[1].p)


@pytest.fixture(scope="module")
def recognizer():
    models = load_people(SHIPPED_MACHETE).of(["Sub_U002"])
    return MultiRecognizer.from_samples([r.sample for r in models], [r.gesture for r in models])


def test_a_pending_gesture_fires_at_its_own_wait_when_the_hands_move_on(recognizer):
    spotter = recognizer.spotter
    spotter.reset()
    assert np.all(spotter.model_waits >= recognizer.config.max_wait)
    learned = spotter.model_waits.copy()
    try:
        spotter.model_waits = np.full(len(recognizer.labels), 1.0)
        spotter.model_waits[3] = 2.5
        spotter.pending = _cand(3, 10.0)
        spotter._last_end_t = 10.0
        assert spotter.poll(11.2, resting=False) is None  # another gesture would fire at 1 s
        assert spotter.poll(12.4, resting=False) is None
        assert spotter.poll(12.5, resting=False).model == 3
        spotter.pending = _cand(0, 20.0)
        assert spotter.poll(21.0, resting=False).model == 0
    finally:
        spotter.reset()
        spotter.model_waits = learned


def test_the_confirming_rest_follows_the_hands_last_motion(recognizer):
    """The hands carried the pending gesture on until 10.6 s: the rest of ``confirm`` (0.2 s)
    counts from there, not from the candidate's end at 10.0 s."""
    spotter = recognizer.spotter
    spotter.reset()
    try:
        spotter.pending = _cand(1, 10.0)
        spotter._last_end_t = 10.6
        assert spotter.poll(10.7, resting=True) is None
        assert spotter.poll(10.8, resting=True).model == 1
    finally:
        spotter.reset()


def test_the_learned_waits_are_stored_with_their_rule(recognizer):
    waits = recognizer.learned_.continuations
    assert set(waits) == set(recognizer.gestures) and all(w >= 0 for w in waits.values())
    rule = recognizer.learned_.provenance.rules["continuations"]
    assert rule == "framefree.online.continuations.continuation_waits"


def test_a_given_wait_is_kept():
    models = load_people(SHIPPED_MACHETE).of(["Sub_U002"])
    given = {r.gesture: 3.0 for r in models}
    rec = MultiRecognizer.from_samples([r.sample for r in models], [r.gesture for r in models],
                                       continuations=given)
    assert rec.learned_.continuations == given
    assert rec.learned_.provenance.rules["continuations"] == "given"
    np.testing.assert_allclose(rec.spotter.model_waits, 3.0)


@pytest.mark.skipif(MACHETE == SHIPPED_MACHETE, reason="needs ../shared/data/machete_vive")
def test_a_hook_waits_for_the_combo_that_begins_with_it():
    """Real takes: in a *right-left-right combo* the first right hook is accepted as a *hook
    right*, and the combo's motion goes on for longer than ``max_wait`` after it; no other
    gesture of Sub_U001 begins another."""
    models = load_people(MACHETE).of(["Sub_U001"])
    rec = MultiRecognizer.from_samples([r.sample for r in models], [r.gesture for r in models])
    waits = rec.learned_.continuations
    assert waits["hook_right"] > rec.config.max_wait
    assert {g for g, w in waits.items() if w > 0} == {"hook_right"}
