"""Windowed stop detector: golden speeds, jitter robustness, calibration, replica stop signals."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.datasets import GESTURES, STOP
from framefree.online.paper.stop import SampleRateStopDetector
from framefree.online.stop import (
    StopDetector,
    WindowedAngularSpeed,
    sustained_peak_speed,
    windowed_angular_speeds,
)
from framefree.replica import make_stream, synthesize_gesture
from framefree.replica.faults import duplicates, jitter

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


# ------------------------------------------------------------------------ shape check (confirm)
def strokes(angles, durations, period: float = 0.02):
    """Times and quaternions of minimum-jerk rotation strokes about one fixed axis, one after
    the other (``angles`` [rad], signed; ``durations`` [s])."""
    axis = np.array([2.0, 1.0, 2.0]) / 3.0
    t_all, a_all, t0, a0 = [0.0], [0.0], 0.0, 0.0
    for angle, dur in zip(angles, durations, strict=True):
        t = np.arange(1, round(dur / period) + 1) * period
        x = t / dur
        t_all.extend(t0 + t)
        a_all.extend(a0 + angle * x**3 * (10 - 15 * x + 6 * x**2))
        t0, a0 = t0 + t[-1], a0 + angle
    t, a = np.array(t_all), np.array(a_all)
    t = np.concatenate([t, t[-1] + period * np.arange(1, 30)])  # then hold still
    a = np.concatenate([a, np.full(29, a[-1])])
    return t, np.column_stack([np.cos(a / 2), np.sin(a / 2)[:, None] * axis])


def _detector(confirm):
    return StopDetector(threshold=7.0, confirm=confirm, sustain_ratio=0.82, instant=1.6)


def test_a_quick_shake_is_a_stop_with_and_without_the_shape_check():
    a = math.radians(65)
    t, q = strokes([a, -2 * a, a], [0.25, 0.4, 0.25])  # peak ~9.3 rad/s
    plain = _detector(0.0).run(zip(t, q, strict=True))
    checked = _detector(0.3).run(zip(t, q, strict=True))
    assert len(plain) == 1 and len(checked) == 1
    assert 0.25 <= checked[0] - plain[0] <= 0.35  # it waits for the shape check


def test_a_fast_gesture_stroke_is_not_a_stop():
    # a forearm turn of 150 degrees and back in 0.65 s strokes: peak ~7.6 rad/s, above the
    # threshold, but sustained in one direction for longer than a stop signal's strokes (strokes
    # under about 0.55 s are as quick as a stop's and are not told apart)
    a = math.radians(150)
    t, q = strokes([a, -a], [0.65, 0.65])
    assert len(_detector(0.0).run(zip(t, q, strict=True))) == 1
    assert _detector(0.3).run(zip(t, q, strict=True)) == []


def test_a_rotation_beyond_instant_fires_at_once():
    t, q = spin(12.0, 0.6)  # 12 rad/s > 1.6 x 7 rad/s
    plain = _detector(0.0).run(zip(t, q, strict=True))
    checked = _detector(0.3).run(zip(t, q, strict=True))
    assert checked == plain and len(plain) == 1


def _jittered(t, amplitude, rng):
    return np.maximum.accumulate(t + rng.uniform(-amplitude, amplitude, t.size))


@settings(max_examples=20, deadline=None)
@given(st.floats(0.6, 1.0), st.floats(0.18, 0.3), st.integers(0, 1000))
def test_shakes_fire_under_time_stamp_jitter(amp, dur, seed):
    # jitter (±8 ms) inflates the short-window peak and so makes every rotation look less
    # sustained: a stop signal is never lost to it (a gesture stroke may then pass as a stop, as
    # without the check)
    t, q = strokes([amp, -2 * amp, amp], [dur, 1.6 * dur, dur])
    t = _jittered(t, 0.008, np.random.default_rng(seed))
    det = StopDetector(threshold=min(7.0, 0.8 * float(np.nanmax(windowed_angular_speeds(t, q)))),
                       confirm=0.3)
    assert len(det.run(zip(t, q, strict=True))) == 1


@settings(max_examples=20, deadline=None)
@given(st.floats(2.0, 2.9), st.floats(0.7, 1.0), st.integers(0, 1000))
def test_sustained_strokes_are_no_stop_under_small_jitter(amp, dur, seed):
    t, q = strokes([amp, -amp], [dur, dur])
    t = _jittered(t, 0.002, np.random.default_rng(seed))
    peak = float(np.nanmax(windowed_angular_speeds(t, q)))
    assert StopDetector(threshold=0.9 * peak, confirm=0.0).run(zip(t, q, strict=True))
    assert StopDetector(threshold=0.9 * peak, confirm=0.3).run(zip(t, q, strict=True)) == []


def test_no_stop_fires_while_a_relocation_settles():
    a = math.radians(65)
    t, q = strokes([a, -2 * a, a], [0.25, 0.4, 0.25])  # a quick shake: a stop
    det = _detector(0.3)
    det.settle(t[0] - 0.5)  # the tracker jumped half a second before
    assert det.run(zip(t, q, strict=True)) == []
    det = _detector(0.3)
    det.settle(t[0] - det.refractory - 0.01)  # long enough before
    assert len(det.run(zip(t, q, strict=True))) == 1


def test_an_orientation_flip_of_hand_tracking_is_no_stop(model_set):
    """A hand tracker at 20 Hz flips the palm's orientation by 140 degrees for two frames and
    turns it back over three (as in a real SFINGE3D sequence): the gate takes the flip for a
    relocation, and the fast turn back does not fire a stop."""
    from framefree.online import Recognizer

    trajs, labels = model_set
    rec = Recognizer.from_trajectories(trajs, labels, stop_threshold=8.0)
    rec.background = False
    t = np.arange(0.0, 4.0, 0.05)
    p = np.column_stack([0.3 + 0.01 * np.sin(t), 0.2 + 0 * t, 0.4 + 0 * t])
    q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    k = int(np.searchsorted(t, 2.0))
    angles = [2.45, 2.3, 1.0, 0.35]  # about x: out in one frame, back over three
    for j, angle in enumerate(angles):
        q[k + j] = [math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0]
    events = []
    for tt, pp, qq in zip(t, p, q, strict=True):
        events += rec.push(tt, pp, qq)
    assert rec.gate.stats["relocations"] == 1
    assert [e for e in events if e.is_stop] == []
    speeds = windowed_angular_speeds(t[k + 1:], q[k + 1:])
    assert np.nanmax(speeds) > 8.0  # the turn back alone is faster than the threshold
