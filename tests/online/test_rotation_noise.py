"""The noise on a sensor's orientations (v32): a tracker whose orientation jitters makes a still
hand appear to turn, as position noise makes it appear to move. v32 let that noise decide the
smoothing with the positions'; since v34 drops an orientation noisy enough to matter, v36 lets
the positions' noise alone decide it (a hand tracker's palm turns more noisily in motion than
at rest, and on examples cut without rests the turns alone set the smoothing off wrongly).

The tests check the estimate (it reads injected white noise, depends on neither frame, is 0
without orientation), that the real trackers read as precise, and that a Vive whose orientation
jitters by 5° per sample reads as noisy but, its positions as recorded, is not smoothed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.smoothing import noise_limit, position_noise, rotation_noise
from real_data import shipped_right_controller

L = 0.1
twists = st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6).map(np.array)


def turning_motion(seed: int, rate: float, seconds: float = 6.0) -> Trajectory:
    """A hand that moves and turns smoothly (sines of 0.2-0.8 Hz: 5-15 cm, up to 0.6 rad per
    axis) at ``rate`` [Hz]."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 1.0 / rate)
    freq, phase = rng.uniform(0.2, 0.8, (2, 3)), rng.uniform(0, 2 * np.pi, (2, 3))
    p = rng.uniform(0.05, 0.15, 3) * np.sin(2 * np.pi * t[:, None] * freq[0] + phase[0])
    phi = rng.uniform(0.2, 0.6, 3) * np.sin(2 * np.pi * t[:, None] * freq[1] + phase[1])
    T = np.repeat(np.eye(4)[None], t.size, axis=0)
    T[:, :3, :3] = se3.rotation_from_vector(phi)
    T[:, :3, 3] = p
    return Trajectory.from_poses(t, T)


def with_orientation_noise(traj: Trajectory, rng: np.random.Generator, radians: float
                           ) -> Trajectory:
    """``traj`` with each orientation turned by a random rotation vector of ``radians`` per axis."""
    T = traj.poses()
    T[:, :3, :3] = T[:, :3, :3] @ se3.rotation_from_vector(radians * rng.standard_normal((len(traj), 3)))
    return Trajectory.from_poses(traj.t, T)


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([20.0, 30.0, 60.0, 90.0]),
       st.sampled_from([1.0, 2.0, 5.0]))
def test_rotation_noise_reads_the_white_noise_on_a_turning_hand(seed, rate, degrees):
    clean = turning_motion(seed, rate)
    noisy = with_orientation_noise(clean, np.random.default_rng(seed + 1), math.radians(degrees))
    assert rotation_noise(noisy) == pytest.approx(math.radians(degrees), rel=0.35)
    assert L * rotation_noise(clean) < noise_limit(0.03, 0.1)  # smooth turning: no noise


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 10_000), twists, twists)
def test_rotation_noise_depends_on_neither_frame(seed, world, body):
    traj = with_orientation_noise(turning_motion(seed, 30.0), np.random.default_rng(seed),
                                  math.radians(3.0))
    W, G = se3.pose_from_twist(world), se3.pose_from_twist(body)
    moved = Trajectory.from_poses(traj.t, W @ traj.poses() @ G)
    assert rotation_noise(moved) == pytest.approx(rotation_noise(traj), rel=1e-6)


def test_no_orientation_no_rotation_noise():
    traj = turning_motion(3, 30.0)
    still = Trajectory(traj.t, traj.p, np.tile([1.0, 0.0, 0.0, 0.0], (len(traj), 1)))
    assert rotation_noise(still) == 0.0
    assert math.isnan(rotation_noise(Trajectory(traj.t[:5], traj.p[:5], traj.q[:5])))


def test_real_trackers_read_as_precise_and_a_jittering_orientation_as_noisy_but_not_smoothed():
    takes, labels = shipped_right_controller()
    limit = noise_limit(0.03, 0.1)
    assert np.median([position_noise(t) for t in takes]) < limit / 3  # a Vive controller, 90 Hz
    assert L * np.median([rotation_noise(t) for t in takes]) < limit / 3  # its turns too
    rng = np.random.default_rng(5)
    jittering = [with_orientation_noise(t, rng, math.radians(5.0)) for t in takes]
    assert np.median([position_noise(t) for t in jittering]) < limit / 3  # positions as recorded
    assert L * np.median([rotation_noise(t) for t in jittering]) > 3 * limit  # turns noisy
    precise = Recognizer.from_trajectories(takes, labels)
    # kept: at 5° per sample the orientation is dropped by default (v34, test_noisy_orientation)
    kept = Recognizer.from_trajectories(jittering, labels, positions_only=False)
    assert precise.learned_.smoothing == 0.0
    assert kept.learned_.smoothing == 0.0  # v36: the positions' noise alone decides
    assert "position noise" in kept.learned_.provenance.rules["smoothing"]
