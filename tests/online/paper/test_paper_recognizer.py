import math
import tracemalloc

import numpy as np
import pytest

from framefree import Trajectory
from framefree.online import STOP
from framefree.online.paper import PaperRecognizer


@pytest.fixture(scope="module")
def rec(model_set, config):
    trajs, labels = model_set
    r = PaperRecognizer.from_trajectories(trajs, labels, config)
    r.warmup()
    return r


@pytest.fixture(scope="module")
def session(model_set, concat):
    trajs, _ = model_set
    return concat([trajs[0], trajs[6], trajs[3], trajs[7]])


def _run(rec, rows):
    rec.reset()
    events = []
    for t, p, q in rows:
        events += rec.push(t, p, q)
    return events, dict(rec.stats)


def _rows(traj):
    return [(float(traj.t[k]), traj.p[k].copy(), traj.q[k].copy()) for k in range(len(traj))]


def test_clean_session_detects_the_gestures(rec, session):
    events, stats = _run(rec, _rows(session))
    assert stats["accepted"] == len(session)
    labels = [e.label for e in events if not e.is_stop]
    assert labels[0] == "pour"
    assert {"pour", "scoop", "pour_ip"} <= set(labels)


@pytest.mark.parametrize(
    "kind",
    ["nan", "bad_quaternion", "repeated", "backwards", "sign_flips", "jumps"],
)
def test_bad_samples_are_skipped_and_counted(rec, session, kind):
    clean_events, clean = _run(rec, _rows(session))
    rows = _rows(session)
    k = len(rows) // 3
    t, p, q = rows[k]
    if kind == "nan":
        rows.insert(k, (t + 0.001, np.array([np.nan, 0, 0]), q))
    elif kind == "bad_quaternion":
        rows.insert(k, (t + 0.001, p, np.zeros(4)))
    elif kind == "repeated":
        rows.insert(k + 1, (t, p + 0.01, q))
    elif kind == "backwards":
        rows.insert(k + 1, (t - 0.5, p, q))
    elif kind == "sign_flips":
        rows = [(tt, pp, -qq if i % 7 == 3 else qq) for i, (tt, pp, qq) in enumerate(rows)]
    elif kind == "jumps":
        rows.insert(k + 1, (t + 0.001, p + np.array([5.0, 0.0, 0.0]), q))
    events, stats = _run(rec, rows)
    assert stats[kind] >= 1
    if kind != "sign_flips":
        assert stats[kind] == 1
    assert stats["accepted"] == clean["accepted"]
    assert stats["geometric"] == clean["geometric"]
    assert stats["descriptors"] == clean["descriptors"]
    assert [(e.label, e.time) for e in events] == [(e.label, e.time) for e in clean_events]


def test_gap_restarts(rec, session):
    rows = _rows(session)
    k = len(rows) // 2
    rows = rows[:k] + [(t + 5.0, p, q) for t, p, q in rows[k:]]
    _, stats = _run(rec, rows)
    assert stats["gaps"] == 1
    assert rec.preprocessor.n_geometric < stats["geometric"]


def test_relocation_after_persistent_jump(rec, session):
    rows = _rows(session)
    k = len(rows) // 2
    rows = rows[:k] + [(t, p + np.array([0.0, 3.0, 0.0]), q) for t, p, q in rows[k:]]
    _, stats = _run(rec, rows)
    assert stats["jumps"] == rec.config.jump_patience - 1
    assert stats["relocations"] == 1


def _fast_rotation(t0, p, q0, speed=12.0, duration=0.3):
    """Rotation about x at ``speed`` rad/s (|dq/dt| = speed/2), 50 Hz."""
    rows = []
    for i in range(1, int(duration * 50) + 1):
        a = speed * i * 0.02
        dq = np.array([math.cos(a / 2), math.sin(a / 2), 0.0, 0.0])
        w1, x1, y1, z1 = q0
        w2, x2, y2, z2 = dq
        q = np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                      w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])
        rows.append((t0 + i * 0.02, p, q))
    return rows


def test_stop_takes_precedence(model_set, config, session):
    trajs, labels = model_set
    # threshold so loose that every ready matcher fires: a stop must still win
    rec = PaperRecognizer.from_trajectories(trajs, labels, config.replace(threshold=1e9))
    rows = _rows(session)
    k = len(rows) // 2
    t, p, q = rows[k]
    fast = _fast_rotation(t, p, q)
    later = [(tt + 0.3 + 1e-3, pp, qq) for tt, pp, qq in rows[k + 1 :]]
    rec.reset()
    stop_seen = False
    for tt, pp, qq in rows[: k + 1] + fast + later:
        evs = rec.push(tt, pp, qq)
        if any(e.label == STOP for e in evs):
            assert len(evs) == 1 and evs[0].dissimilarity == -1.0 and evs[0].model == -1
            stop_seen = True
            assert rec.bank.count == 0  # windows cleared
        if rec.stop.active:
            assert all(e.is_stop for e in evs)
    assert stop_seen
    assert rec.stats["stops"] == 1


def test_refractory_reset(model_set, config, session):
    trajs, labels = model_set
    rec = PaperRecognizer.from_trajectories(trajs, labels, config.replace(threshold=1e9))
    _, stats = _run(rec, _rows(session))
    assert stats["events"] >= 2
    # after each event all windows restart: the next one needs a full (latency-shortened) window
    shortest = int(min(rec.bank.lengths - rec.bank.lat_hi))
    assert stats["events"] <= stats["descriptors"] // shortest + 1
    loose = PaperRecognizer.from_trajectories(trajs, labels,
                                         config.replace(threshold=1e9, refractory_reset=False))
    _, stats2 = _run(loose, _rows(session))
    assert stats2["events"] > stats["events"]


def test_memory_stays_flat(rec):
    rng = np.random.default_rng(0)
    n = 100_000
    t = np.arange(n) * 0.02
    a = 0.7 * t
    p = np.column_stack([0.3 * np.sin(a), 0.2 * np.cos(1.7 * a), 0.1 * np.sin(0.3 * a)])
    ang = 0.8 * np.sin(0.5 * a)
    q = np.column_stack([np.cos(ang / 2), np.sin(ang / 2) * 0.6, np.sin(ang / 2) * 0.8,
                         np.zeros(n)]) + 1e-4 * rng.normal(size=(n, 4))
    rec.reset()
    for k in range(2000):
        rec.push(t[k], p[k], q[k])
    sizes = (len(rec.preprocessor._raw), len(rec.preprocessor._twists), rec.bank.S.size)
    # traced allocations over 20k samples (tracemalloc is slow), buffer sizes over all 100k
    tracemalloc.start()
    base, _ = tracemalloc.get_traced_memory()
    for k in range(2000, 22_000):
        rec.push(t[k], p[k], q[k])
    now, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert now - base < 100_000  # bytes
    for k in range(22_000, n):
        rec.push(t[k], p[k], q[k])
    assert rec.stats["samples"] == n
    assert rec.stats["descriptors"] > 5000
    assert (len(rec.preprocessor._raw), len(rec.preprocessor._twists), rec.bank.S.size) == sizes


def test_automatic_calibration(model_set, session):
    trajs, labels = model_set
    rec = PaperRecognizer.from_trajectories(trajs, labels, resolution=0.04)
    cal = rec.calibration
    assert cal is not None and rec.threshold > 0
    assert cal.negatives.size >= len(trajs)
    assert set(cal.negative_kinds) <= {"rest", "moves", "cross"}
    assert rec.stop_threshold >= rec.config.stop_floor
    d = rec.describe()
    assert d["calibration"]["threshold"] == rec.threshold
    # per-gesture thresholds (default), each from its own positives and negatives
    assert set(rec.gesture_thresholds) == set(labels)
    assert all(v > 0 for v in rec.gesture_thresholds.values())
    for j, lab in enumerate(rec.labels):
        assert rec.model_thresholds[j] == rec.gesture_thresholds[lab]
    # the cut pieces of the recordings remain available; global mode gives one τ
    rec3 = PaperRecognizer.from_trajectories(trajs, labels, resolution=0.04, threshold_mode="global",
                                        calibration_negatives=("head", "middle", "tail", "splice"))
    assert set(rec3.calibration.negative_kinds) <= {"head", "middle", "tail", "splice"}
    assert len(set(rec3.gesture_thresholds.values())) == 1
    # the user can override both
    rec2 = PaperRecognizer.from_trajectories(trajs, labels, resolution=0.04, threshold=0.123,
                                        stop_threshold=9.0)
    assert rec2.threshold == 0.123 and rec2.stop_threshold == 9.0 and rec2.calibration is None


def test_from_dataset_layout(tmp_path, model_set):
    trajs, labels = model_set
    for k, (tr, lab) in enumerate(zip(trajs, labels, strict=True)):
        tr.to_csv(tmp_path / lab / "original_1" / f"trial_{k + 1}.csv")
    rec = PaperRecognizer.from_dataset(tmp_path, model_context="original_1", resolution=0.04,
                                  threshold=0.5, stop_threshold=3.0)
    assert sorted(rec.gestures) == sorted(set(labels))
    assert len(rec.labels) == len(trajs)


def test_models_are_the_streaming_replay(rec, model_set):
    from framefree.online.paper.preprocess import replay

    trajs, _ = model_set
    c = rec.config
    d, _ = replay(trajs[2], c.resolution, c.L, c.ds_scale, c.window, c.twist_noise)
    np.testing.assert_array_equal(d, rec.models.descriptors[2])


def test_trajectory_is_not_modified(session):
    assert isinstance(session, Trajectory)


def test_decision_rules_and_pruning(model_set, config, session):
    """``minimum`` fires at most as often as ``first``, never before it, with a label of the dip's
    minimum; pruning (any factor >= 1) changes no decision."""
    trajs, labels = model_set
    base = config.replace(prune_factor=None)
    first = PaperRecognizer.from_trajectories(trajs, labels, base.replace(decision="first"))
    ev_first, _ = _run(first, _rows(session))
    mini = PaperRecognizer.from_trajectories(trajs, labels, base.replace(decision="minimum"))
    ev_min, _ = _run(mini, _rows(session))
    assert 0 < len(ev_min) <= len(ev_first)
    assert ev_min[0].time >= ev_first[0].time
    assert ev_min[0].dissimilarity <= ev_first[0].dissimilarity + 1e-12
    for factor in (1.0, 3.0):
        pr = PaperRecognizer.from_trajectories(trajs, labels, base.replace(prune_factor=factor))
        ev_pr, _ = _run(pr, _rows(session))
        assert [(e.label, e.time, e.model) for e in ev_pr] == [(e.label, e.time, e.model) for e in ev_min]
        np.testing.assert_allclose([e.dissimilarity for e in ev_pr], [e.dissimilarity for e in ev_min],
                                   rtol=1e-12)


def test_second_best_margin(model_set, config, session):
    """``decision_margin`` only suppresses events (counted as ambiguous); 1.0 changes nothing, and
    an impossible margin suppresses every gesture event whose runner-up is finite."""
    trajs, labels = model_set
    base = config.replace(prune_factor=None)
    plain = PaperRecognizer.from_trajectories(trajs, labels, base)
    ev_plain, st_plain = _run(plain, _rows(session))
    assert st_plain["ambiguous"] == 0
    strict = PaperRecognizer.from_trajectories(trajs, labels, base.replace(decision_margin=1e6))
    ev_strict, st_strict = _run(strict, _rows(session))
    gestures = [e for e in ev_plain if e.label != STOP]
    assert len([e for e in ev_strict if e.label != STOP]) + st_strict["ambiguous"] == len(gestures)
    assert st_strict["ambiguous"] >= 1
    with pytest.raises(ValueError):
        base.replace(decision_margin=0.5)
