"""The four stress contexts beyond the paper: what each one is, and that they leave the paper's
twelve contexts untouched."""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree.core import se3
from framefree.datasets import CONTEXTS, GESTURES, REPLICA_CONTEXTS, STRESS_CONTEXTS
from framefree.replica.build import _other_person_trial, _rng
from framefree.replica.contexts import (
    HEAVY_NOISE_SCALE,
    NOISE_POS_STD,
    NOISE_ROT_STD,
    OTHER_PERSON,
    RANDOM_BODY_OFFSET,
    RANDOM_WORLD_OFFSET,
    random_frames,
)
from framefree.replica.people import person

from .conftest import SEED, residuals, trial


def _check_noise(dp: np.ndarray, dr: np.ndarray, scale: float) -> None:
    """Zero-mean white residuals with ``scale`` times the paper's standard deviations (±15 %)."""
    n = dp.shape[0]
    for err, std in ((dp, scale * NOISE_POS_STD), (dr, scale * NOISE_ROT_STD)):
        assert np.all(np.abs(err.mean(axis=0)) < 5 * std / math.sqrt(n))
        assert 0.85 * std < err.std() < 1.15 * std


def test_names_and_order() -> None:
    assert STRESS_CONTEXTS == ("heavy_noise", "slower_3x", "random_frames", "other_person")
    assert REPLICA_CONTEXTS == (*CONTEXTS, *STRESS_CONTEXTS)
    assert len(CONTEXTS) == 12


def test_every_context_is_in_the_replica(replica) -> None:
    assert replica.contexts == REPLICA_CONTEXTS
    for c in STRESS_CONTEXTS:
        assert len(replica.select(GESTURES[0], c)) == 5


@pytest.mark.parametrize("gesture", ["go_left", "open_gripper", "go_home"])
def test_heavy_noise_is_three_times_the_paper_noise(replica, gesture: str) -> None:
    o = trial(replica, gesture, "original_1", "trial_2")
    x = trial(replica, gesture, "heavy_noise", "trial_2")
    np.testing.assert_array_equal(x.t, o.t)
    assert HEAVY_NOISE_SCALE == 3.0
    _check_noise(*residuals(o.poses(), x.poses()), HEAVY_NOISE_SCALE)


@pytest.mark.parametrize("gesture", ["go_right", "go_down"])
def test_slower_3x_is_three_times_as_long_on_a_50_hz_grid(replica, gesture: str) -> None:
    o = trial(replica, gesture, "original_1", "trial_3")
    x = trial(replica, gesture, "slower_3x", "trial_3")
    assert x.duration == pytest.approx(3.0 * o.duration, abs=1e-9)
    dt = np.diff(x.t)
    assert np.allclose(dt, 0.02, atol=1e-3)
    ref = se3.interpolate_poses(o.t, o.poses(), np.minimum(x.t / 3.0, o.t[-1]))
    _check_noise(*residuals(ref, x.poses()), 1.0)


@pytest.mark.parametrize(("gi", "k"), [(0, 1), (4, 5)])
def test_random_frames_are_drawn_per_trial_within_bounds(replica, gi: int, k: int) -> None:
    gesture, ci = GESTURES[gi], REPLICA_CONTEXTS.index("random_frames")
    W, B = random_frames(_rng(SEED, 2, gi, k, ci))  # the context's first draws
    assert np.linalg.norm(W[:3, 3]) <= RANDOM_WORLD_OFFSET
    assert np.linalg.norm(B[:3, 3]) <= RANDOM_BODY_OFFSET
    o = trial(replica, gesture, "original_1", f"trial_{k}")
    x = trial(replica, gesture, "random_frames", f"trial_{k}")
    _check_noise(*residuals(W @ o.poses() @ B, x.poses()), 1.0)


def test_random_frames_cover_rotations_and_offsets() -> None:
    rng = np.random.default_rng(0)
    draws = [random_frames(rng) for _ in range(400)]
    angles = [np.linalg.norm(se3.vector_from_rotation(W[:3, :3])) for W, _ in draws]
    world = [np.linalg.norm(W[:3, 3]) for W, _ in draws]
    body = [np.linalg.norm(B[:3, 3]) for _, B in draws]
    assert max(angles) > 2.8 and min(angles) < 1.0  # uniform on SO(3): angles up to π
    assert max(world) <= 3.0 and np.median(world) > 2.0  # uniform in the ball: median 3·0.5^(1/3)
    assert max(body) <= 0.1 and np.median(body) > 0.07


def test_other_person_is_a_new_recording_by_a_held_out_person(replica, replica_root) -> None:
    from framefree.replica.people import HELDOUT_PEOPLE

    assert OTHER_PERSON in HELDOUT_PEOPLE and not person(OTHER_PERSON).is_nominal
    gi = 2
    o = trial(replica, GESTURES[gi], "original_1", "trial_1")
    x = trial(replica, GESTURES[gi], "other_person", "trial_1")
    assert len(x) != len(o)  # not an augmentation of the original
    from framefree.replica.gestures import default_world

    world = default_world(_rng(SEED, 0))
    expect = _other_person_trial(GESTURES[gi], SEED, gi, 1, world)
    np.testing.assert_allclose(x.t, expect.t, atol=1e-6)
    dp, dr = residuals(expect.poses(), x.poses())
    assert np.abs(dp).max() < 1e-6 and np.abs(dr).max() < 1e-6
