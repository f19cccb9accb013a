"""Each context of the replica is what docs/dataset.md (*The twelve contexts*) says, up to the noise."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.datasets import CONTEXTS, GESTURES, REPLICA_CONTEXTS
from framefree.replica import (
    BODY_FRAMES,
    NOISE_POS_STD,
    NOISE_ROT_STD,
    WORLD_FRAMES,
    apply_context,
    synthesize_gesture,
)
from framefree.replica.contexts import COMBINATION_FRAMES

from .conftest import residuals, trial


def _check_noise(dp: np.ndarray, dr: np.ndarray) -> None:
    """Residuals are zero-mean white noise with the stated standard deviations (±15 %)."""
    n = dp.shape[0]
    for err, std in ((dp, NOISE_POS_STD), (dr, NOISE_ROT_STD)):
        assert np.all(np.abs(err.mean(axis=0)) < 5 * std / math.sqrt(n))
        assert 0.85 * std < err.std() < 1.15 * std
        # white: neighbouring samples uncorrelated
        c = np.corrcoef(err[1:].ravel(), err[:-1].ravel())[0, 1]
        assert abs(c) < 4 / math.sqrt(err.size)


def test_frame_constants_are_the_table() -> None:
    Rz = np.diag([-1.0, -1.0, 1.0])
    Rx = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])
    Ry = np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]])
    expect_b = {"body_frame_1": (Rz, [0.05, 0, 0]), "body_frame_2": (Rx, [0, 0.05, 0]),
                "body_frame_3": (Ry, [0, 0, -0.05])}
    expect_w = {"world_frame_1": (Rz, [1, 0, 0]), "world_frame_2": (Rx, [0, 1, 0]),
                "world_frame_3": (Ry, [0, 0, 1])}
    for table, expect in ((BODY_FRAMES, expect_b), (WORLD_FRAMES, expect_w)):
        for name, (R, d) in expect.items():
            np.testing.assert_allclose(table[name][:3, :3], R, atol=1e-15)
            np.testing.assert_allclose(table[name][:3, 3], d, atol=1e-15)
            np.testing.assert_array_equal(table[name][3], [0, 0, 0, 1])
    assert COMBINATION_FRAMES == ("world_frame_1", "body_frame_1")


@pytest.mark.parametrize("gesture", GESTURES)
def test_original_2_is_original_1_plus_noise(replica, gesture: str) -> None:
    o = trial(replica, gesture, "original_1", "trial_1")
    x = trial(replica, gesture, "original_2", "trial_1")
    np.testing.assert_array_equal(x.t, o.t)
    _check_noise(*residuals(o.poses(), x.poses()))


@pytest.mark.parametrize("context", list(BODY_FRAMES))
@pytest.mark.parametrize("gesture", ["go_left", "open_gripper"])
def test_body_frame_is_right_multiplied(replica, gesture: str, context: str) -> None:
    for k in (1, 4):
        o = trial(replica, gesture, "original_1", f"trial_{k}")
        x = trial(replica, gesture, context, f"trial_{k}")
        np.testing.assert_array_equal(x.t, o.t)
        _check_noise(*residuals(o.poses() @ BODY_FRAMES[context], x.poses()))
        # and it is not the left multiplication
        dp, _ = residuals(BODY_FRAMES[context] @ o.poses(), x.poses())
        assert np.abs(dp).mean() > 0.01


@pytest.mark.parametrize("context", list(WORLD_FRAMES))
@pytest.mark.parametrize("gesture", ["go_right", "close_gripper"])
def test_world_frame_is_left_multiplied(replica, gesture: str, context: str) -> None:
    for k in (2, 5):
        o = trial(replica, gesture, "original_1", f"trial_{k}")
        x = trial(replica, gesture, context, f"trial_{k}")
        np.testing.assert_array_equal(x.t, o.t)
        _check_noise(*residuals(WORLD_FRAMES[context] @ o.poses(), x.poses()))
        dp, _ = residuals(o.poses() @ WORLD_FRAMES[context], x.poses())
        assert np.abs(dp).mean() > 0.01


@pytest.mark.parametrize(("context", "factor"), [("slower", 2.0), ("faster", 0.5)])
@pytest.mark.parametrize("gesture", GESTURES)
def test_time_scaling(replica, gesture: str, context: str, factor: float) -> None:
    o = trial(replica, gesture, "original_1", "trial_3")
    x = trial(replica, gesture, context, "trial_3")
    assert x.t[0] == 0.0
    assert x.duration == pytest.approx(factor * o.duration, abs=1e-9)
    dt = np.diff(x.t)
    assert np.allclose(dt, dt.mean(), atol=1e-9) and abs(dt.mean() - 0.02) < 0.001  # 50 Hz grid
    # same path: ScLERP of the original at t / factor
    ref = se3.interpolate_poses(o.t, o.poses(), np.minimum(x.t / factor, o.t[-1]))
    _check_noise(*residuals(ref, x.poses()))


@pytest.mark.parametrize("gesture", GESTURES)
def test_first_half(replica, gesture: str) -> None:
    o = trial(replica, gesture, "original_1", "trial_4")
    x = trial(replica, gesture, "first_half", "trial_4")
    assert len(x) == math.ceil(len(o) / 2)
    np.testing.assert_array_equal(x.t, o.t[: len(x)])
    _check_noise(*residuals(o.poses()[: len(x)], x.poses()))


@pytest.mark.parametrize("gesture", GESTURES)
def test_combination(replica, gesture: str) -> None:
    o = trial(replica, gesture, "original_1", "trial_5")
    fast = trial(replica, gesture, "faster", "trial_5")
    x = trial(replica, gesture, "combination", "trial_5")
    assert len(x) == math.ceil(len(fast) / 2)
    np.testing.assert_array_equal(x.t, fast.t[: len(x)])
    W, B = (WORLD_FRAMES[COMBINATION_FRAMES[0]], BODY_FRAMES[COMBINATION_FRAMES[1]])
    ref = W @ se3.interpolate_poses(o.t, o.poses(), np.minimum(2 * x.t, o.t[-1])) @ B
    _check_noise(*residuals(ref, x.poses()))


def test_every_context_present(replica) -> None:
    assert replica.contexts == REPLICA_CONTEXTS  # the paper's twelve, then the stress contexts
    for g in GESTURES:
        for c in REPLICA_CONTEXTS:
            assert [t.name for t in replica.select(g, c)] == [f"trial_{k}" for k in range(1, 6)]


def test_unknown_context() -> None:
    traj = synthesize_gesture("go_left", np.random.default_rng(0))
    with pytest.raises(ValueError, match="unknown context"):
        apply_context(traj, "sideways", np.random.default_rng(0))


@settings(max_examples=5)
@given(seed=st.integers(0, 2**32 - 1), context=st.sampled_from(CONTEXTS), gesture=st.sampled_from(GESTURES))
def test_apply_context_is_deterministic(seed: int, context: str, gesture: str) -> None:
    traj = synthesize_gesture(gesture, np.random.default_rng(seed))
    a = apply_context(traj, context, np.random.default_rng(seed))
    b = apply_context(traj, context, np.random.default_rng(seed))
    np.testing.assert_array_equal(a.to_array(), b.to_array())
