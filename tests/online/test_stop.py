"""Windowed stop detector: golden speeds, jitter robustness, calibration, replica stop signals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.datasets import GESTURES, STOP, make_stream, synthesize_gesture
from framefree.datasets.faults import duplicates, jitter
from framefree.online.stop import (
    SampleRateStopDetector,
    StopDetector,
    WindowedAngularSpeed,
    sustained_peak_speed,
    windowed_angular_speeds,
)

#: Stop threshold = MARGIN × the fastest sustained rotation of the model recordings.
MARGIN = 1.15


def spin(omega: float, duration: float, period: float = 0.02, t0: float = 0.0):
    """Times (n,) and quaternions (n, 4) of a rotation at ``omega`` rad/s about a fixed axis."""
    t = t0 + np.arange(round(duration / period) + 1) * period
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    half = 0.5 * omega * (t - t0)
    return t, np.column_stack([np.cos(half), np.sin(half)[:, None] * axis])


def test_windowed_speed_is_exact_on_a_constant_rotation():
    t, q = spin(4.0, 1.0)
    s = windowed_angular_speeds(t, q, window=0.08)
    assert np.isnan(s[:4]).all()
    np.testing.assert_allclose(s[4:], 4.0, rtol=1e-9)


def test_jitter_and_duplicates_do_not_inflate_the_speed():
    t, q = spin(5.0, 2.0)
    p = np.zeros((t.size, 3))
    rng = np.random.default_rng(1)
    tj, _, qj = jitter(t, p, q, rng, amplitude=0.008)
    s = windowed_angular_speeds(tj, qj, window=0.08)
    s = s[np.isfinite(s)]
    assert s.min() > 5.0 * 0.064 / 0.088 and s.max() < 5.0 * 0.096 / 0.08  # ±16 ms on ≥ 80 ms
    td, _, qd = duplicates(t, p, q, rng, fraction=0.2)
    sd = windowed_angular_speeds(td, qd, window=0.08)
    np.testing.assert_allclose(sd[np.isfinite(sd)], 5.0, rtol=1e-9)
    # the per-sample rate of the paper's detector is far off on the same jittered stamps
    rate = 2.0 * np.linalg.norm(np.diff(qj, axis=0), axis=1) / np.diff(tj)
    assert rate.max() > 1.5 * 5.0


def test_fires_after_min_duration_then_refractory_and_rearm():
    t1, q1 = spin(8.0, 0.5)
    det = StopDetector(threshold=6.0, window=0.08, min_duration=0.06, refractory=1.5)
    fired = det.run(zip(t1, q1, strict=True))
    assert fired == pytest.approx([0.08 + 0.06])  # window filled at 0.08 s, then 0.06 s above
    assert det.active and not det.armed
    rest_t = t1[-1] + 0.02 * np.arange(1, 20)
    assert det.run((tt, q1[-1]) for tt in rest_t) == []
    assert det.armed and det.active  # re-armed, still within the refractory time
    t2, q2 = spin(8.0, 0.5, t0=rest_t[-1] + 0.02)
    assert det.run(zip(t2, q2, strict=True)) == []  # second fast rotation within 1.5 s: silent
    t3, q3 = spin(8.0, 0.5, t0=t2[-1] + 1.0)
    det.reset()
    assert len(det.run(zip(t3, q3, strict=True))) == 1
    assert math.isclose(det.angular_speed, 8.0, rel_tol=1e-9)


def test_a_single_glitch_does_not_fire():
    t, q = spin(0.5, 2.0)
    q = q.copy()
    q[50] = [0.0, 1.0, 0.0, 0.0]  # one sample rotated by 180°
    det = StopDetector(threshold=3.0, min_duration=0.04)
    assert det.run(zip(t, q, strict=True)) == []
    assert max(windowed_angular_speeds(t, q)[np.isfinite(windowed_angular_speeds(t, q))]) > 3.0


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([0.0, 0.02, 0.04, 0.08]))
def test_calibration_matches_the_detector(seed, min_duration):
    """Just above the sustained peak the detector is silent; just below it fires."""
    rng = np.random.default_rng(seed)
    n = 60
    t = np.cumsum(rng.uniform(0.005, 0.04, n))
    q = np.cumsum(rng.normal(0.0, 0.1, (n, 4)), axis=0)
    q[:, 0] += 3.0
    q /= np.linalg.norm(q, axis=1)[:, None]
    peak = sustained_peak_speed(t, q, window=0.08, min_duration=min_duration)
    if peak <= 0.0:
        return
    samples = list(zip(t, q, strict=True))
    assert StopDetector(peak * (1 + 1e-9), min_duration=min_duration).run(samples) == []
    assert len(StopDetector(peak * (1 - 1e-6), min_duration=min_duration).run(samples)) >= 1


def test_speed_buffer_is_bounded():
    w = WindowedAngularSpeed(window=0.08, max_samples=256)
    t, q = spin(1.0, 20.0, period=0.001)
    for k in range(t.size):
        w.update(t[k], q[k])
        assert len(w._buf) <= 82


@pytest.fixture(scope="module")
def threshold() -> float:
    """MARGIN × the fastest sustained rotation of 35 synthetic model recordings."""
    rng = np.random.default_rng(2024)
    peak = 0.0
    for g in GESTURES:
        for _ in range(5):
            tr = synthesize_gesture(g, rng)
            peak = max(peak, sustained_peak_speed(tr.t, tr.q))
    return MARGIN * peak


@pytest.mark.parametrize("seed", [31, 32, 33, 34])
@pytest.mark.parametrize("jittered", [False, True])
def test_replica_stop_signals_fire_once_and_gestures_never(threshold, seed, jittered):
    traj, segments = make_stream(seed, n_gestures=6, n_stops=2)
    t, q = traj.t, traj.q
    if jittered:
        t, _, q = jitter(t, traj.p, q, np.random.default_rng(seed), amplitude=0.008)
    fired = StopDetector(threshold).run(zip(t, q, strict=True))
    stops = [s for s in segments if s.label == STOP]
    assert len(stops) == 2
    for s in stops:
        assert sum(s.start_t <= f <= s.end_t + 0.1 for f in fired) == 1, (s, fired)
    assert len(fired) == len(stops), (fired, segments)


def test_sample_rate_detector_keeps_the_paper_behaviour():
    t, q = spin(8.0, 0.5)  # |q̇| = ω / 2 = 4 per second
    det = SampleRateStopDetector(threshold=3.0, samples=2)
    assert det.run(zip(t, q, strict=True)) == pytest.approx([0.04])
    assert math.isclose(det.rate, 2.0 * math.sin(0.5 * 8.0 * 0.02 / 2) / 0.02, rel_tol=1e-9)
