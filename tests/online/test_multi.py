"""Live recognition of two trackers (``MultiRecognizer``) on real recordings.

The shipped Machete Vive subset (tests/data/machete_vive: two people, seven whole-body gestures,
two takes each, a controller in each hand): one person's takes are the models, the other's are
played one after another as a continuous session (:func:`continuous_session`: the takes
unchanged, made-up moves and rests between them). A few seconds in all.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree import NearestNeighborClassifier
from framefree.core.multitrajectory import MultiTrajectory
from framefree.datasets.multi_sessions import continuous_session
from framefree.datasets.people_layout import load_people
from framefree.online.evaluation import match_events, run_stream
from framefree.online.multi import MultiRecognizer
from framefree.online.multi_stream import GridJoiner, grid_poses
from real_data import SHIPPED_MACHETE


@pytest.fixture(scope="module")
def people():
    ds = load_people(SHIPPED_MACHETE)
    return ds.of(["Sub_U002"]), ds.of(["Sub_U001"])


@pytest.fixture(scope="module")
def recognizer(people):
    models, _ = people
    return MultiRecognizer.from_samples([r.sample for r in models], [r.gesture for r in models])


@pytest.fixture(scope="module")
def offline(people, recognizer):
    models, _ = people
    assert recognizer.invariance == "gravity"  # the live default for several trackers
    clf = NearestNeighborClassifier(invariance="gravity")
    return clf.fit([r.sample for r in models], [r.gesture for r in models])


@pytest.fixture(scope="module")
def session(people):
    _, queries = people
    order = np.random.default_rng(1).permutation(len(queries))
    takes = [queries[k] for k in order]
    sample, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                          rate=60.0)
    return sample, segments, takes


@pytest.fixture(scope="module")
def run(recognizer, session):
    """Events and every classified candidate of the session."""
    sample, _, _ = session
    logged = []
    spotter = recognizer.spotter
    original = spotter.candidates

    def logging(buffer):
        out = original(buffer)
        logged.extend(out)
        return out

    spotter.candidates = logging
    try:
        events, _ = run_stream(recognizer, sample)
    finally:
        del spotter.candidates
    return events, logged


def test_a_recording_is_classified_live_as_offline(recognizer, offline, people):
    """The live classifier of a take's grid poses gives the label (and the distances) that the
    fitted offline classifier gives the take as recorded."""
    _, queries = people
    expected = offline.predict([r.sample for r in queries])
    for r, label in zip(queries, expected, strict=True):
        times, poses = grid_poses(r.sample)
        d, size = recognizer.classifier.distances(times, poses)
        assert recognizer.labels[int(np.argmin(d))] == label, r.path
        assert size > 0.5
    times, poses = grid_poses(queries[0].sample)
    live, _ = recognizer.classifier.distances(times, poses)
    same = recognizer.classifier.sample(times, poses)
    np.testing.assert_array_equal(live, offline.distance_matrix([same])[0])


def test_a_candidate_cut_from_the_session_gets_the_offline_label(recognizer, offline, session, run):
    """Item 2 of issue 39: the candidate the live segmenter cuts around a take (the one that
    overlaps it most) gets the label the offline classifier gives the recording."""
    _, segments, takes = session
    _, logged = run
    expected = offline.predict([r.sample for r in takes])
    whole = 0
    for seg, label in zip(segments, expected, strict=True):
        def iou(c, seg=seg):
            inter = min(c.end_t, seg.end_t) - max(c.start_t, seg.start_t)
            return max(inter, 0.0) / (max(c.end_t, seg.end_t) - min(c.start_t, seg.start_t))

        best = max(logged, key=iou)
        if iou(best) >= 0.7:
            whole += 1
            assert recognizer.labels[best.model] == label, seg
    assert whole >= 11, f"only {whole} of {len(segments)} takes were cut as one candidate"


def test_the_session_is_recognized(session, run):
    sample, segments, _ = session
    events, _ = run
    res = match_events(events, segments, float(sample.t[-1] - sample.t[0]))
    assert res.tp >= 11 and res.fp <= 3, res.summary()
    inside = [e for e in events
              if any(s.start_t <= e.time <= s.end_t + 0.5 and s.label != e.label for s in segments)]
    assert len(inside) <= 1


def test_background_classification_gives_the_inline_events(recognizer, session, run):
    sample, _, _ = session
    inline, _ = run
    recognizer.background = True
    try:
        recognizer.reset()
        P = np.stack([tr.p for tr in sample.trackers], axis=1)
        Q = np.stack([tr.q for tr in sample.trackers], axis=1)
        events = []
        for k in range(len(sample)):
            events += recognizer.push(sample.t[k], P[k], Q[k])
        events += recognizer.finish()
    finally:
        recognizer.close()
    assert [(e.label, e.time) for e in events] == [(e.label, e.time) for e in inline]


def _still(n: int, rate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    t = np.arange(n) / rate
    P = np.tile([[0.0, 0.0, 1.0], [0.0, 0.4, 1.0]], (n, 1, 1))
    Q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 2, 1))
    return t, P, Q


@pytest.mark.parametrize("hands", [{0}, {1}, {0, 1}])
def test_a_stop_signal_of_either_hand_is_one_stop(recognizer, hands):
    """A quick back-and-forth turn of one controller (far faster than any model's rotation)
    is the stop signal; both hands making it at once still give one stop."""
    rate = 90.0
    t, P, Q = _still(int(4 * rate), rate)
    k0 = int(1.5 * rate)
    w = 1.5 * recognizer.stop_threshold  # rad/s, below the instant level, a short flick
    for k in range(k0, k0 + int(0.24 * rate)):
        tau = (k - k0) / rate
        angle = w * (tau if tau < 0.12 else 0.24 - tau)
        for j in hands:
            Q[k, j] = [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]
    recognizer.reset()
    events = []
    for k in range(t.size):
        events += recognizer.push(t[k], P[k], Q[k])
    assert [e.label for e in events] == ["stop"]
    assert 1.5 <= events[0].time <= 2.1


def test_grids_that_start_apart_are_joined():
    joiner = GridJoiner(2, 0.02)
    T = np.eye(4)
    joiner.add(0, np.array([0.0, 0.02, 0.04]), np.stack([T] * 3))
    joiner.add(1, np.array([0.021, 0.041]), np.stack([T] * 2))  # starts later, 1 ms off
    ready = joiner.ready()
    assert [round(t, 3) for t, _ in ready] == [0.02, 0.04]
    assert ready[0][1].shape == (2, 4, 4)
    joiner.add(1, np.array([0.061]), T[None])
    assert joiner.ready() == []  # tracker 0 has not reached 0.06 s yet


def test_models_of_different_trackers_are_refused(people):
    models, _ = people
    one = models[0].sample
    single = MultiTrajectory((one.trackers[0],), ("a",), one.up, "one")
    with pytest.raises(ValueError, match="different numbers of trackers"):
        MultiRecognizer.from_samples([one, single], ["x", "y"])


def test_a_lost_tracker_bridges_and_nothing_breaks(recognizer, session):
    """NaN rows of one controller for 0.2 s inside the session (tracking lost) are bridged."""
    sample, _, _ = session
    P = np.stack([tr.p for tr in sample.trackers], axis=1)
    Q = np.stack([tr.q for tr in sample.trackers], axis=1)
    P[300:312, 1] = np.nan
    recognizer.reset()
    for k in range(600):
        recognizer.push(sample.t[k], P[k], Q[k])
    assert recognizer.stats["nan"] == 12 and recognizer.stats["restarts"] == 0


def test_thresholds_allow_for_the_live_cut(recognizer, people, offline):
    """τ_g is the offline P + N rule or more: P_g also comes from the takes as the live spotter
    cuts them (from the first stroke to the last), which lie a little farther from the others."""
    from framefree.online.multi_stream import live_cut
    from framefree.online.segmentation import SpeedLevels
    from framefree.rejection import thresholds_from_models

    models, _ = people
    samples, labels = [r.sample for r in models], [r.gesture for r in models]
    base = thresholds_from_models(offline.distance_matrix(samples), labels)
    assert all(recognizer.gesture_thresholds[g] >= base[g] for g in base)
    assert any(recognizer.gesture_thresholds[g] > base[g] for g in base)
    s = recognizer.learned_
    cut = live_cut(samples[0], SpeedLevels(s.rest_speed, s.move_speed), recognizer.config.descriptor.L)
    assert cut is not None and cut.t[-1] - cut.t[0] < samples[0].t[-1] - samples[0].t[0] + 1.0


def test_a_session_on_another_clock_after_a_reset_is_joined():
    """After a reset the grid starts again where the new stream starts, even before the old one."""
    joiner = GridJoiner(2, 0.02)
    T = np.eye(4)
    joiner.add(0, np.array([10.0]), T[None])
    joiner.add(1, np.array([10.0]), T[None])
    assert len(joiner.ready()) == 1
    joiner.reset()
    for j in (0, 1):
        joiner.add(j, np.array([-5.0, -4.98]), np.stack([T, T]))
    assert [t for t, _ in joiner.ready()] == [-5.0, -4.98]
