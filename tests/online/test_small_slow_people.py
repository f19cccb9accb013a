"""Small, slow people (v8): a narrower speed hysteresis, re-grips among the negatives, and size
ranges that reach further down where nothing that is no gesture looks like the gesture."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.datasets.layout import load_model_recordings
from framefree.online import Recognizer, RecognizerConfig
from framefree.online.negatives import _regrip, non_gesture_motions
from framefree.online.rest_levels import speed_levels
from framefree.online.segmentation import MotionSegmenter, SpeedLevels
from framefree.online.thresholds import SegmentScores, reach_down
from framefree.replica import replica_path
from replica_recognizer import replica_recognizer


@pytest.fixture(scope="module")
def models():
    return load_model_recordings(replica_path(0), "original_1")


@pytest.fixture(scope="module")
def recognizer() -> Recognizer:
    return replica_recognizer()


def test_move_level_is_the_rest_level_times_the_hysteresis(models):
    trajs, _ = models
    for factor in (1.2, 1.5, 2.0):
        lv = speed_levels(trajs, 0.1, move_factor=factor)
        assert lv.move == pytest.approx(factor * lv.rest)
    with pytest.raises(ValueError, match="move_factor"):
        RecognizerConfig().replace(move_factor=1.0)


def _stroke(peak: float, dt: float = 0.02, duration: float = 1.0) -> np.ndarray:
    """Poses of a straight minimum-jerk stroke whose speed peaks at ``peak`` [m/s], between rests."""
    x = np.linspace(0.0, 1.0, round(duration / dt))
    length = peak * duration / 1.875  # the minimum-jerk profile peaks at 1.875 × the mean speed
    s = length * x**3 * (10 - 15 * x + 6 * x**2)
    rest = round(1.0 / dt)
    s = np.concatenate([np.zeros(rest), s, np.full(rest, length)])
    P = np.repeat(np.eye(4)[None], s.size, axis=0)
    P[:, 0, 3] = s
    return P


@pytest.mark.parametrize("factor, units", [(2.0, 0), (1.5, 1)])
def test_a_slow_stroke_between_the_two_levels_is_a_unit_only_with_the_narrower_hysteresis(factor, units):
    rest = 0.076  # the replica models' rest level
    seg = MotionSegmenter(SpeedLevels(rest, factor * rest), L=0.1)
    found = [u for k, T in enumerate(_stroke(1.7 * rest)) if (u := seg.push(0.02 * k, T)) is not None]
    assert len(found) == units


def test_regrips_turn_the_tracker_in_the_hand(models):
    trajs, _ = models
    rng = np.random.default_rng(5)
    for T0 in (trajs[0].poses()[0], trajs[7].poses()[-1]):
        for _ in range(20):
            P = _regrip(T0, rng, 0.02)
            R = P[:, :3, :3]
            assert np.allclose(R @ R.transpose(0, 2, 1), np.eye(3), atol=1e-9)
            # about a pivot within 6 cm: the tracker stays within 12 cm of where it was
            assert np.linalg.norm(P[:, :3, 3] - T0[:3, 3], axis=1).max() <= 0.12 + 1e-9
            # held still at both ends, and turned by at least 20° on the way
            assert np.allclose(P[0], T0) and np.allclose(P[-1], P[-2])
            turned = np.linalg.norm(se3.vector_from_rotation(R.transpose(0, 2, 1) @ T0[:3, :3]), axis=1)
            assert turned.max() >= math.radians(20.0) - 1e-9


def test_regrips_leave_the_other_negatives_as_they_were(models):
    trajs, labels = models
    kinds = ("rest", "moves", "drawn")
    without = non_gesture_motions(trajs, labels, 0.1, kinds=kinds, seed=3)
    both = non_gesture_motions(trajs, labels, 0.1, kinds=(*kinds, "regrip"), seed=3)
    assert [k for k, _ in both if k != "regrip"] == [k for k, _ in without]
    for (_, a), (_, b) in zip(without, [x for x in both if x[0] != "regrip"], strict=True):
        assert np.array_equal(a.p, b.p) and np.array_equal(a.q, b.q)
    assert sum(k == "regrip" for k, _ in both) == 2 * len(trajs)


class _Limits:
    """The two things :func:`reach_down` asks of a spotter: one model's size limits and the
    closure rule (here: everything closes)."""

    size_limits = np.array([[0.3, 1.0]])

    def admissible(self, j, closures, sizes, corners, turns, pauses=0.0, shares=None):
        return np.ones(len(closures), dtype=bool)


@settings(max_examples=60, deadline=None)
@given(size=st.floats(0.05, 1.2), distance=st.floats(0.0, 1.0), reach=st.floats(1.01, 3.0))
def test_the_size_range_reaches_down_unless_a_negative_in_the_band_would_be_taken(size, distance,
                                                                                  reach):
    records = [SegmentScores(np.array([[distance]]), np.array([0.0]), np.array([size]),
                             np.array([0]), np.array([0]), np.array([0.0]))]
    floor = reach_down(records, np.array([True]), 0, 0.5, _Limits(), reach)
    in_band = 0.3 / reach <= size < 0.3
    if in_band and distance < 0.5:
        assert floor is None
    else:
        assert floor == pytest.approx(0.3 / reach)
    assert reach_down(records, np.array([True]), 0, 0.5, _Limits(), 1.0) is None


def test_a_forearm_turn_keeps_its_size_range_and_a_circle_reaches_down(recognizer, models):
    """On the replica's models: a re-grip turned back is a *go down* done by less, so *go down*
    keeps its lower size limit; nothing that is no gesture looks like a small circle."""
    k, sizes = recognizer.config.constants, recognizer.learned_.size_limits
    never = Recognizer.from_trajectories(*models, size_reach=1.0)
    plain = never.learned_.size_limits
    assert sizes["go_down"] == pytest.approx(plain["go_down"])
    ratio = k.size_reach / k.size_factor
    assert sizes["go_right"][0] == pytest.approx(plain["go_right"][0] / ratio)
    assert sizes["go_right"][1] == pytest.approx(plain["go_right"][1])
    assert recognizer.learned_.provenance.rules["size_limits"].endswith("thresholds.reach_down")
    assert recognizer.gesture_thresholds == pytest.approx(never.gesture_thresholds)
