"""Smoothing a noisy sensor's poses (``RecognizerConfig.smoothing``): it keeps framefree's
invariances exactly, the live smoother gives the offline smoothing pose for pose, on noisy
real takes it brings the learned rest level back down, and by default the takes' own position
noise decides it."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer, RecognizerConfig
from framefree.online.learned import LearnedSettings
from framefree.online.smoothing import (
    GridSmoother,
    grid_gaussian,
    noise_limit,
    position_noise,
    smooth_in_own_frame,
    smoothed_take,
)
from real_data import shipped_right_controller

DT = 0.02


def wobbly_poses(seed: int, n: int = 80, noise: float = 0.01) -> np.ndarray:
    """A turning, travelling motion (n, 4, 4) with white position noise [m]."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    xi = np.column_stack([0.3 * np.sin(3 * t), 0.2 * t, 0.1 * np.cos(t), t, 0.5 * t**2, 0 * t])
    poses = se3.pose_from_twist(xi)
    poses[:, :3, 3] += rng.normal(0.0, noise, (n, 3))
    return poses


def test_weights_are_a_centred_gaussian_summing_to_one():
    w = grid_gaussian(0.067, DT)
    assert w.size == 2 * 11 + 1 and w.sum() == pytest.approx(1.0)
    np.testing.assert_allclose(w, w[::-1])
    assert np.argmax(w) == 11
    assert grid_gaussian(0.0, DT).tolist() == [1.0]
    with pytest.raises(ValueError, match="must not be negative"):
        grid_gaussian(-0.1, DT)


twists = st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6).map(np.array)


@settings(max_examples=30, deadline=None)
@given(twists, twists, st.integers(0, 1000), st.sampled_from([0.02, 0.05, 0.1]))
def test_smoothing_commutes_with_any_change_of_world_and_body_frame(world, body, seed, std):
    W, B = se3.pose_from_twist(world), se3.pose_from_twist(body)
    poses = wobbly_poses(seed)
    w = grid_gaussian(std, DT)
    np.testing.assert_allclose(smooth_in_own_frame(W @ poses @ B, w), W @ smooth_in_own_frame(poses, w) @ B,
                               atol=1e-9)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.integers(1, 9), min_size=1, max_size=30), st.integers(0, 1000))
def test_the_live_smoother_gives_the_offline_poses_whatever_the_chunks(chunks, seed):
    poses = wobbly_poses(seed)
    times = np.arange(poses.shape[0]) * DT
    smoother = GridSmoother(0.05, DT)
    got_t, got_p, k = [], [], 0
    for size in chunks:
        t, p = smoother.push(times[k:k + size], poses[k:k + size])
        got_t.append(t)
        got_p.append(p)
        k += size
        if k >= poses.shape[0]:
            break
    got_t, got_p = np.concatenate(got_t), np.concatenate(got_p)
    done = max(0, min(k, poses.shape[0]) - smoother.half)  # every pose whose window is complete
    assert got_p.shape[0] == done
    np.testing.assert_allclose(got_t, times[:done])
    offline = smooth_in_own_frame(poses, smoother.weights)
    # the live smoother cannot see past the last pose pushed: compare where the window is whole
    np.testing.assert_allclose(got_p, offline[:done], atol=1e-12)
    assert smoother.delay == pytest.approx(smoother.half * DT)


def test_positions_only_are_averaged_and_the_noise_shrinks():
    rng = np.random.default_rng(3)
    n = 400
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, 3] = rng.normal(0.0, 0.01, (n, 3))
    w = grid_gaussian(0.067, DT)
    out = smooth_in_own_frame(poses, w)
    h = (w.size - 1) // 2
    np.testing.assert_allclose(out[h:-h, :3, 3],
                               np.stack([w @ poses[c - h:c + h + 1, :3, 3]
                                         for c in range(h, n - h)]), atol=1e-12)
    np.testing.assert_allclose(out[:, :3, :3], poses[:, :3, :3])
    assert out[h:-h, :3, 3].std() < 0.4 * poses[:, :3, 3].std()


def test_a_take_is_smoothed_on_the_grid_and_zero_leaves_it_alone():
    poses = wobbly_poses(1)
    take = Trajectory.from_poses(5.0 + np.arange(poses.shape[0]) * DT, poses)
    assert smoothed_take(take, 0.0, DT) is take
    smooth = smoothed_take(take, 0.05, DT)
    assert len(smooth) == len(take) and smooth.t[0] == pytest.approx(5.0)
    np.testing.assert_allclose(smooth.poses(), smooth_in_own_frame(take.uniform_poses(DT)[1],
                                                            grid_gaussian(0.05, DT)), atol=1e-9)


@pytest.mark.parametrize("bad", [-0.01, float("nan"), float("inf")])
def test_a_bad_smoothing_is_refused(bad):
    with pytest.raises(ValueError, match="smoothing must be a finite number"):
        RecognizerConfig(smoothing=bad)


def noisy_positions(traj: Trajectory, rng: np.random.Generator, noise: float) -> Trajectory:
    """A skeleton tracker's view of ``traj``: 30 Hz, positions only, white noise [m]."""
    t = np.arange(traj.t[0], traj.t[-1], 1 / 30)
    p = np.column_stack([np.interp(t, traj.t, traj.p[:, k]) for k in range(3)])
    return Trajectory(t, p + rng.normal(0.0, noise, p.shape), np.tile([1.0, 0, 0, 0], (t.size, 1)))


def test_on_noisy_real_takes_smoothing_brings_the_rest_level_down():
    takes, labels = shipped_right_controller()
    keep = [i for i, g in enumerate(labels) if g in ("cartwheel_left", "golf_swing", "fly_eagle")]
    rng = np.random.default_rng(0)
    noisy = [noisy_positions(takes[i], rng, 0.01) for i in keep]
    clean = [noisy_positions(takes[i], rng, 0.0) for i in keep]
    names = [labels[i] for i in keep]
    learned = {name: Recognizer.from_trajectories(trajs, names, **extra).learned_
               for name, trajs, extra in (("clean", clean, {}), ("noisy", noisy, {"smoothing": 0}),
                                          ("smoothed", noisy, {"smoothing": 0.067}),
                                          ("by default", noisy, {}))}
    rest = {name: s.rest_speed for name, s in learned.items()}
    assert rest["noisy"] > 1.5 * rest["clean"]  # what the setting is for
    assert rest["smoothed"] < 0.75 * rest["noisy"]
    # by default the takes' noise decides: these are smoothed, the clean ones are not
    assert learned["by default"].smoothing == 0.067 and rest["by default"] == rest["smoothed"]
    assert "position noise" in learned["by default"].provenance.rules["smoothing"]
    assert learned["clean"].smoothing == 0.0 and learned["noisy"].smoothing == 0.0


def test_the_recognizer_smooths_its_stream_and_restarts_the_smoother():
    takes, labels = shipped_right_controller()
    rec = Recognizer.from_trajectories(takes[:6], labels[:6], smoothing=0.05)
    assert isinstance(rec.smoother, GridSmoother) and rec.smoother.delay == pytest.approx(0.16)
    tr = takes[0]
    for k in range(len(tr)):
        rec.push(float(tr.t[k]), tr.p[k], tr.q[k])
    assert rec.stats["grid"] > 0
    assert rec.smoother._seen > rec.stats["grid"]  # the last poses wait for their window
    rec.reset()
    assert rec.smoother._seen == 0
    assert Recognizer.from_trajectories(takes[:6], labels[:6]).smoother is None


def noisy_sample(sample, rng: np.random.Generator, noise: float):
    """Every tracker of a two-controller ``sample`` as :func:`noisy_positions` gives it."""
    from framefree.core.multitrajectory import MultiTrajectory

    t = np.arange(sample.t[0], sample.t[-1], 1 / 30)
    trackers = []
    for tr in sample.trackers:
        p = np.column_stack([np.interp(t, tr.t, tr.p[:, k]) for k in range(3)])
        q = np.tile([1.0, 0, 0, 0], (t.size, 1))
        trackers.append(Trajectory(t, p + rng.normal(0.0, noise, p.shape), q))
    return MultiTrajectory(tuple(trackers), sample.names, sample.up, sample.source)


@pytest.fixture(scope="module")
def two_controller_hooks():
    from framefree.datasets.people_layout import load_people
    from real_data import SHIPPED_MACHETE

    people = [r for r in load_people(SHIPPED_MACHETE) if r.gesture.startswith("hook")]
    return [r.sample for r in people], [r.gesture for r in people]


def test_a_recognizer_of_several_trackers_smooths_every_tracker_of_noisy_takes(two_controller_hooks):
    from framefree.online.multi import MultiRecognizer

    samples, labels = two_controller_hooks
    rng = np.random.default_rng(6)
    noisy = [noisy_sample(s, rng, 0.01) for s in samples]
    rec = MultiRecognizer.from_samples(noisy, labels)
    assert rec.learned_.smoothing == 0.067 and len(rec.smoothers) == 2
    assert rec.smoothing_delay == pytest.approx(0.22)  # 11 grid steps: 3 σ, rounded up
    clean = MultiRecognizer.from_samples([noisy_sample(s, rng, 0.0) for s in samples], labels)
    assert clean.learned_.smoothing == 0.0 and clean.smoothers == []
    unsmoothed = MultiRecognizer.from_samples(noisy, labels, smoothing=0)
    assert unsmoothed.learned_.rest_speed > 1.5 * clean.learned_.rest_speed  # what it is for
    assert rec.learned_.rest_speed < unsmoothed.learned_.rest_speed
    # every tracker of the takes the classifier and the calibration see is smoothed
    from framefree.online.model_settings import LearnedDraft
    from framefree.online.multi import smoothed_samples

    seen = smoothed_samples(noisy, RecognizerConfig(), LearnedDraft())
    limit = noise_limit(0.03, 0.1)
    assert np.median([position_noise(tr) for smp in noisy for tr in smp.trackers]) > 5 * limit
    assert np.median([position_noise(tr) for smp in seen for tr in smp.trackers]) < limit


def test_a_recognizer_of_several_trackers_finds_a_smoothed_gesture_and_stamps_it_when_it_fires(
        two_controller_hooks):
    from framefree.online.multi import MultiRecognizer

    samples, labels = two_controller_hooks
    held = len(labels) - 1
    rec = MultiRecognizer.from_samples(samples[:held], labels[:held], smoothing=0.05)
    rec.background = False
    smp = samples[held]
    rest = np.arange(1, 76) * 0.02  # 1.5 s holding the last pose, so the gesture is confirmed
    t = np.concatenate([smp.t, smp.t[-1] + rest])

    def held_still(x: np.ndarray) -> np.ndarray:
        return np.concatenate([x, np.repeat(x[-1:], rest.size, axis=0)])

    P = np.stack([held_still(tr.p) for tr in smp.trackers], axis=1)
    Q = np.stack([held_still(tr.q) for tr in smp.trackers], axis=1)
    fired = [(float(t[k]), e) for k in range(t.size) for e in rec.push(float(t[k]), P[k], Q[k])]
    assert [e.label for _, e in fired] == [labels[held]]
    pushed_at, event = fired[0]
    assert pushed_at - 0.02 <= event.time <= pushed_at  # not a smoothing delay (0.16 s) earlier
    rec.reset()
    assert all(sm._seen == 0 for sm in rec.smoothers)


def test_an_event_is_stamped_when_it_fires_not_when_its_smoothed_pose_was_taken():
    takes, labels = shipped_right_controller()
    gesture = "cartwheel_right"
    own = [i for i, g in enumerate(labels) if g == gesture]
    models = [i for i, g in enumerate(labels) if g != gesture or i != own[-1]]
    rec = Recognizer.from_trajectories([takes[i] for i in models], [labels[i] for i in models],
                                       smoothing=0.05)
    rec.background = False
    tr = takes[own[-1]]
    rest = np.arange(1, 76) * 0.02  # 1.5 s holding the last pose, so the gesture is confirmed
    t = np.concatenate([tr.t, tr.t[-1] + rest])
    p = np.concatenate([tr.p, np.repeat(tr.p[-1:], rest.size, axis=0)])
    q = np.concatenate([tr.q, np.repeat(tr.q[-1:], rest.size, axis=0)])
    fired = [(float(t[k]), e) for k in range(t.size) for e in rec.push(float(t[k]), p[k], q[k])]
    assert [e.label for _, e in fired] == [gesture]
    pushed_at, event = fired[0]
    assert pushed_at - DT <= event.time <= pushed_at  # not a smoothing delay (0.16 s) earlier


def test_check_compares_the_takes_as_the_recognizer_smooths_them():
    from framefree.library.check import check_takes
    from framefree.library.store import TakeSet

    takes, labels = shipped_right_controller()
    keep = [i for i, g in enumerate(labels) if g in ("cartwheel_left", "golf_swing")]
    rng = np.random.default_rng(1)
    noisy = [noisy_positions(takes[i], rng, 0.01) for i in keep]
    names, gestures = tuple(f"{labels[i]}/own/{i}" for i in keep), tuple(labels[i] for i in keep)
    by_setting = check_takes(TakeSet(tuple(noisy), gestures, names), RecognizerConfig(smoothing=0.067))
    smoothed_first = check_takes(TakeSet(tuple(smoothed_take(t, 0.067, DT) for t in noisy),
                                         gestures, names), RecognizerConfig())
    unsmoothed = check_takes(TakeSet(tuple(noisy), gestures, names), RecognizerConfig(smoothing=0))
    by_default = check_takes(TakeSet(tuple(noisy), gestures, names), RecognizerConfig())
    np.testing.assert_allclose(by_setting.distances, smoothed_first.distances)
    np.testing.assert_allclose(by_default.distances, by_setting.distances)  # noisy: smoothed
    assert not np.allclose(by_setting.distances, unsmoothed.distances)


def smooth_motion(seed: int, rate: float, seconds: float = 6.0) -> Trajectory:
    """A hand's smooth motion (three sines of 5-15 cm at 0.2-0.8 Hz per axis) at ``rate`` [Hz]."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 1.0 / rate)
    freq, amp = rng.uniform(0.2, 0.8, (3, 3)), rng.uniform(0.05, 0.15, (3, 3))
    phase = rng.uniform(0, 2 * np.pi, (3, 3))
    p = np.stack([(amp[k] * np.sin(2 * np.pi * np.outer(t, freq[k]) + phase[k])).sum(axis=1)
                  for k in range(3)], axis=1)
    return Trajectory(t, p, np.tile([1.0, 0, 0, 0], (t.size, 1)))


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([20.0, 30.0, 60.0, 90.0]),
       st.sampled_from([0.003, 0.005, 0.01, 0.02]))
def test_position_noise_reads_the_white_noise_on_a_moving_hand(seed, rate, noise):
    clean = smooth_motion(seed, rate)
    rng = np.random.default_rng(seed + 1)
    noisy = Trajectory(clean.t, clean.p + rng.normal(0.0, noise, clean.p.shape), clean.q)
    assert position_noise(noisy) == pytest.approx(noise, rel=0.35)  # a median of 120-540
    assert position_noise(clean) < noise_limit(0.03, 0.1) < 0.002  # smooth motion: no noise


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), twists)
def test_position_noise_does_not_depend_on_the_world_frame(seed, world):
    rng = np.random.default_rng(seed)
    clean = smooth_motion(seed, 30.0)
    traj = Trajectory(clean.t, clean.p + rng.normal(0.0, 0.01, clean.p.shape), clean.q)
    W = se3.pose_from_twist(world)
    moved = Trajectory(traj.t, traj.p @ W[:3, :3].T + W[:3, 3], traj.q)
    assert position_noise(moved) == pytest.approx(position_noise(traj), rel=1e-9)


def test_the_real_trackers_read_as_precise_and_a_skeleton_tracker_as_noisy():
    takes, _ = shipped_right_controller()
    limit = noise_limit(0.03, 0.1)
    assert limit == pytest.approx(0.00133, abs=1e-5)
    assert np.median([position_noise(t) for t in takes]) < limit / 3  # a Vive controller, 90 Hz
    rng = np.random.default_rng(2)
    for noise, noisy in ((0.0, False), (0.005, True)):  # 30 Hz: the sampling raises the motion's share
        read = np.median([position_noise(noisy_positions(t, rng, noise)) for t in takes])
        assert (read > limit) == noisy


def test_a_library_saved_before_the_smoothing_was_learned_stays_unsmoothed():
    takes, labels = shipped_right_controller()
    rng = np.random.default_rng(3)
    noisy = [noisy_positions(t, rng, 0.01) for t in takes[:6]]
    rec = Recognizer.from_trajectories(noisy, labels[:6], learned=LearnedSettings())
    assert rec.learned_.smoothing == 0.0 and rec.smoother is None
    assert "saved before" in rec.learned_.provenance.rules["smoothing"]
    assert Recognizer.from_trajectories(noisy, labels[:6], learned=LearnedSettings(),
                                        smoothing=0.05).learned_.smoothing == 0.05


def test_the_users_smoothing_replaces_a_librarys_value_and_its_rule():
    from framefree.online.learned import Provenance

    takes, labels = shipped_right_controller()
    rng = np.random.default_rng(7)
    noisy = [noisy_positions(t, rng, 0.01) for t in takes[:6]]
    library = LearnedSettings(smoothing=0.067,
                              provenance=Provenance({"smoothing": "sensor_smoothing (noisy)"}))
    kept = Recognizer.from_trajectories(noisy, labels[:6], learned=library).learned_
    assert kept.smoothing == 0.067 and kept.provenance.rules["smoothing"] == "sensor_smoothing (noisy)"
    mine = Recognizer.from_trajectories(noisy, labels[:6], learned=library, smoothing=0.05).learned_
    assert mine.smoothing == 0.05 and mine.provenance.rules["smoothing"] == "given: smoothing"


def test_a_decided_smoothing_is_said_in_one_line_and_a_chosen_one_is_not():
    from framefree.library.check import check_takes
    from framefree.library.store import TakeSet
    from framefree.online.model_settings import smoothing_advice

    takes, labels = shipped_right_controller()
    rng = np.random.default_rng(4)
    noisy = [noisy_positions(t, rng, 0.01) for t in takes[:6]]
    line = smoothing_advice(noisy, RecognizerConfig(), 0.067)
    assert line is not None and "smoothing=0" in line and "\n" not in line
    reading = re.search(r"noisy \(([0-9.]+) mm", line)
    assert reading is not None and 9.0 < float(reading.group(1)) < 11.0  # 1 cm injected
    assert smoothing_advice(noisy, RecognizerConfig(smoothing=0.067), 0.067) is None
    assert smoothing_advice(takes[:6], RecognizerConfig(), 0.0) is None
    report = check_takes(TakeSet(tuple(noisy), tuple(labels[:6]),
                                 tuple(f"{g}/own/{i}" for i, g in enumerate(labels[:6]))))
    assert any("takes are noisy" in f.message for f in report.findings)


def test_enroll_smooths_noisy_takes_says_so_and_the_library_keeps_it(tmp_path):
    from click.testing import CliRunner

    from framefree.cli import cli
    from framefree.library import load_library

    takes, labels = shipped_right_controller()
    rng = np.random.default_rng(5)
    folder = tmp_path / "takes"
    for k, (tr, g) in enumerate(zip(takes, labels, strict=True)):
        if g in ("cartwheel_left", "golf_swing", "fly_eagle"):
            noisy_positions(tr, rng, 0.01).to_csv(folder / g / "own" / f"{k:02d}.csv")
    lib = tmp_path / "lib.npz"
    res = CliRunner().invoke(cli, ["enroll", str(folder), "-o", str(lib)])
    assert res.exit_code == 0, res.output
    assert "note: the takes are noisy" in res.output
    assert load_library(lib).learned_settings().smoothing == 0.067
    assert Recognizer.load(lib).smoother is not None
