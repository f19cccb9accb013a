"""SampleGate: every tracker defect injected into a clean replica stream, and arbitrary input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.online.acceptance import GATE_STAT_KEYS, SampleGate
from framefree.replica import make_stream
from framefree.replica.faults import FAULT_KINDS, dropouts, inject, outliers

SEQUENCE = ["go_up", "stop", "go_left", "close_gripper"]


@pytest.fixture(scope="module")
def stream() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    traj, _ = make_stream(21, sequence=SEQUENCE)
    return traj.t.copy(), traj.p.copy(), traj.q.copy()


def feed(gate: SampleGate, t: np.ndarray, p: np.ndarray, q: np.ndarray):
    """All samples through the gate: output arrays and the number of restarts."""
    out, restarts = [], 0
    for k in range(t.shape[0]):
        acc = gate.push(t[k], p[k], q[k])
        restarts += acc.restarted
        out.extend(acc.samples)
    return (np.array([s[0] for s in out]), np.array([s[1] for s in out]),
            np.array([s[2] for s in out]), restarts)


def true_poses(t: np.ndarray, p: np.ndarray, q: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The clean stream interpolated (ScLERP) at times ``at``."""
    return se3.interpolate_poses(t, se3.poses_from_pq(p, q), at)


def pose_errors(T_true: np.ndarray, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position [m] and rotation-angle [rad] errors of (p, q) against poses (n, 4, 4)."""
    q_true = se3.quaternion_from_matrix(T_true[:, :3, :3], continuous=False)
    ang = 2.0 * np.arccos(np.clip(np.abs(np.sum(q_true * q, axis=1)), 0.0, 1.0))
    return np.linalg.norm(T_true[:, :3, 3] - p, axis=1), ang


def check_clean_output(t: np.ndarray, q: np.ndarray) -> None:
    assert (np.diff(t) > 0).all()
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    assert (np.sum(q[1:] * q[:-1], axis=1) >= 0.0).all()


def test_clean_stream_passes_unchanged(stream):
    t, p, q = stream
    gate = SampleGate()
    to, po, qo, restarts = feed(gate, t, p, q)
    assert restarts == 0
    np.testing.assert_array_equal(to, t)
    np.testing.assert_allclose(po, p, atol=1e-15)
    np.testing.assert_allclose(qo, q, atol=1e-15)
    assert gate.stats["accepted"] == t.size
    assert sum(gate.stats[k] for k in ("outliers", "gaps", "relocations", "repeated")) == 0


@pytest.mark.parametrize("kind", FAULT_KINDS)
def test_fault_output_stays_on_the_clean_stream(stream, kind):
    t, p, q = stream
    ft, fp, fq = inject(kind, t, p, q, np.random.default_rng(5))
    gate = SampleGate()
    to, po, qo, restarts = feed(gate, ft, fp, fq)
    assert restarts == 0
    check_clean_output(to, qo)
    real = np.isin(to, ft)
    if kind == "jitter":  # stamps moved: compare with the samples as delivered
        k = np.searchsorted(ft, to[real])
        np.testing.assert_allclose(po[real], fp[k], atol=1e-12)
        np.testing.assert_allclose(np.abs(np.sum(qo[real] * fq[k], axis=1)), 1.0, atol=1e-12)
        assert gate.stats["accepted"] == t.size
        return
    dp, da = pose_errors(true_poses(t, p, q, to), po, qo)
    assert dp[real].max() < 1e-9 and da[real].max() < 1e-6  # every real sample is a clean one
    if kind in ("outliers", "rotation_outliers"):
        assert gate.stats["outliers"] == gate.stats["samples"] - gate.stats["accepted"] > 0
    if kind == "sign_flips":
        np.testing.assert_allclose(qo, q, atol=1e-15)  # flips undone: the clean signs
        assert gate.stats["sign_flips"] > 0
    if kind == "duplicates":
        np.testing.assert_array_equal(to, t)
        assert gate.stats["repeated"] == ft.size - t.size
    if kind == "nan":
        assert gate.stats["nan"] == ft.size - np.isfinite(ft).sum() + (
            ~np.isfinite(fp).all(axis=1)).sum() + (~np.isfinite(fq).all(axis=1)).sum()
    kept = np.isin(t, to)
    if kind != "dropouts":
        assert kept.sum() == gate.stats["accepted"]


def slow_start(t: np.ndarray, p: np.ndarray, duration: float) -> float:
    """Start of the ``duration``-second stretch where the hand moves least."""
    best, where = math.inf, 0.0
    for k in range(0, t.size, 5):
        m = (t >= t[k]) & (t <= t[k] + duration + 0.1)
        if t[k] + duration + 0.1 > t[-1]:
            break
        path = np.linalg.norm(np.diff(p[m], axis=0), axis=1).sum()
        if path < best:
            best, where = path, float(t[k])
    return where


@pytest.mark.parametrize("gap", [0.3, 0.45])
def test_dropout_in_a_slow_part_is_bridged_close_to_the_truth(stream, gap):
    t, p, q = stream
    start = slow_start(t, p, gap)
    ft, fp, fq = dropouts(t, p, q, np.random.default_rng(0), starts=[start],
                          min_duration=gap, max_duration=gap)
    assert np.diff(ft).max() > gap - 0.03
    gate = SampleGate()
    to, po, qo, restarts = feed(gate, ft, fp, fq)
    assert restarts == 0 and gate.stats["bridged_gaps"] >= 1
    bridged = ~np.isin(to, ft)
    assert bridged.sum() == gate.stats["bridged_samples"]
    assert abs(bridged.sum() - round(gap / 0.02)) <= 3
    dp, da = pose_errors(true_poses(t, p, q, to[bridged]), po[bridged], qo[bridged])
    assert dp.max() < 0.005 and np.degrees(da.max()) < 3.0
    assert np.diff(to[bridged]).max() < 0.025  # at about the nominal period


def test_a_long_gap_restarts(stream):
    t, p, q = stream
    ft, fp, fq = dropouts(t, p, q, np.random.default_rng(0), starts=[8.0],
                          min_duration=1.0, max_duration=1.0)
    gate = SampleGate()
    to, _, _, restarts = feed(gate, ft, fp, fq)
    assert restarts == 1 and gate.stats["gaps"] == 1 and gate.stats["bridged_samples"] == 0
    np.testing.assert_array_equal(to, ft)


def test_outlier_next_to_a_dropout_is_dropped_without_restart(stream):
    t, p, q = stream
    for before in (True, False):  # outlier just before the gap, or just after it
        k = int(np.searchsorted(t, 6.0))
        ft, fp, fq = t.copy(), p.copy(), q.copy()
        fp[k] += [0.5, 0.0, 0.0]
        lo, hi = (k + 1, k + 16) if before else (k - 15, k)
        keep = np.ones(t.size, bool)
        keep[lo:hi] = False
        gate = SampleGate()
        to, po, _, restarts = feed(gate, ft[keep], fp[keep], fq[keep])
        assert restarts == 0
        assert gate.stats["outliers"] == 1 and gate.stats["relocations"] == 0
        assert gate.stats["bridged_gaps"] == 1
        assert t[k] not in to
        assert np.linalg.norm(po - true_poses(t, p, q, to)[:, :3, 3], axis=1).max() < 0.05


def test_relocation_restarts_after_patience(stream):
    t, p, q = stream
    k = int(np.searchsorted(t, 7.0))
    fp = p.copy()
    fp[k:] += [0.0, 0.0, 0.5]
    gate = SampleGate(patience=4)
    to, po, _, restarts = feed(gate, t, fp, q)
    assert restarts == 1 and gate.stats["relocations"] == 1 and gate.stats["outliers"] == 0
    np.testing.assert_array_equal(to, t)  # the held far samples are released, none lost
    np.testing.assert_allclose(po, fp)


def test_repeated_backwards_and_clock_reset():
    gate = SampleGate()
    q = np.array([1.0, 0.0, 0.0, 0.0])
    got = []
    for k in range(10):
        got += gate.push(0.02 * k, [0.0, 0.0, 0.001 * k], q).samples
    assert len(got) == 10
    assert gate.push(0.18, [0.0, 0.0, 0.009], q).samples == []  # same time stamp
    assert gate.push(0.10, [0.0, 0.0, 0.009], q).samples == []  # backwards
    assert gate.stats["repeated"] == 1 and gate.stats["backwards"] == 1
    released = []
    for k in range(6):  # the clock starts again from zero
        acc = gate.push(0.02 * k + 0.001, [0.0, 0.0, 0.0], q)
        if acc.samples:
            released.append((acc.restarted, [s[0] for s in acc.samples]))
    assert gate.stats["clock_resets"] == 1
    assert released[0][0] and not any(r for r, _ in released[1:])
    assert released[0][1][0] == pytest.approx(0.021)  # third backwards stamp in a row (0.10 first)


def test_invalid_values_are_counted():
    gate = SampleGate()
    assert gate.push(0.0, [0, 0, 0], [0, 0, 0, 0]).samples == []
    assert gate.push(0.0, [math.nan, 0, 0], [1, 0, 0, 0]).samples == []
    assert gate.push(math.inf, [0, 0, 0], [1, 0, 0, 0]).samples == []
    assert gate.stats["bad_quaternion"] == 1 and gate.stats["nan"] == 2
    assert set(gate.stats) == set(GATE_STAT_KEYS)


def test_memory_stays_bounded(stream):
    t, p, q = stream
    rng = np.random.default_rng(3)
    ft, fp, fq = outliers(t, p, q, rng, count=200, distance=0.5)
    for kind in ("dropouts", "duplicates", "nan", "sign_flips", "jitter"):
        ft, fp, fq = inject(kind, ft, fp, fq, rng)
    gate = SampleGate(patience=3, period_window=8)
    worst = 0
    for k in range(ft.size):
        gate.push(ft[k], fp[k], fq[k])
        worst = max(worst, gate.n_held)
    assert worst <= 3
    assert len(gate._intervals) <= 8
    assert 0.015 < gate.period < 0.025


finite = st.floats(-1e3, 1e3, allow_nan=False)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.floats(-10, 10, allow_nan=False), st.tuples(finite, finite, finite),
                          st.tuples(finite, finite, finite, finite)), max_size=60))
def test_any_finite_sequence_gives_a_clean_stream(samples):
    gate = SampleGate()
    pieces: list[list] = [[]]  # the output, split where the stream restarted
    for t, p, q in samples:
        acc = gate.push(t, p, q)
        if acc.restarted:
            pieces.append([])
        pieces[-1].extend(acc.samples)
        assert gate.n_held <= gate.patience
    out = [s for piece in pieces for s in piece]
    if out:
        check_clean_output(np.arange(len(out)), np.array([s[2] for s in out]))
        assert all(np.isfinite(s[1]).all() and math.isfinite(s[0]) for s in out)
    for piece in pieces:
        assert (np.diff([s[0] for s in piece]) > 0).all()
    assert gate.stats["samples"] == len(samples)
