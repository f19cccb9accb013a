"""Cutting a recording into takes: where the takes are, invariance, live recording, writing."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree.core.trajectory import Trajectory
from framefree.datasets import GESTURES
from framefree.errors import FramefreeError
from framefree.library import (
    TakeRecorder,
    TakeSettings,
    find_takes,
    join_recordings,
    motion_speed,
    random_frame,
    split_takes,
    write_take,
)
from framefree.library.recorder import is_way_back
from framefree.library.takes import takes_from_speed
from framefree.replica import synthesize_gesture
from real_data import REAL_MOTIONS

from .conftest import chain

REAL = REAL_MOTIONS


def _session(gesture: str, seed: int, n: int = 4) -> tuple[Trajectory, np.ndarray]:
    """``n`` fresh performances joined into one recording, and the boundaries between them [s]."""
    rng = np.random.default_rng([seed, 12])
    trials = [synthesize_gesture(gesture, rng) for _ in range(n)]
    long = chain(trials)
    cuts = np.cumsum([0.0] + [tr.duration + float(np.median(np.diff(tr.t))) for tr in trials])
    return long, cuts


@pytest.mark.parametrize("gesture", [*GESTURES, "figure_eight", "push_twist"])
def test_one_take_per_performance(gesture: str) -> None:
    long, cuts = _session(gesture, seed=1)
    spans = find_takes(long)
    assert len(spans) == 4
    for k, sp in enumerate(spans):
        # the motion lies inside its own performance, the trimmed take keeps a rest margin
        assert cuts[k] < sp.onset < sp.end < cuts[k + 1]
        assert sp.start < sp.onset and sp.stop > sp.end
        # up to `margin` of rest, less only where the rest is shared with the neighbouring take
        for kept in (sp.onset - sp.start, sp.stop - sp.end):
            assert 0.3 < kept <= TakeSettings().margin + 1e-9


def test_split_takes_cuts_the_samples_and_starts_at_zero() -> None:
    long, _ = _session("go_home", seed=2, n=3)
    takes = split_takes(long)
    spans = find_takes(long)
    assert len(takes) == 3
    for tk, sp in zip(takes, spans, strict=True):
        assert tk.t[0] == 0.0
        assert tk.duration == pytest.approx(sp.stop - sp.start, abs=0.06)  # sample spacing, dropouts
        k0 = int(np.searchsorted(long.t, sp.start - 1e-9))
        np.testing.assert_array_equal(tk.p, long.p[k0:k0 + len(tk)])
        assert "take" in tk.source


def test_rest_only_recording_has_no_take() -> None:
    rng = np.random.default_rng(0)
    n = 300
    p = 1e-4 * rng.standard_normal((n, 3))
    q = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)) + 1e-4 * rng.standard_normal((n, 4))
    assert split_takes(Trajectory(0.02 * np.arange(n), p, q)) == []


def test_too_short_recording_is_an_error() -> None:
    tr = Trajectory(0.01 * np.arange(6), np.zeros((6, 3)), np.tile([1.0, 0, 0, 0], (6, 1)), source="x.csv")
    with pytest.raises(FramefreeError, match=r"x\.csv"):
        find_takes(tr)


@given(seed=st.integers(0, 2**31 - 1))
def test_speed_does_not_depend_on_the_world_frame(seed: int) -> None:
    long, _ = _session("go_left", seed=3, n=1)
    rng = np.random.default_rng(seed)
    moved = long.transformed(world=random_frame(rng, 2.0))
    _, v0 = motion_speed(long)
    _, v1 = motion_speed(moved)
    np.testing.assert_allclose(v1, v0, rtol=1e-6, atol=1e-9)


@given(seed=st.integers(0, 2**31 - 1))
def test_takes_do_not_depend_on_frames(seed: int) -> None:
    long, _ = _session("open_gripper", seed=4, n=2)
    rng = np.random.default_rng(seed)
    moved = long.transformed(world=random_frame(rng, 2.0), body=random_frame(rng, 0.05))
    a, b = find_takes(long), find_takes(moved)
    assert len(a) == len(b) == 2
    for x, y in zip(a, b, strict=True):
        assert abs(x.onset - y.onset) < 0.1 and abs(x.end - y.end) < 0.1


def test_real_recording_takes_do_not_depend_on_frames() -> None:
    path = REAL / "kettle_pour_trial2_ref_com.csv"
    if not path.is_file():
        pytest.skip("real recordings not available")
    real = Trajectory.from_csv(path)
    spans = find_takes(real)
    assert spans, "a real pouring motion has at least one take"
    rng = np.random.default_rng(7)
    moved = find_takes(real.transformed(world=random_frame(rng, 1.5), body=random_frame(rng, 0.05)))
    assert [round(s.onset, 1) for s in moved] == pytest.approx([round(s.onset, 1) for s in spans], abs=0.1)
    # the motion starts after the first rest and the take keeps a margin before it
    assert spans[0].onset > real.t[0]


def test_live_recorder_finds_the_offline_takes() -> None:
    long, _ = _session("go_up", seed=5, n=3)
    rec = TakeRecorder()
    live = []
    last = -1.0
    for k in range(len(long)):
        rec.push(long.t[k], long.p[k], long.q[k])
        if long.t[k] - last >= 0.5:
            last = long.t[k]
            live += rec.poll()
    live += rec.finish()
    offline = find_takes(long)
    assert len(live) == len(offline) == 3
    for (span, take), ref in zip(live, offline, strict=True):
        assert span.onset == pytest.approx(ref.onset, abs=0.1)
        assert take.duration == pytest.approx(ref.stop - ref.start, abs=0.2)
    # polls before the rest after a take is long enough return nothing new
    assert rec.poll() == [] and rec.finish() == []


def test_write_take_numbers_and_never_overwrites(tmp_path: Path) -> None:
    long, _ = _session("go_down", seed=6, n=2)
    a, b = split_takes(long)
    p1 = write_take(a, tmp_path, "wave")
    p2 = write_take(b, tmp_path, "wave")
    assert p1 == tmp_path / "wave" / "own" / "trial_1.csv"
    assert p2.name == "trial_2.csv"
    (tmp_path / "wave" / "own" / "trial_7.csv").write_text(p1.read_text())
    assert write_take(a, tmp_path, "wave").name == "trial_8.csv"
    np.testing.assert_array_equal(np.loadtxt(p2, delimiter=","), b.to_array())  # full precision


@pytest.mark.parametrize("name", ["", "../x", "a/b", ".hidden", "streams"])
def test_write_take_rejects_bad_names(tmp_path: Path, name: str) -> None:
    long, _ = _session("go_down", seed=6, n=1)
    with pytest.raises(FramefreeError, match="name"):
        write_take(split_takes(long)[0], tmp_path, name)


def test_settings_are_validated() -> None:
    with pytest.raises(ValueError, match="level"):
        TakeSettings(level=1.5)
    with pytest.raises(ValueError, match="min_rest"):
        TakeSettings(min_rest=0.0)


def test_join_recordings_is_continuous_and_keeps_each_shape() -> None:
    rng = np.random.default_rng(9)
    a, b = synthesize_gesture("go_left", rng), synthesize_gesture("go_home", rng)
    joined = join_recordings([a, b])
    assert len(joined) == len(a) + len(b) - 1
    assert np.all(np.diff(joined.t) > 0)
    np.testing.assert_allclose(joined.p[len(a) - 1], a.p[-1], atol=1e-12)
    # the second recording, rigidly moved: distances between its positions are unchanged
    part = joined.p[len(a) - 1:]
    np.testing.assert_allclose(np.linalg.norm(part[1:] - part[0], axis=1),
                               np.linalg.norm(b.p[1:] - b.p[0], axis=1), rtol=1e-9, atol=1e-12)
    with pytest.raises(ValueError):
        join_recordings([])


@pytest.mark.parametrize(("shape", "seed"), [("zigzag", 0), ("letter_v", 1), ("go_left", 2), ("triangle", 3),
                                             ("zigzag", 18), ("spiral", 6)])
def test_recorder_leaves_out_the_ways_back_between_takes(shape: str, seed: int) -> None:
    """Five performances in one recording give five takes: the moves back to the start of an open
    stroke (and small settling moves) are listed as left out, not written."""
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    session = take_session(shape, person(seed), n_takes=5, seed=seed)
    kept = TakeRecorder()
    every = TakeRecorder(keep_all=True)
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        kept.push(t, p, q)
        every.push(t, p, q)
    takes = kept.finish()
    assert len(takes) == 5
    assert len(every.finish()) == 5 + len(kept.left_out)
    if shape in ("zigzag", "letter_v"):
        assert [why for _, why in kept.left_out].count("way back") == 4
    # each kept take covers one labelled performance
    for (span, _), seg in zip(takes, session.segments, strict=True):
        assert span.onset < seg.end_t and span.end > seg.start_t


def test_a_twitch_inside_a_rest_does_not_join_two_takes() -> None:
    """Two motions 1.4 s apart, the rest between them broken by one fast sample (a twitch or a
    tracker's glitch): each half of the rest is shorter than ``min_rest``. The twitch is too
    brief and too small to be a take, so the rest stays whole and the motions stay two takes."""
    t = np.arange(0.0, 6.0, 0.02)
    v = np.full(t.size, 0.01)
    v[(t >= 1.0) & (t < 2.0)] = 0.5
    v[(t >= 3.4) & (t < 4.4)] = 0.5
    v[np.argmin(np.abs(t - 2.7))] = 0.3
    spans = takes_from_speed(t, v)
    assert [(round(sp.onset, 1), round(sp.end, 1)) for sp in spans] == [(1.0, 2.0), (3.4, 4.4)]
    v[(t >= 2.6) & (t < 2.8)] = 0.3  # 6 cm of screw path is a move, not a twitch: one take
    assert len(takes_from_speed(t, v)) == 1


def test_a_twitch_between_ten_check_marks_leaves_out_the_way_back() -> None:
    """The replica's person records ten check marks (demonstration 4 of
    ``benchmarks/eighth_gesture.py``); a twitch splits the rest before the ninth way back, which
    was kept inside the ninth take and gave every gesture a pause allowance of 3.8 s."""
    from framefree.replica import DEFAULT_PERSON
    from framefree.replica.people_streams import take_session

    session = take_session("check_mark", DEFAULT_PERSON, n_takes=10, seed=4)
    rec = _record(session.traj)
    takes = rec.finish()
    assert len(takes) == 10
    assert [why for _, why in rec.left_out] == ["way back"] * 9
    assert max(take.duration for _, take in takes) < 3.5


def _line(start: tuple, end: tuple) -> Trajectory:
    """A straight move from ``start`` to ``end`` [m] in one second, the hand's orientation held."""
    t = np.linspace(0.0, 1.0, 51)
    p = np.asarray(start, float) + t[:, None] * (np.asarray(end, float) - np.asarray(start, float))
    return Trajectory(t, p, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)))


def test_a_way_back_that_overshoots_the_start_or_ends_beside_it_is_still_a_way_back() -> None:
    """A swipe of 0.3 m. Coming back 0.17 m past the start, or to 0.16 m beside it, is beyond
    half the swipe's distance from the start (the tolerance), but twice as near the start as the
    swipe's end: a way back (before session 41 neither was). Going on the same way, stopping
    0.12 m back, or starting elsewhere is no way back."""
    swipe = _line((0, 0, 0), (0.3, 0, 0))
    assert is_way_back(swipe, _line((0.3, 0, 0), (0.0, 0, 0)))
    assert is_way_back(swipe, _line((0.3, 0, 0), (-0.17, 0, 0)))
    assert is_way_back(swipe, _line((0.3, 0, 0), (0.0, 0.16, 0)))
    assert not is_way_back(swipe, _line((0.3, 0, 0), (0.6, 0, 0)))
    assert not is_way_back(swipe, _line((0.3, 0, 0), (0.18, 0, 0)))
    assert not is_way_back(swipe, _line((0.0, 0.3, 0), (0.0, 0, 0)))


def _hesitant_session() -> object:
    """A development person (seed 6) whose pause at the turning point of *go left* outlasts the
    recorder's shortest rest in some performances: their first take used to be cut in two."""
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    return take_session("go_left", person(6), n_takes=5, seed=6)


def _record(traj: Trajectory, **kwargs) -> TakeRecorder:
    rec = TakeRecorder(**kwargs)
    for t, p, q in zip(traj.t, traj.p, traj.q, strict=True):
        rec.push(t, p, q)
    return rec


def _covers(span, seg) -> bool:
    """The span holds most of the labelled performance."""
    return min(span.end, seg.end_t) - max(span.onset, seg.start_t) > 0.8 * (seg.end_t - seg.start_t)


def test_a_performance_that_hesitates_at_its_turning_point_is_one_take() -> None:
    session = _hesitant_session()
    rec = _record(session.traj)
    takes = rec.finish()
    assert len(takes) == 5 and rec.joined
    for (span, _), seg in zip(takes, session.segments, strict=True):
        assert _covers(span, seg)
    first, second, both = rec.joined[0]
    assert both.onset == first.onset and both.end == second.end
    # without joining, the same recording loses a performance to halves (the test can fail)
    halves = _record(session.traj, pause_ratio=0.0).finish()
    assert not all(_covers(span, seg) for (span, _), seg in zip(halves, session.segments, strict=False))


def test_joining_does_not_depend_on_the_world_frame() -> None:
    session = _hesitant_session()
    moved = session.traj.transformed(world=random_frame(np.random.default_rng(3), 2.0))
    a, b = _record(session.traj), _record(moved)
    spans_a, spans_b = [s for s, _ in a.finish()], [s for s, _ in b.finish()]
    assert len(a.joined) == len(b.joined)
    assert [s.onset for s in spans_a] == pytest.approx([s.onset for s in spans_b], abs=0.1)


def test_an_open_stroke_is_returned_once_the_next_move_shows_it_complete() -> None:
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    session = take_session("zigzag", person(0), n_takes=2, seed=0)
    end_of_first = session.segments[0].end_t
    rec = TakeRecorder()
    seen_pending = False
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        rec.push(t, p, q)
        if t > end_of_first + 1.5 and t < session.segments[1].start_t and not rec.spans:
            rec.poll()
            seen_pending |= rec.pending == 1
    assert seen_pending, "the first Z waits for the move after it"
    rec.finish()
    assert len(rec.spans) == 2 and not rec.joined
    assert [why for _, why in rec.left_out] == ["way back"]


def _held_z_session(hold: float, rest: float = 2.5, n: int = 3) -> Trajectory:
    """A Z drawn ``n`` times (0.3 m wide), the hand held still for ``hold`` seconds at each corner,
    resting ``rest`` seconds after each performance and after each way back to the start."""
    a, b, c, d = (np.array(v) for v in ([0, 0, 0.0], [0.3, 0, 0], [0, -0.25, 0], [0.3, -0.25, 0]))
    plan: list[tuple[np.ndarray, float]] = [(a, rest)]
    for k in range(n):
        if k:
            plan += [(a, 0.8), (a, rest)]
        plan += [(b, 0.5), (b, hold), (c, 0.6), (c, hold), (d, 0.5), (d, rest)]
    dt, pos, rows = 0.02, a, [a]
    for target, duration in plan:
        u = np.arange(1, round(duration / dt) + 1) / round(duration / dt)
        s = 10 * u**3 - 15 * u**4 + 6 * u**5  # minimum jerk
        rows += list(pos + s[:, None] * (target - pos))
        pos = target
    p = np.array(rows) + np.random.default_rng(0).normal(0.0, 2e-4, (len(rows), 3))
    return Trajectory(dt * np.arange(len(rows)), p, np.tile([1.0, 0, 0, 0], (len(rows), 1)))


def test_a_z_held_at_its_corners_is_one_take_and_its_ways_back_are_left_out() -> None:
    session = _held_z_session(hold=1.0)
    rec = _record(session)
    takes = rec.finish()
    assert len(takes) == 3 and len(rec.joined) == 6  # each Z put back together from three strokes
    assert [why for _, why in rec.left_out] == ["way back", "way back"]
    assert all(3.0 < span.duration < 4.5 for span, _ in takes)
    # without joining every stroke is a take of its own (the test can fail)
    assert len(_record(session, pause_ratio=0.0).finish()) > 3


@pytest.mark.parametrize(("shape", "seed", "demonstrator"), [
    ("zigzag", 13, True), ("check_mark", 19, True), ("wave", 0, False), ("letter_l", 4, False)])
def test_a_way_back_soon_after_an_open_stroke_is_not_joined_to_it(shape: str, seed: int,
                                                                    demonstrator: bool) -> None:
    """A person who starts the way back soon after an open stroke (a rest much shorter than their
    rests between performances) does not make it the stroke's second half: it takes a shorter
    way than the stroke (session 42). Joined, a zigzag's take held the zigzag and its way back, a
    closed shape, and triangles fired it 18 times on the development people."""
    from framefree.replica import DEFAULT_PERSON, person
    from framefree.replica.people_streams import take_session

    session = take_session(shape, DEFAULT_PERSON if demonstrator else person(seed), n_takes=5,
                           seed=seed)
    rec = TakeRecorder()
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        rec.push(t, p, q)
    takes = rec.finish()
    assert len(takes) == 5 and not rec.joined
    assert [why for _, why in rec.left_out].count("way back") == 4
    for (span, _), seg in zip(takes, session.segments, strict=True):
        assert span.onset < seg.end_t and span.end < seg.end_t + 1.0


def test_a_pause_at_the_turning_point_still_joins_the_second_half() -> None:
    """The second half of an out-and-back gesture retraces the first: still joined."""
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    session = take_session("go_left", person(5), n_takes=5, seed=5)
    rec = TakeRecorder()
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        rec.push(t, p, q)
    takes = rec.finish()
    assert len(takes) == 5 and len(rec.joined) >= 2
    for (span, _), seg in zip(takes, session.segments, strict=True):
        assert span.onset < seg.end_t and span.end > seg.start_t
