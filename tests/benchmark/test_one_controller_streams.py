"""``benchmarks/one_controller_streams.py``: the vocabulary ``--gestures`` names, and its usage
errors (``--gestures``, ``--set``) in one line with exit status 2."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from benchmark_scripts import BENCH, load_benchmark
from framefree.datasets.people_layout import load_people
from real_data import MACHETE

GESTURES = {"backflip", "cartwheel_left", "cartwheel_right", "fly_eagle", "golf_swing",
            "hook_left", "hook_right", "left_right_left_combo", "right_left_right_combo",
            "uppercut_left", "uppercut_right"}


@pytest.fixture(scope="module")
def script():
    return load_benchmark("one_controller_streams")


def test_the_right_hand_vocabulary_leaves_out_the_left_hand_gestures(script):
    right = script.vocabulary("right-hand", GESTURES)
    assert right == set(script.RIGHT_HAND) and right < GESTURES
    assert not right & {"hook_left", "uppercut_left", "left_right_left_combo"}
    assert {"cartwheel_left", "right_left_right_combo"} <= right  # both arms move in these


def test_the_left_hand_vocabulary_mirrors_the_right_hands(script):
    left = script.vocabulary("left-hand", GESTURES)
    right = set(script.RIGHT_HAND)
    assert left == set(script.LEFT_HAND)
    assert left & right == {"backflip", "cartwheel_left", "cartwheel_right", "fly_eagle",
                            "golf_swing"}  # both arms move in these
    assert left - right == {"hook_left", "uppercut_left", "left_right_left_combo"}


def test_a_list_of_gestures_and_no_list(script):
    assert script.vocabulary(" hook_right, backflip ,", GESTURES) == {"hook_right", "backflip"}
    assert script.vocabulary(None, GESTURES) is None


@pytest.mark.parametrize("text", ["hook_right,no_such_gesture", ",", "Hook_Right"])
def test_a_name_the_recordings_lack_is_refused(script, text):
    with pytest.raises(ValueError, match="unknown gesture"):
        script.vocabulary(text, GESTURES)


@pytest.mark.parametrize(("args", "named"), [
    (["--gestures", "hook_right,no_such_gesture"], "no_such_gesture"),
    (["--set", "nonsense"], "NAME=JSON"),
    (["--set", "no_such_setting=1"], "no_such_setting"),
    (["--set", "rival_quantile=2"], "rival_quantile"),
    (["--no-orientation", "--turn-noise", "5"], "--turn-noise"),
])
def test_usage_errors_are_one_line_and_exit_2(args, named):
    proc = subprocess.run([sys.executable, str(BENCH / "one_controller_streams.py"),
                           "--models", str(MACHETE), *args], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and named in proc.stderr


def test_the_right_hand_vocabulary_is_where_the_right_hand_moves_as_far(script):
    """In the median take of each gesture of the list the right controller travels at least 0.9
    times as far as the left; in the median take of every other gesture, at most 0.7 times (the
    six people of ../shared/data, else the two shipped in tests/data)."""
    ratios: dict[str, list[float]] = {}
    for r in load_people(MACHETE):
        right, left = (float(np.linalg.norm(np.diff(r.sample.trackers[k].p, axis=0), axis=1).sum())
                       for k in (0, 1))
        ratios.setdefault(r.gesture, []).append(right / left)
    median = {g: float(np.median(v)) for g, v in ratios.items()}
    assert {"hook_left", "hook_right"} <= set(median)  # the shipped subset has 7 of the 11
    assert {g for g, m in median.items() if m >= 0.9} == set(script.RIGHT_HAND) & set(median)
    assert all(m <= 0.7 for g, m in median.items() if g not in script.RIGHT_HAND)


def test_another_sensor_resamples_and_adds_the_same_noise_each_time(script):
    """``--rate`` and ``--noise``: the recording at the new rate, its quaternions kept, and
    positions off by noise of the given size, the same on every run."""
    from framefree.core.trajectory import Trajectory

    t = np.arange(0.0, 2.0, 1 / 90)
    p = np.c_[0.3 * np.sin(t), 0.2 * t, np.zeros_like(t)]
    traj = Trajectory(t, p, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)))
    same = script.as_sensor(traj, None, 0.0)
    assert same is traj
    at_30 = script.as_sensor(traj, 30.0, 0.0)
    assert np.median(np.diff(at_30.t)) == pytest.approx(1 / 30, rel=0.02)  # the grid spans the take
    assert np.allclose(at_30.q, [1.0, 0.0, 0.0, 0.0])
    noisy = script.as_sensor(traj, 30.0, 0.01)
    off = noisy.p - at_30.p
    assert off.std() == pytest.approx(0.01, rel=0.15)
    assert np.array_equal(noisy.p, script.as_sensor(traj, 30.0, 0.01).p)


def test_another_sensor_jitters_the_orientation_by_the_given_angle(script):
    """``--turn-noise``: the positions kept, each orientation turned by about the given angle."""
    from framefree.core.trajectory import Trajectory
    from framefree.online.smoothing import rotation_noise

    t = np.arange(0.0, 4.0, 1 / 90)
    p = np.c_[0.3 * np.sin(t), 0.2 * t, np.zeros_like(t)]
    traj = Trajectory(t, p, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)))
    jittered = script.as_sensor(traj, None, 0.0, turn_noise=5.0)
    assert np.allclose(jittered.p, traj.p)
    assert np.degrees(rotation_noise(jittered)) == pytest.approx(5.0, rel=0.2)
    assert np.array_equal(jittered.q, script.as_sensor(traj, None, 0.0, turn_noise=5.0).q)
