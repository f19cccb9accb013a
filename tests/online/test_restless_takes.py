"""Takes that hold no rest: the rest level is measured where the takes hold still; models cut
where the motion starts and ends have no rest to measure, so their level is where they start or
end or, cut in mid-motion, the slowest the hand moves inside them, and they get a note saying so
(docs/online.md, Models cut without rests). Real Vive recordings, as recorded and cut at 5 % and
a fifth of their peak speed."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.core.trajectory import Trajectory
from framefree.library import read_takes
from framefree.online import RecognizerConfig
from framefree.online.model_settings import rest_advice
from framefree.online.rest_levels import (
    end_speed,
    holds_no_rest,
    restless_takes,
    slowest_stretch,
    speed_levels,
    take_motion,
    take_speeds,
)
from framefree.replica import replica_path
from real_data import shipped_right_controller


def cut(traj: Trajectory, share: float) -> Trajectory:
    """``traj`` from where its position speed first exceeds ``share`` × its peak to where it last
    does: a segmented example without the rests around the gesture."""
    speed = np.linalg.norm(np.gradient(traj.p, traj.t, axis=0), axis=1)
    fast = np.flatnonzero(speed > share * speed.max())
    a, b = int(fast[0]), int(fast[-1]) + 1
    return Trajectory(traj.t[a:b], traj.p[a:b], traj.q[a:b])


@pytest.fixture(scope="module")
def vive() -> tuple[list[Trajectory], list[str]]:
    """The right controller's recordings of the shipped real people."""
    return shipped_right_controller()


def test_real_recordings_rest_and_their_cut_copies_do_not(vive):
    trajs, _ = vive
    L = RecognizerConfig().descriptor.L
    assert restless_takes(trajs, L).mean() <= 0.25
    assert restless_takes([cut(t, 0.05) for t in trajs], L).mean() > 0.5
    assert restless_takes([cut(t, 0.2) for t in trajs], L).mean() >= 0.9


def test_noisy_takes_that_rest_are_not_restless():
    # the replica's takes with a tracker's noise: a resting hand seems to move at up to a
    # seventh of the peak speed, but it goes nowhere
    takes = list(read_takes(replica_path(), "original_2").takes)
    assert not restless_takes(takes, RecognizerConfig().descriptor.L).any()


def test_cut_takes_rest_below_the_speed_they_start_at_and_get_advice(vive):
    trajs, _ = vive
    config = RecognizerConfig()
    L = config.descriptor.L
    rest = speed_levels(trajs, L).rest
    floors = [np.percentile(v, 10) for v in take_speeds(trajs, L) if v.size]
    assert rest == pytest.approx(3 * float(np.median(floors)))  # takes that rest: their floor
    # cut at 5 % of their peak: no floor to measure, and where the cut was made the hand left its
    # rest, so the level is the median speed the restless takes start or end at (session 30)
    cuts = [cut(t, 0.05) for t in trajs]
    motion = list(take_motion(cuts, L))
    starts = [end_speed(v, 5) for v, p in motion if holds_no_rest(v, p, 5)]
    peaks = [v.max() for v, _ in motion]
    rest_cut = speed_levels(cuts, L).rest
    assert rest_cut == pytest.approx(float(np.median(starts)))
    assert rest_cut < 0.6 * 3 * 0.05 * float(np.median(peaks))  # well under session 29's level
    assert rest_cut < 1.5 * rest  # near the level of the takes as recorded
    # cut at a fifth they start faster than three times the bound on the floor (session 29):
    # cut in mid-motion, the level is the slowest the hand moves for a rest's length (0.2 s)
    # inside them, so that no gesture rests inside (v37)
    cuts20 = [cut(t, 0.2) for t in trajs]
    speeds20 = [v for v in take_speeds(cuts20, L) if v.size]
    bound = 3 * 0.05 * float(np.median([v.max() for v in speeds20]))
    slowest = [slowest_stretch(v, 10) for v in speeds20]
    rest20 = speed_levels(cuts20, L).rest
    assert rest20 == pytest.approx(float(np.percentile(slowest, 10)))
    assert rest20 < 0.7 * bound  # v36 took the bound itself
    assert 0.5 * rest < rest20 < 1.5 * rest  # near the level of the takes as recorded
    assert rest_advice(trajs, config) is None
    for takes in (cuts, cuts20):
        advice = rest_advice(takes, config)
        assert advice is not None and f"of {len(takes)} takes hold no rest" in advice
        assert "rest_speed" in advice


def test_a_take_moving_from_end_to_end_is_restless_and_a_resting_one_is_not():
    t = np.arange(0.0, 2.0, 0.01)
    q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    moving = Trajectory(t, np.column_stack([0.3 * t, 0.05 * np.sin(3 * t), 0 * t]), q)
    s = np.clip((t - 0.5) / 1.0, 0.0, 1.0)
    bump = 0.3 * (10 * s**3 - 15 * s**4 + 6 * s**5)  # at rest, a smooth stroke, at rest
    resting = Trajectory(t, np.column_stack([bump, 0 * t, 0 * t]), q)
    jitter = np.random.default_rng(0).normal(0.0, 0.002, (t.size, 3))  # fast, but going nowhere
    noisy = Trajectory(t, np.column_stack([bump, 0 * t, 0 * t]) + jitter, q)
    assert restless_takes([moving, resting, noisy], 0.1).tolist() == [True, False, False]
    assert holds_no_rest(np.ones(3), np.zeros((4, 1, 3)), 5) is False  # too short to tell


def test_evaluate_stream_notes_models_cut_without_rests(vive, tmp_path):
    trajs, labels = vive
    models = tmp_path / "models"
    for k, (tr, g) in enumerate(zip(trajs, labels, strict=True)):
        (models / g).mkdir(parents=True, exist_ok=True)
        cut(tr, 0.2).to_csv(models / g / f"{k:02d}.csv")
    stream = tmp_path / "stream.csv"
    trajs[0].to_csv(stream)
    (tmp_path / "stream_labels.csv").write_text(f"label,start_t,end_t\n{labels[0]},"
                                                f"{trajs[0].t[0]:.3f},{trajs[0].t[-1]:.3f}\n")
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(models), "--stream",
                                   str(stream)])
    assert res.exit_code == 0, res.output
    assert "note: " in res.output and "hold no rest" in res.output


def test_several_trackers_cut_without_rests_get_the_same_level():
    from framefree.core.multitrajectory import MultiTrajectory
    from framefree.datasets.people_layout import load_people
    from framefree.online.multi_stream import combined_motion, combined_speed, multi_speed_levels
    from real_data import SHIPPED_MACHETE

    samples = [r.sample for r in load_people(SHIPPED_MACHETE)]
    L = RecognizerConfig().descriptor.L

    def cut_both(s, fraction):  # both trackers cut where their combined speed first and last passes
        v = combined_speed(s, L)
        idx = np.flatnonzero(v > fraction * v.max())
        a, b = (np.searchsorted(s.t, s.t[0] + k * 0.02) for k in (idx[0], idx[-1] + 1))
        return MultiTrajectory(tuple(Trajectory(tr.t[a:b], tr.p[a:b], tr.q[a:b]) for tr in s.trackers),
                               s.names, s.up, s.source)

    cuts = [cut_both(s, 0.2) for s in samples]  # cut in mid-motion: the slowest stretch (v37)
    speeds = [combined_speed(s, L) for s in cuts]
    bound = 3 * 0.05 * float(np.median([v.max() for v in speeds]))
    slowest = float(np.percentile([slowest_stretch(v, 10) for v in speeds], 10))
    assert slowest < bound
    assert multi_speed_levels(cuts, L).rest == pytest.approx(slowest)
    floors = [np.percentile(combined_speed(s, L), 10) for s in samples]
    assert multi_speed_levels(samples, L).rest == pytest.approx(3 * float(np.median(floors)))
    cuts5 = [cut_both(s, 0.05) for s in samples]  # the speed they start at, as for one tracker
    motion = [combined_motion(s, L) for s in cuts5]
    starts = [end_speed(v, 5) for v, p in motion if holds_no_rest(v, p, 5)]
    assert 2 * len(starts) > len(cuts5)
    assert multi_speed_levels(cuts5, L).rest == pytest.approx(float(np.median(starts)))


def test_the_slowest_stretch_is_inside_the_motion_and_lasts_a_rest():
    # two strokes with a slow top between them (a golf swing), cut in mid-motion at both ends
    t = np.arange(0.0, 2.0, 0.02)
    v = 1.0 + 3.0 * np.abs(np.sin(np.pi * t))  # 1 m/s at both cut ends and at the top
    v[(t > 0.95) & (t < 1.05)] = 0.2  # the top: 0.1 s slow, then up again
    # the ends are slower than half the peak and take no part; 10 samples (0.2 s) around the
    # top average the 0.2 m/s of its 5 samples with the faster samples on either side
    slowest = slowest_stretch(v, 10)
    assert 0.2 < slowest < 1.0
    window = np.convolve(v[(t > 0.8) & (t < 1.2)], np.full(10, 0.1), "valid")
    assert slowest == pytest.approx(window.min())
    assert slowest_stretch(np.array([0.5, 2.0, 1.5]), 10) == pytest.approx(1.75)  # too short
