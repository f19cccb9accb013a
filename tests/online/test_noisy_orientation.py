"""An orientation too noisy to use (v34): where the takes' orientation noise, times ``L``, would
make a still hand appear to move even after the smoothing of a noisy sensor, the recognizer
drops the orientation of the takes and of the stream and works on the positions alone.

The tests check the smoothing's effect on white noise, that the real trackers keep their
orientation and a Vive jittering by 5° or 10° per sample does not (2° does), that such a
recognizer ignores whatever quaternion the stream sends, and that a library saved before keeps
its orientation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from test_rotation_noise import turning_motion, with_orientation_noise

from framefree.cli import cli
from framefree.online import Recognizer
from framefree.online.evaluation import run_stream
from framefree.online.model_settings import takes_advice
from framefree.online.noisy_orientation import (
    constant_orientation,
    orientation_unusable,
    residual_noise,
)
from real_data import shipped_right_controller


@settings(max_examples=30, deadline=None)
@given(st.floats(1e-4, 0.1), st.floats(0.0, 0.5), st.sampled_from([1 / 90, 1 / 30, 1 / 20]))
def test_smoothing_leaves_less_white_noise_and_never_more(noise, smoothing, period):
    left = residual_noise(noise, smoothing, period, 0.02)
    assert 0 < left <= noise
    if smoothing > 0:
        s = smoothing / max(period, 0.02)
        assert left == pytest.approx(noise * min(1.0, (2 * math.sqrt(math.pi) * s) ** -0.5))
    else:
        assert left == noise


def test_white_noise_smoothed_by_a_gaussian_leaves_what_the_rule_says():
    """The rule's factor against a Gaussian applied to white noise of 1 at the grid step."""
    rng = np.random.default_rng(0)
    dt, std = 0.02, 0.067
    h = math.ceil(3 * std / dt)
    w = np.exp(-0.5 * (np.arange(-h, h + 1) * dt / std) ** 2)
    smoothed = np.convolve(rng.standard_normal(200_000), w / w.sum(), mode="valid")
    assert smoothed.std() == pytest.approx(residual_noise(1.0, std, dt, dt), rel=0.03)


@pytest.mark.parametrize(("degrees", "unusable"), [(0.0, False), (2.0, False), (5.0, True),
                                                   (10.0, True)])
def test_a_vive_whose_orientation_jitters_by_degrees(degrees, unusable):
    takes, _ = shipped_right_controller()
    rng = np.random.default_rng(11)
    jittering = [with_orientation_noise(t, rng, math.radians(degrees)) for t in takes]
    dropped, noise = orientation_unusable(jittering, 0.03, 0.1, 0.067, 0.1, 0.02)
    assert dropped is unusable
    if degrees:
        assert math.degrees(noise) == pytest.approx(degrees, rel=0.35)


def test_a_smoothly_turning_hand_keeps_its_orientation():
    takes = [turning_motion(seed, rate) for seed in range(3) for rate in (20.0, 30.0, 90.0)]
    assert orientation_unusable(takes, 0.03, 0.1, 0.067, 0.1, 0.02)[0] is False


@pytest.fixture(scope="module")
def jittering_recognizer():
    """The shipped Vive right controller's takes with 10° of orientation noise per sample."""
    takes, labels = shipped_right_controller()
    rng = np.random.default_rng(3)
    jittering = [with_orientation_noise(t, rng, math.radians(10.0)) for t in takes]
    return Recognizer.from_trajectories(jittering, labels), jittering, labels


def test_the_recognizer_drops_an_orientation_that_noisy(jittering_recognizer):
    rec, jittering, _ = jittering_recognizer
    assert rec.learned_.positions_only is True and rec.positions_only
    assert "orientation noise" in rec.learned_.provenance.rules["positions_only"]
    assert rec.learned_.fixed_frame is True  # the takes as it uses them never turn
    advice = takes_advice(jittering, rec.config, rec.learned_)
    assert any("too noisy to use (10°" in line and "positions alone" in line
               for line in advice)
    assert not any("hold no orientation" in line for line in advice)


def test_without_orientation_the_stream_quaternions_do_not_matter(jittering_recognizer):
    rec, jittering, _ = jittering_recognizer
    take = jittering[0]
    other = with_orientation_noise(take, np.random.default_rng(99), math.radians(40.0))
    events = []
    for stream in (take, other, constant_orientation(take)):
        rec.reset()
        events.append([(e.label, e.time) for e in run_stream(rec, stream)[0]])
    assert events[0] == events[1] == events[2]


def test_precise_takes_keep_their_orientation_and_a_given_value_wins():
    takes, labels = shipped_right_controller()
    precise = Recognizer.from_trajectories(takes, labels)
    assert precise.learned_.positions_only is False and not precise.positions_only
    old = precise.learned_.replace(positions_only=None)  # a library saved before v34
    restored = Recognizer.from_trajectories(takes, labels, precise.config, old)
    assert restored.learned_.positions_only is False
    assert "saved before" in restored.learned_.provenance.rules["positions_only"]
    forced = Recognizer.from_trajectories(takes, labels, positions_only=True)
    assert forced.positions_only
    assert not any("too noisy" in line
                   for line in takes_advice(takes, forced.config, forced.learned_))


def test_enroll_says_when_it_drops_the_orientation(jittering_recognizer, tmp_path):
    _, jittering, labels = jittering_recognizer
    for k, (take, gesture) in enumerate(zip(jittering, labels, strict=True)):
        take.to_csv(tmp_path / "takes" / gesture / "own" / f"trial_{k + 1}.csv")
    res = CliRunner().invoke(cli, ["enroll", str(tmp_path / "takes"), "-o",
                                   str(tmp_path / "lib.npz")])
    assert res.exit_code == 0, res.output
    assert "note: the takes' orientation is too noisy to use" in res.output
    assert "hold no orientation" not in res.output
