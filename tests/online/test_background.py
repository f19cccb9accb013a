"""Classification off the pose path: the worker thread decides exactly what the inline recognizer
decides, events keep the source's clock, and the pose path never waits for a classification."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.online import Recognizer, spotting
from framefree.online.background import SerialWorker
from framefree.online.segmentation import PoseBuffer
from framefree.replica.people import HELDOUT_PEOPLE, person
from framefree.replica.people_streams import person_stream
from replica_recognizer import replica_recognizer


@pytest.fixture(scope="module")
def recognizer() -> Recognizer:
    rec = replica_recognizer()
    rec.warmup()
    return rec


@pytest.fixture(scope="module")
def streams():
    """Sessions of two held-out simulated people (two trackers, one per person)."""
    return [person_stream(k, person(HELDOUT_PEOPLE[k]), n_gestures=8, n_stops=1).traj
            for k in (1, 2)]


def _events(rec: Recognizer, traj) -> list[tuple[str, float, float]]:
    rec.reset()
    events = []
    for k in range(len(traj)):
        events += rec.push(traj.t[k], traj.p[k], traj.q[k])
    events += rec.finish()
    return sorted((e.label, e.time, e.dissimilarity) for e in events)


def test_background_events_are_the_inline_events(recognizer, streams):
    inline = _events(recognizer, streams[0])
    recognizer.background = True
    try:
        background = _events(recognizer, streams[0])
        assert recognizer.background
    finally:
        recognizer.close()
    assert not recognizer.background
    assert background == inline
    assert len(inline) >= 6 and any(label == "stop" for label, _, _ in inline)


def test_two_trackers_in_background_give_each_tracker_its_own_events(recognizer, streams):
    """Two recognizers, one per tracker, pushed alternately (two workers, one kernel lock)."""
    alone = [_events(recognizer, tr) for tr in streams]
    recs = [recognizer, Recognizer(recognizer.classifier, recognizer.labels, recognizer.config,
                                   recognizer.learned_)]
    for rec in recs:
        rec.reset()
        rec.background = True
    events: list[list] = [[], []]
    try:
        n = max(len(tr) for tr in streams)
        for k in range(n):
            for i, (rec, tr) in enumerate(zip(recs, streams, strict=True)):
                if k < len(tr):
                    events[i] += rec.push(tr.t[k], tr.p[k], tr.q[k])
        for i, rec in enumerate(recs):
            events[i] += rec.finish()
    finally:
        for rec in recs:
            rec.close()
    for mine, reference in zip(events, alone, strict=True):
        assert sorted((e.label, e.time, e.dissimilarity) for e in mine) == reference


def test_the_pose_path_does_not_wait_for_a_classification(recognizer, streams, monkeypatch):
    """While the worker is held inside a classification, poses keep being accepted; the events
    come afterwards with the times of the poses that fired them."""
    traj = streams[0]
    reference = _events(recognizer, traj)
    release = threading.Event()
    entered = threading.Event()
    search = spotting.SegmentClassifier.search_described

    def held(self, descriptor, accept_below=None):
        entered.set()
        release.wait()
        return search(self, descriptor, accept_below)

    monkeypatch.setattr(spotting.SegmentClassifier, "search_described", held)
    recognizer.reset()
    recognizer.background = True
    try:
        events, first = [], 0
        while not entered.is_set() and first < len(traj):
            events += recognizer.push(traj.t[first], traj.p[first], traj.q[first])
            first += 1
        assert entered.wait(60)  # a classification has started and cannot finish
        held_until = min(first + 500, len(traj))  # 10 s of poses, fewer than the worker's queue
        for k in range(first, held_until):  # holds, are still accepted
            events += recognizer.push(traj.t[k], traj.p[k], traj.q[k])
        assert [e.label for e in events if e.label != "stop"] == []
        assert recognizer.stats["samples"] == held_until
        release.set()
        for k in range(held_until, len(traj)):
            events += recognizer.push(traj.t[k], traj.p[k], traj.q[k])
        events += recognizer.finish()
    finally:
        release.set()
        recognizer.close()
    assert sorted((e.label, e.time, e.dissimilarity) for e in events) == reference


@settings(max_examples=40, deadline=None)
@given(capacity=st.integers(2, 40), count=st.integers(0, 120), back=st.integers(0, 50),
       lo=st.integers(0, 60), length=st.integers(0, 60))
def test_a_snapshot_slices_as_the_buffer_did(capacity, count, back, lo, length):
    buffer = PoseBuffer(capacity)
    for k in range(count):
        T = np.eye(4)
        T[:3, 3] = k
        buffer.append(0.02 * k, T)
    start = max(buffer.count - back, 0)
    copy = buffer.snapshot(start)
    a = max(start, lo)
    expected = buffer.slice(a, a + length)
    for k in range(capacity):  # the buffer goes on filling and overwrites; the copy does not change
        buffer.append(99.0 + k, np.eye(4))
    got = copy.slice(a, a + length)
    assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])
    assert copy.count == count
    assert copy.oldest == min(max(start, count - capacity, 0), count)


def test_the_worker_keeps_order_bounds_its_queue_and_raises_errors():
    worker = SerialWorker(max_pending=3)
    release = threading.Event()
    worker.submit(release.wait)
    for k in range(2):
        worker.submit(lambda k=k: k)
    assert len(worker) == 3
    threading.Timer(0.05, release.set).start()
    worker.submit(lambda: "fourth")  # waits for the first call: at most 3 unfinished
    assert release.is_set()
    assert worker.wait()[-3:] == [0, 1, "fourth"]
    worker.submit(lambda: 1 / 0)
    with pytest.raises(ZeroDivisionError):
        worker.wait()
    worker.close()


def test_with_a_slow_classifier_events_leave_in_time_order_and_a_stop_never_overtakes(
        recognizer, streams, monkeypatch):
    """Every classification takes 30 ms longer while the poses come as fast as they can: the
    worker falls seconds behind the pose path, and yet the events leave :meth:`push` in time
    order (a stop waits for the gestures before it), the same events as inline."""
    traj = streams[0]
    reference = _events(recognizer, traj)
    search = spotting.SegmentClassifier.search_described

    def slow(self, descriptor, accept_below=None):
        time.sleep(0.03)
        return search(self, descriptor, accept_below)

    monkeypatch.setattr(spotting.SegmentClassifier, "search_described", slow)
    recognizer.reset()
    recognizer.background = True
    arrived, lag = [], []
    try:
        for k in range(len(traj)):
            for e in recognizer.push(traj.t[k], traj.p[k], traj.q[k]):
                arrived.append(e)
                lag.append(traj.t[k] - e.time)
        arrived += recognizer.finish()
    finally:
        recognizer.close()
    times = [e.time for e in arrived]
    assert times == sorted(times)
    assert sorted((e.label, e.time, e.dissimilarity) for e in arrived) == reference
    stops = [e for e in arrived if e.is_stop]
    assert stops and len(stops) < len(arrived)
    assert max(lag) > 1.0  # the worker did fall behind: the order is not a matter of luck
