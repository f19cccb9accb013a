import numpy as np

from framefree.online.paper.preprocess import (
    StreamingBILTSPlus,
    descriptor_from_samples,
    geometric_samples,
    replay,
)


def test_streaming_equals_offline_path(kettle):
    res, L, ds_scale = 0.03, 0.5, 0.09
    live, times = replay(kettle, res, L, ds_scale)
    offline = descriptor_from_samples(geometric_samples(kettle, res, L), res, L, ds_scale)
    assert live.shape == offline.shape
    assert live.shape[0] > 20
    np.testing.assert_allclose(live, offline, rtol=0, atol=1e-12)
    assert np.all(np.diff(times) > 0)


def test_sample_count_and_delay(kettle):
    calc = StreamingBILTSPlus(0.03, 0.5, 0.09)
    n_out = sum(calc.push(kettle.p[k], kettle.q[k]) is not None for k in range(len(kettle)))
    assert n_out == calc.n_geometric - 5 - 2 * calc.m
    assert calc.delay == calc.m + 5


def test_reset_starts_new_sequence(kettle):
    calc = StreamingBILTSPlus(0.03, 0.5, 0.09)
    first = [d for k in range(len(kettle)) if (d := calc.push(kettle.p[k], kettle.q[k])) is not None]
    calc.reset()
    second = [d for k in range(len(kettle)) if (d := calc.push(kettle.p[k], kettle.q[k])) is not None]
    np.testing.assert_array_equal(np.array(first), np.array(second))


def test_world_frame_invariance(kettle):
    rng = np.random.default_rng(1)
    from framefree.core import se3

    W = np.eye(4)
    W[:3, :3] = se3.rotation_from_vector(rng.normal(size=3))
    W[:3, 3] = rng.normal(size=3)
    a, _ = replay(kettle, 0.03, 0.5, 0.09)
    b, _ = replay(kettle.transformed(world=W), 0.03, 0.5, 0.09)
    from framefree.core.kabsch import kabsch_residual

    # same samples up to a rotation of each 3×6 block
    A = a.reshape(-1, 6, 3).transpose(0, 2, 1)
    B = b.reshape(-1, 6, 3).transpose(0, 2, 1)
    assert a.shape == b.shape
    assert kabsch_residual(A, B).max() < 1e-8


def test_presmoothed_streaming_equals_offline_path(kettle):
    res, L, ds_scale = 0.03, 0.5, 0.09
    live, _ = replay(kettle, res, L, ds_scale, presmooth=5)
    offline = descriptor_from_samples(geometric_samples(kettle, res, L, presmooth=5), res, L, ds_scale)
    assert live.shape == offline.shape and live.shape[0] > 20
    np.testing.assert_allclose(live, offline, rtol=0, atol=1e-12)
    raw, _ = replay(kettle, res, L, ds_scale)
    assert not np.array_equal(raw[: min(len(raw), len(live))], live[: min(len(raw), len(live))])
