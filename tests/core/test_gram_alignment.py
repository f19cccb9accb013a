"""BILTS+ with ``align="gram"``: DTW aligned on the dot products of each sample's six vectors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import framefree as ff
from framefree.core import se3
from framefree.core.kabsch import residual_columns
from framefree.descriptors.bilts import GRAM_NAMES, gram_columns

from .test_bilts import _generic_motion, pose_strategy

LIVE = {"L": 0.1, "ds_scale": 0.06, "presmooth": 5, "axis_prior": 1.0, "spacing": 4}


def _kabsch_dtw(X: np.ndarray, Y: np.ndarray) -> float:
    """The smallest sum of Kabsch residuals over every monotone path, divided as the distance is:
    what any alignment's path sum is at least."""
    n, m = len(X), len(Y)
    C = np.full((n + 1, m + 1), np.inf)
    C[0, 0] = 0.0
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            C[i, j] = residual_columns(X[i - 1], Y[j - 1], 6) + min(C[i - 1, j], C[i, j - 1],
                                                                     C[i - 1, j - 1])
    return float(C[n, m] / (n + m - 1))


@given(st.lists(st.floats(-np.pi, np.pi), min_size=3, max_size=3), st.integers(0, 1000))
def test_gram_columns_do_not_depend_on_the_moving_frame(rotation, seed):
    samples = np.random.default_rng(seed).normal(size=(5, 24))
    R = se3.rotation_from_vector(np.array(rotation))
    turned = samples.copy()
    turned[:, :18] = (samples[:, :18].reshape(5, 6, 3) @ R.T).reshape(5, 18)
    np.testing.assert_allclose(gram_columns(turned), gram_columns(samples), atol=1e-12)
    assert gram_columns(samples).shape == (5, len(GRAM_NAMES)) == (5, 21)


@given(pose_strategy, st.integers(0, 50))
def test_gram_descriptor_keeps_world_invariance(Tw, seed):
    traj = _generic_motion(seed)
    desc = ff.get_descriptor("bilts+", align="gram", **LIVE)
    a, b = desc.compute(traj), desc.compute(traj.transformed(world=Tw))
    assert a.shape[1] == desc.n_features == 45
    np.testing.assert_allclose(b, a, atol=1e-8)


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 1000), st.integers(0, 1000))
def test_no_alignment_beats_the_best_path(seed_a, seed_b):
    """Both alignments sum the same Kabsch residuals along a path: never below the best path."""
    singular = ff.get_descriptor("bilts+", **LIVE)
    gram = ff.get_descriptor("bilts+", align="gram", **LIVE)
    A, B = _generic_motion(seed_a % 50), _generic_motion(seed_b % 50 + 50)
    best = _kabsch_dtw(singular.compute(A), singular.compute(B))
    assert gram.distance(gram.compute(A), gram.compute(B)) >= best - 1e-12
    assert singular.distance(singular.compute(A), singular.compute(B)) >= best - 1e-12


def test_gram_alignment_follows_the_strokes_of_a_zigzag():
    """Five zigzags recorded in one go (replica): aligned on the singular values, two of them lie
    ten times farther apart than the others (straight strokes give nearly constant singular values,
    and the path slides one stroke over another); aligned on the dot products, every pair lies near
    the best path."""
    from framefree.library import TakeRecorder
    from framefree.replica import DEFAULT_PERSON
    from framefree.replica.people_streams import take_session

    session = take_session("zigzag", DEFAULT_PERSON, 5, seed=0)
    rec = TakeRecorder()
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        rec.push(t, p, q)
    takes = [take for _, take in rec.finish()]
    assert len(takes) == 5
    out = {}
    for align in ("singular", "gram"):
        desc = ff.get_descriptor("bilts+", align=align, **LIVE)
        models = [desc.compute(tk) for tk in takes]
        out[align] = desc.distance_matrix(models, models)
    best = np.array([[_kabsch_dtw(a, b) for b in models] for a in models])
    assert out["singular"].max() > 0.3
    assert out["gram"].max() < 0.15
    np.testing.assert_allclose(out["gram"], best, atol=0.01)


def test_align_is_validated():
    with pytest.raises(ValueError, match="align"):
        ff.get_descriptor("bilts+", align="svd")
    desc = ff.get_descriptor("bilts+", align="gram", **LIVE)
    with pytest.raises(ValueError, match="45"):
        desc.distance(np.zeros((5, 24)), np.zeros((5, 24)))
