"""The practitioner's sliding-window baseline (``--method window``): it finds a gesture in a
resting stream, names it, stays silent while the hand rests, and refuses what it cannot use."""

from __future__ import annotations

import numpy as np
import pytest

from cli_helpers import one_line_error, run
from framefree import Trajectory
from framefree.errors import FramefreeError
from framefree.online.window_baseline import WindowSpotter, dtw_distances, window_points

GESTURES = ("line", "circle", "vee")


def synthesize_gesture(shape: str, rng: np.random.Generator) -> Trajectory:
    """A take at 50 Hz: 0.5 s of rest, the shape drawn in the x-y plane with a minimum-jerk pace
    (size and duration ±20 %, 0.5 mm jitter), 0.5 s of rest; the orientation held."""
    n = int(50 * 1.6 * rng.uniform(0.8, 1.2))
    s = np.linspace(0.0, 1.0, n)
    s = 10 * s**3 - 15 * s**4 + 6 * s**5
    size = 0.25 * rng.uniform(0.8, 1.2)
    if shape == "line":  # out to the right and back
        xy = np.column_stack([size * np.sin(np.pi * s), 0 * s])
    elif shape == "circle":
        xy = 0.5 * size * np.column_stack([np.sin(2 * np.pi * s), 1 - np.cos(2 * np.pi * s)])
    else:  # down-right, then up-right
        xy = size * np.column_stack([s, -1 + np.abs(2 * s - 1)])
    xy = np.concatenate([np.repeat(xy[:1], 25, axis=0), xy, np.repeat(xy[-1:], 25, axis=0)])
    p = np.column_stack([xy, np.zeros(len(xy))]) + 5e-4 * rng.standard_normal((len(xy), 3))
    q = np.repeat([[1.0, 0.0, 0.0, 0.0]], len(xy), axis=0)
    return Trajectory(np.arange(len(xy)) * 0.02, p + np.array([0.3, 1.2, 0.1]), q)


@pytest.fixture(scope="module")
def takes() -> tuple[list[Trajectory], list[str]]:
    rng = np.random.default_rng(3)
    trajs, labels = [], []
    for g in GESTURES:
        for _ in range(8):
            trajs.append(synthesize_gesture(g, rng))
            labels.append(g)
    return trajs, labels


@pytest.fixture(scope="module")
def spotter(takes) -> WindowSpotter:
    rec = WindowSpotter.from_trajectories(*takes)
    rec.warmup()
    return rec


def _held(T: Trajectory, k: int, seconds: float, t0: float, rng) -> Trajectory:
    """Pose ``k`` of ``T`` held for ``seconds`` at 50 Hz from time ``t0``, with 0.2 mm jitter."""
    t = t0 + np.arange(1, int(seconds * 50) + 1) * 0.02
    p = T.p[k] + 2e-4 * rng.standard_normal((t.size, 3))
    return Trajectory(t, p, np.repeat(T.q[k][None], t.size, axis=0))


def _in_rest(take: Trajectory, rest: float = 3.0) -> tuple[Trajectory, float, float]:
    """``rest`` s of holding still, the take, ``rest`` s of holding still; and the take's span."""
    rng = np.random.default_rng(5)
    before = _held(take, 0, rest, -0.02, rng)
    t_take = take.t - take.t[0] + before.t[-1] + 0.02
    after = _held(take, -1, rest, t_take[-1], rng)
    t = np.concatenate([before.t, t_take, after.t])
    p = np.concatenate([before.p, take.p, after.p])
    q = np.concatenate([before.q, take.q, after.q])
    return Trajectory(t, p, q), float(t_take[0]), float(t_take[-1])


@pytest.mark.parametrize("gesture", GESTURES)
def test_an_enrolled_gesture_in_a_resting_stream_is_found_once_and_named(spotter, takes, gesture):
    """One of the takes, elsewhere in space with fresh jitter, between 3 s rests: one event, with
    its label, between its start and 0.5 s after its end. (A new performance is found only as
    far as it lies within the takes' leave-one-out spread: that is what the baseline measures.)"""
    trajs, labels = takes
    k = labels.index(gesture) + 2
    T = trajs[k]
    rng = np.random.default_rng(100 + k)
    take = Trajectory(T.t, T.p + np.array([0.5, -0.3, 0.2]) + 3e-4 * rng.standard_normal(T.p.shape), T.q)
    stream, start, end = _in_rest(take)
    spotter.reset()
    events = spotter.run(stream)
    assert [e.label for e in events] == [gesture]
    assert start <= events[0].time <= end + 0.5
    assert spotter.stats["windows"] > 0 and spotter.stats["still"] > 0


def test_silent_while_the_hand_rests(spotter, takes):
    rest = _held(takes[0][0], 0, 30.0, 0.0, np.random.default_rng(7))
    spotter.reset()
    assert spotter.run(rest) == []
    assert spotter.stats["accepted"] == len(rest)


def test_bad_samples_are_skipped_and_counted(spotter, takes):
    spotter.reset()
    T = takes[0][0]
    spotter.push(0.0, T.p[0], T.q[0])
    assert spotter.push(0.02, [np.nan, 0, 0], T.q[0]) == []
    assert spotter.push(0.02, T.p[0], [0, 0, 0, 0]) == []
    assert spotter.push(-1.0, T.p[0], T.q[0]) == []
    s = spotter.stats
    assert (s["nan"], s["bad_quaternion"], s["not_later"], s["accepted"]) == (1, 1, 1, 1)


def test_windows_are_translation_invariant_and_dtw_is_zero_on_itself(takes):
    T = takes[0][takes[1].index("vee")]
    a = window_points(T.t, T.p, 32)
    b = window_points(T.t, T.p + np.array([1.0, -2.0, 0.5]), 32)
    np.testing.assert_allclose(a, b, atol=1e-12)
    d = dtw_distances(a, np.stack([a, a[::-1].copy()]))
    assert d[0] == 0.0 and d[1] > 0.01


def test_thresholds_come_from_the_takes(spotter, takes):
    assert set(spotter.gesture_thresholds) == set(GESTURES)
    assert all(0 < v < 0.02 for v in spotter.gesture_thresholds.values())
    trajs, _ = takes
    durations = sorted(float(tr.t[-1] - tr.t[0]) for tr in trajs)
    assert spotter.config.durations[0] == pytest.approx(durations[0])
    assert spotter.config.durations[-1] == pytest.approx(durations[-1])
    assert spotter.config.refractory == pytest.approx(durations[0])


def test_refuses_what_it_cannot_use(takes):
    trajs, labels = takes
    with pytest.raises(FramefreeError, match="one label per take"):
        WindowSpotter.from_trajectories(trajs, labels[:-1])
    with pytest.raises(FramefreeError, match="--ds-scale do not apply to --method window"):
        WindowSpotter.from_trajectories(trajs, labels, ds_scale=0.1)
    with pytest.raises(FramefreeError, match="one take"):
        WindowSpotter.from_trajectories(trajs[:9], labels[:9])


def test_the_command_line_refuses_other_methods_settings_in_one_line(tmp_path, takes):
    trajs, labels = takes
    models = tmp_path / "models"
    for k, (tr, g) in enumerate(zip(trajs, labels, strict=True)):
        (models / g).mkdir(parents=True, exist_ok=True)
        tr.to_csv(models / g / f"{k}.csv")
    stream, start, end = _in_rest(trajs[0], rest=1.0)
    stream.to_csv(tmp_path / "s.csv")
    (tmp_path / "s_labels.csv").write_text(f"label,start_t,end_t\n{labels[0]},{start},{end}\n")
    res = run("evaluate-stream", "--models", models, "--method", "window", "--L", "0.3",
              tmp_path / "s.csv")
    one_line_error(res, "--L do not apply to --method window")
    res = run("evaluate-stream", "--models", models, "--method", "window", tmp_path / "s.csv")
    assert res.exit_code == 0, res.output
    assert "window method" in res.output and "TP 1 FP 0 FN 0" in res.output
