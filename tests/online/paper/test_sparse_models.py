"""Recordings too sparse for Algorithm 1 (few poses, a low frame rate) are interpolated, models and
live stream alike; dense recordings are left as they were."""

import numpy as np
import pytest

from framefree import Trajectory
from framefree.core import se3
from framefree.core.progress import StreamingReparameterizer
from framefree.errors import FramefreeError
from framefree.online.paper import PaperConfig
from framefree.online.paper.models import auto_interpolation, build_models
from framefree.online.paper.preprocess import (
    StreamingBILTSPlus,
    densify_poses,
    descriptor_from_samples,
    replay,
)


def _every(traj: Trajectory, n: int) -> Trajectory:
    """Every ``n``-th sample of a recording (a lower frame rate)."""
    return Trajectory(traj.t[::n], traj.p[::n], traj.q[::n])


def test_densify_keeps_the_poses_and_puts_screw_steps_between():
    T = se3.poses_from_pq(np.array([[0, 0, 0], [0.1, 0, 0], [0.1, 0.2, 0]], float),
                          np.array([[1, 0, 0, 0], [1, 0, 0, 0], [0.8, 0.6, 0, 0]], float))
    D = densify_poses(T, 4)
    assert D.shape == (9, 4, 4)
    np.testing.assert_array_equal(D[::4], T)
    np.testing.assert_allclose(D[2, :3, 3], [0.05, 0, 0], atol=1e-12)
    assert densify_poses(T, 1) is T


def test_streaming_with_interpolation_equals_offline_path(kettle):
    res, L, ds_scale, k = 0.03, 0.5, 0.09, 3
    sparse = _every(kettle, 5)
    live, times = replay(sparse, res, L, ds_scale, interpolate=k)
    poses = densify_poses(sparse.poses(), k)
    idx = StreamingReparameterizer(res, L).run(poses)
    p, q = se3.pq_from_poses(poses[idx])
    y = np.column_stack([p, se3.quaternion_continuity(q, se3.NEAREST_SIGN)])
    offline = descriptor_from_samples(y, res, L, ds_scale)
    assert live.shape == offline.shape and live.shape[0] > 10
    np.testing.assert_allclose(live, offline, rtol=0, atol=1e-9)
    assert np.all(np.diff(times) >= 0)


def test_push_refuses_when_poses_are_interpolated(kettle):
    calc = StreamingBILTSPlus(0.03, 0.5, 0.09, interpolate=2)
    with pytest.raises(RuntimeError, match="push_all"):
        calc.push(kettle.p[0], kettle.q[0])


def test_sparse_models_are_interpolated_dense_ones_are_not(model_set):
    trajs, labels = model_set
    cfg = PaperConfig(threshold=0.5, stop_threshold=3.0)
    k_dense, _ = auto_interpolation(trajs, cfg)
    assert k_dense == 1
    sparse = [_every(tr, 12) for tr in trajs]
    with pytest.raises(FramefreeError, match="descriptor samples"):
        build_models(sparse, labels, cfg.replace(interpolate=1))
    models = build_models(sparse, labels, cfg)
    assert models.interpolate > 1
    assert min(d.shape[0] for d in models.descriptors) >= 2


def test_a_recognizer_from_sparse_models_recognizes_a_sparse_session(model_set, concat):
    from framefree.online.paper import PaperRecognizer

    trajs, labels = model_set
    sparse = [_every(tr, 10) for tr in trajs]
    rec = PaperRecognizer.from_trajectories(sparse, labels, PaperConfig(threshold=0.5, stop_threshold=3.0))
    assert rec.config.interpolate == rec.models.interpolate == rec.preprocessor.interpolate > 1
    session = _every(concat([trajs[0], trajs[6], trajs[3]]), 10)
    events = [e for e in rec.run(session) if not e.is_stop]
    assert events and events[0].label == "pour"
    assert rec.stats["geometric"] > len(session)
