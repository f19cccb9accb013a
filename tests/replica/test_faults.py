"""Fault injection: pure functions, each fault exactly as documented."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.replica import make_stream
from framefree.replica.faults import (
    FAULT_KINDS,
    dropouts,
    duplicates,
    inject,
    jitter,
    nan_samples,
    outliers,
    rotation_outliers,
    sign_flips,
)


@pytest.fixture(scope="module")
def arrays() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    traj, _ = make_stream(5, sequence=["go_right", "stop", "open_gripper"])
    return traj.t, traj.p, traj.q  # read-only arrays: a fault writing into them would raise


def rng(seed: int = 0) -> np.random.Generator:
    return np.random.default_rng(seed)


@pytest.mark.parametrize("kind", FAULT_KINDS)
def test_pure_and_deterministic(arrays, kind):
    t, p, q = arrays
    before = [a.copy() for a in arrays]
    a = inject(kind, t, p, q, rng(3))
    b = inject(kind, t, p, q, rng(3))
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)
        assert x.flags.writeable
    for x, y in zip(arrays, before, strict=True):
        np.testing.assert_array_equal(x, y)
    assert all(not np.shares_memory(x, y) for x in a for y in arrays)
    n = a[0].shape[0]
    assert a[1].shape == (n, 3) and a[2].shape == (n, 4)


def test_unknown_kind():
    with pytest.raises(ValueError, match="unknown fault 'teleport'"):
        inject("teleport", np.zeros(3), np.zeros((3, 3)), np.zeros((3, 4)), rng())


def test_dropouts(arrays):
    t, p, q = arrays
    ft, fp, _ = dropouts(t, p, q, rng(1), count=4, min_duration=0.3, max_duration=0.5)
    gaps = np.diff(ft)
    long = gaps[gaps > 0.1]
    assert 1 <= long.size <= 4 and long.max() <= 0.5 + 1e-12 and long.min() >= 0.3 - 0.05
    kept = np.searchsorted(t, ft)
    np.testing.assert_array_equal(t[kept], ft)
    np.testing.assert_array_equal(p[kept], fp)
    assert ft[0] == t[0] and ft[-1] == t[-1]
    ft2, _, _ = dropouts(t, p, q, rng(1), starts=[5.0], min_duration=0.4, max_duration=0.4)
    k = int(np.argmax(np.diff(ft2)))
    assert ft2[k] <= 5.0 < ft2[k + 1] and 0.38 <= ft2[k + 1] - ft2[k] <= 0.4


@pytest.mark.parametrize("distribution", ["uniform", "normal"])
def test_jitter(arrays, distribution):
    t, p, q = arrays
    ft, fp, fq = jitter(t, p, q, rng(2), amplitude=0.008, distribution=distribution)
    d = ft - t
    assert np.abs(d).max() <= 0.008 + 1e-12 and np.abs(d).max() > 0.006 and d.std() > 0.002
    np.testing.assert_array_equal(fp, p)
    np.testing.assert_array_equal(fq, q)
    with pytest.raises(ValueError, match="jitter distribution"):
        jitter(t, p, q, rng(), distribution="cauchy")


@pytest.mark.parametrize("same_pose", [True, False])
def test_duplicates(arrays, same_pose):
    t, p, q = arrays
    ft, fp, _ = duplicates(t, p, q, rng(4), fraction=0.05, same_pose=same_pose)
    rep = np.flatnonzero(np.diff(ft) == 0) + 1
    assert rep.size == round(0.05 * t.size) == ft.size - t.size
    np.testing.assert_array_equal(np.delete(ft, rep), t)
    np.testing.assert_array_equal(np.delete(fp, rep, axis=0), p)
    k = np.searchsorted(t, ft[rep])
    if same_pose:
        np.testing.assert_array_equal(fp[rep], p[k])
    else:
        np.testing.assert_array_equal(fp[rep], p[k + 1])


def test_sign_flips(arrays):
    t, p, q = arrays
    _, _, fq = sign_flips(t, p, q, rng(5), fraction=0.1)
    flipped = np.all(fq == -q, axis=1)
    assert np.all(flipped | np.all(fq == q, axis=1))
    assert 0.05 * t.size < flipped.sum() < 0.15 * t.size


def test_outliers(arrays):
    t, p, q = arrays
    ft, fp, fq = outliers(t, p, q, rng(6), count=5, distance=0.5, angle=1.0)
    moved = np.flatnonzero(np.linalg.norm(fp - p, axis=1) > 0)
    assert 1 <= moved.size <= 5 and (np.diff(moved) > 2).all()
    np.testing.assert_allclose(np.linalg.norm(fp[moved] - p[moved], axis=1), 0.5)
    ang = 2 * np.arccos(np.clip(np.abs(np.sum(fq[moved] * q[moved], axis=1)), 0, 1))
    np.testing.assert_allclose(ang, 1.0, atol=1e-9)
    np.testing.assert_array_equal(ft, t)
    _, rp, rq = rotation_outliers(t, p, q, rng(6), count=3)
    np.testing.assert_array_equal(rp, p)
    turned = np.flatnonzero(np.any(rq != q, axis=1))
    ang = 2 * np.arccos(np.clip(np.abs(np.sum(rq[turned] * q[turned], axis=1)), 0, 1))
    np.testing.assert_allclose(ang, np.pi / 2, atol=1e-9)


def test_nan_samples(arrays):
    t, p, q = arrays
    ft, fp, fq = nan_samples(t, p, q, rng(7), fraction=0.02)
    bad = ~np.isfinite(ft) | ~np.isfinite(fp).all(axis=1) | ~np.isfinite(fq).all(axis=1)
    assert bad.sum() == round(0.02 * t.size)
    good = ~bad
    np.testing.assert_array_equal(ft[good], t[good])
    np.testing.assert_array_equal(fq[good], q[good])
