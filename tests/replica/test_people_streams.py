"""Sessions performed by simulated people: the full repertoire between gestures, labels that stay
consistent, the person's tempo in the labelled durations, and the closed-loop person."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.datasets import STOP
from framefree.replica import (
    DEFAULT_PERSON,
    DEV_PEOPLE,
    HELDOUT_PEOPLE,
    PERSON_ACTIVITIES,
    LivePerson,
    StreamItem,
    make_person_streams,
    make_stream,
    person,
    person_stream,
)
from framefree.replica.activities import REACH, Session, _reach_stay, _scratch
from framefree.replica.motion import make_pose


@pytest.fixture(scope="module")
def streams():
    """One 14-gesture session of a development and of a held-out person."""
    return make_person_streams([DEV_PEOPLE[1], HELDOUT_PEOPLE[2]], n_streams_per_person=1,
                               n_gestures=14)


def test_streams_have_the_whole_repertoire(streams) -> None:
    kinds = {a.kind for ps in streams for a in ps.activities}
    assert set(PERSON_ACTIVITIES) <= kinds
    assert {"approach", "settle", "rest", "gesture", "stop", "idle"} <= kinds


@pytest.mark.parametrize("index", [0, 1])
def test_labels_and_activities_are_consistent(streams, index: int) -> None:
    ps = streams[index]
    traj, segs, acts = ps.traj, ps.segments, ps.activities
    assert sum(s.label != STOP for s in segs) == 14
    for a, b in itertools.pairwise(segs):
        assert a.end_t < b.start_t
    for a, b in itertools.pairwise(acts):
        assert b.start_t == pytest.approx(a.end_t)  # one activity after the other, no gap
    assert acts[0].start_t == 0.0 and acts[-1].end_t == pytest.approx(traj.t[-1], abs=0.05)
    performed = [(a.label if a.kind == "gesture" else STOP, a.start_t, a.end_t)
                 for a in acts if a.kind in ("gesture", "stop")]
    assert performed == [(s.label, s.start_t, s.end_t) for s in segs]
    v = np.linalg.norm(np.diff(traj.p, axis=0), axis=1) / np.diff(traj.t)
    for s in segs:
        inside = (traj.t[1:] >= s.start_t) & (traj.t[1:] <= s.end_t)
        assert v[inside].max() > 0.1 or s.label == STOP


def test_person_streams_are_deterministic_and_match_make_stream(streams) -> None:
    who = person(HELDOUT_PEOPLE[2])
    again = person_stream(streams[1].stream_seed, who, n_gestures=14)
    np.testing.assert_array_equal(again.traj.to_array(), streams[1].traj.to_array())
    traj, segs = make_stream(streams[1].stream_seed, n_gestures=14, person=who)
    np.testing.assert_array_equal(traj.to_array(), streams[1].traj.to_array())
    assert segs == streams[1].segments
    assert streams[0].stream_seed != streams[1].stream_seed


def test_dev_and_heldout_sessions_never_share_a_seed() -> None:
    dev = {1000 * p + k for p in DEV_PEOPLE for k in range(100)}
    held = {1000 * p + k for p in HELDOUT_PEOPLE for k in range(100)}
    assert not dev & held


def test_quick_person_performs_faster_than_slow_one() -> None:
    base = dataclasses.replace(person(4), pause=(0.1, 0.1))
    script = ["go_left", "go_up", "go_right", "open_gripper", "go_home", "go_down"]

    def mean_duration(tempo: float) -> float:
        _, segs = make_stream(8, script, person=dataclasses.replace(base, tempo=tempo))
        return float(np.mean([s.end_t - s.start_t for s in segs]))

    ratio = mean_duration(0.6) / mean_duration(1.6)
    assert 2.0 < ratio < 3.0  # strokes 1.6 / 0.6 ≈ 2.7 times as long; the pause is the same


def _walk_turns(ps) -> list[float]:
    """Rotation [deg] of the tracker across every walk-and-turn (the hand is held meanwhile)."""
    T = ps.traj.poses()
    out = []
    for a in ps.activities:
        if a.kind == "walk_turn":
            i, j = np.searchsorted(ps.traj.t, [a.start_t, a.end_t])
            dR = T[i, :3, :3].T @ T[min(j, len(T) - 1), :3, :3]
            out.append(float(np.degrees(np.linalg.norm(se3.vector_from_rotation(dR)))))
    return out


def test_walk_and_turn_turns_the_body(streams) -> None:
    turns = [x for ps in streams for x in _walk_turns(ps)]
    assert turns
    assert all(35 < x < 185 for x in turns)


def _scratch_session(who, seed: int) -> Session:
    home = make_pose(np.eye(3), who.hand_position)
    s = Session(home, np.eye(4), np.eye(4), who)
    _scratch(s, np.random.default_rng(seed))
    return s


def test_scratching_loops_are_small_fast_and_few() -> None:
    who = person(DEV_PEOPLE[0])
    found = 0
    for seed in range(12):
        s = _scratch_session(who, seed)
        if len(s.hand.pieces) != 1:  # moved elsewhere first
            continue
        found += 1
        d = s.time
        t = np.linspace(0.0, d, 600)
        p = s.hand.at(t)[:, :3, 3]
        assert 0.005 < np.ptp(p, axis=0).max() < 0.045
        dev = p - p.mean(axis=0)
        main = dev @ np.linalg.svd(dev)[2][0]
        crossings = np.count_nonzero(np.diff(np.sign(main - main.mean())) != 0)
        cycles = crossings / 2
        assert 1.5 <= cycles <= 5.5
        assert 1.5 < cycles / d < 4.5  # Hz
    assert found >= 3


def test_reach_and_stay_holds_out_there() -> None:
    who = person(DEV_PEOPLE[3])
    home = make_pose(np.eye(3), who.hand_position)
    s = Session(home, np.eye(4), np.eye(4), who)
    _reach_stay(s, np.random.default_rng(0))
    reach, stay = s.hand.pieces[:2]
    forward = reach.end[0, 3] - who.hand_position[0]
    assert REACH["forward"][0] - 1e-9 <= forward <= REACH["forward"][1] + 1e-9
    assert REACH["hold"][0] <= stay.duration <= REACH["hold"][1]
    np.testing.assert_allclose(stay.fn(np.linspace(0, stay.duration, 5)), stay.fn(np.zeros(5)))


def test_live_person_with_a_person() -> None:
    who = person(HELDOUT_PEOPLE[0])

    def session(p: LivePerson):
        p.perform("go_left", start_t=4.0)
        p.perform("figure_eight")
        p.perform("stop")
        return p.samples_until()

    t1, p1, q1 = session(LivePerson(5, max_duration=90.0, person=who))
    t2, p2, q2 = session(LivePerson(5, max_duration=90.0, person=who))
    t3, p3, _ = session(LivePerson(5, max_duration=90.0))
    np.testing.assert_array_equal(t1, t2)
    np.testing.assert_array_equal(p1, p2)
    np.testing.assert_array_equal(q1, q2)
    assert t1.shape != t3.shape or not np.allclose(p1, p3)
    assert np.all(np.diff(t1) > 0) and np.max(np.linalg.norm(np.diff(p1, axis=0), axis=1)) < 0.1


def test_default_person_passed_explicitly_uses_the_rich_repertoire() -> None:
    traj_none, _ = make_stream(2, ["go_up", StreamItem("go_left"), "go_down"])
    traj_default, _ = make_stream(2, ["go_up", StreamItem("go_left"), "go_down"], person=DEFAULT_PERSON)
    assert traj_none.t.shape != traj_default.t.shape or not np.allclose(traj_none.p, traj_default.p)


@settings(max_examples=5, deadline=None)
@given(person_seed=st.integers(0, 10**6), stream_seed=st.integers(0, 10**6))
def test_any_person_gives_a_consistent_short_session(person_seed: int, stream_seed: int) -> None:
    ps = person_stream(stream_seed, person(person_seed), n_gestures=3, n_stops=1)
    assert [s.label for s in ps.segments].count(STOP) == 1 and len(ps.segments) == 4
    for a, b in itertools.pairwise(ps.segments):
        assert a.end_t < b.start_t
    assert all(0 < s.start_t < s.end_t < ps.traj.t[-1] for s in ps.segments)
    assert np.all(np.diff(ps.traj.t) > 0) and np.all(np.isfinite(ps.traj.p))
    assert ps.activities[-1].end_t == pytest.approx(ps.traj.t[-1], abs=0.05)
