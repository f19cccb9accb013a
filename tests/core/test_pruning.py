"""Exact pruning (framefree.core.pruning): bounds never exceed the distance, and every decision is
the full search's — on random vocabularies, on real recordings and live on a stream."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree import NearestNeighborClassifier
from framefree.core.dtw import (
    POINTWISE_EUCLIDEAN,
    POINTWISE_KABSCH,
    POINTWISE_SQUARED,
    path_distance_kernel,
)
from framefree.core.pruning import (
    DistanceSpec,
    ModelBank,
    bound_features,
    envelope_bounds,
    lower_bounds,
    pruned_nearest,
)

MODES = {POINTWISE_KABSCH: (18, 24, 24), POINTWISE_SQUARED: (18, 24, 24), POINTWISE_EUCLIDEAN: (0, 6, 6)}


@st.composite
def vocabularies(draw):
    mode = draw(st.sampled_from(sorted(MODES)))
    lo, hi, width = MODES[mode]
    open_end = draw(st.booleans())
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    n_models = draw(st.integers(1, 12))
    models = [rng.normal(size=(int(rng.integers(3, 25)), width)) for _ in range(n_models)]
    if n_models > 2 and draw(st.booleans()):
        models[-1] = models[0].copy()  # an exact tie
    if mode != POINTWISE_EUCLIDEAN:  # singular-value columns as BILTS stores them, or noise
        for m in models:
            if draw(st.booleans()):
                m[:, 18:24] = bound_features(m, DistanceSpec(18, 24, mode, open_end))
    queries = [rng.normal(size=(int(rng.integers(3, 25)), width)) for _ in range(3)]
    queries.append(models[0] + rng.normal(scale=0.01, size=models[0].shape))
    return DistanceSpec(lo, hi, mode, open_end), models, queries


def _full(models, query, spec):
    return np.array([path_distance_kernel(np.ascontiguousarray(m), np.ascontiguousarray(query),
                                          spec.align_lo, spec.align_hi, spec.mode, spec.open_end)
                     for m in models])


@given(vocab=vocabularies(), chunk=st.integers(1, 5))
def test_decisions_equal_the_full_search(vocab, chunk):
    spec, models, queries = vocab
    bank = ModelBank(models, spec)
    for q in queries:
        full = _full(models, q, spec)
        tight = lower_bounds(q, bank)
        assert np.all(tight <= full)
        assert np.all(envelope_bounds(q, bank) <= tight)
        found = pruned_nearest(q, bank, chunk=chunk)
        assert np.all(found.values <= full)
        assert found.nearest == int(np.argmin(full))
        assert np.array_equal(found.values[found.exact], full[found.exact])
        assert found.values[found.nearest] == full.min()
        assert np.all(found.values[~found.exact] > full.min())
        assert found.cells <= found.full_cells


@given(vocab=vocabularies(), scale=st.floats(0.0, 2.0), chunk=st.integers(1, 5))
def test_decisions_with_rejection_equal_the_full_search(vocab, scale, chunk):
    """1-NN with rejection: accepted iff the nearest model is below its threshold; then the same
    model and distance."""
    spec, models, queries = vocab
    bank = ModelBank(models, spec)
    rng = np.random.default_rng(len(models))
    for q in queries:
        full = _full(models, q, spec)
        tau = scale * np.median(full) * rng.uniform(0.5, 1.5, len(models))
        found = pruned_nearest(q, bank, chunk=chunk, accept_below=tau)
        j_full, j = int(np.argmin(full)), found.nearest
        accepted_full = full[j_full] < tau[j_full]
        assert (found.values[j] < tau[j]) == accepted_full
        if accepted_full:
            assert j == j_full and found.values[j] == full[j_full] and found.exact[j]


def test_classifier_predicts_the_same_with_and_without_pruning(kettle_files, real_dir):
    from framefree import Trajectory

    trajs = [Trajectory.from_csv(f) for f in kettle_files]
    scoop = Trajectory.from_csv(real_dir / "reference_set" / "ip_scooping_motion.csv")
    moved = Trajectory.from_csv(real_dir / "reference_set" / "ip_scooping_motion__tfworldbody.csv")
    models, labels = [trajs[0], trajs[3], scoop], ["pour", "pour_top", "scoop"]
    queries = [*trajs, moved, scoop]
    for make in (NearestNeighborClassifier.recommended, lambda **k: NearestNeighborClassifier("bilts", **k)):
        plain = make().fit(models, labels)
        pruned = make(prune=True).fit(models, labels)
        assert list(pruned.predict(queries)) == list(plain.predict(queries))
        descs = plain._describe(queries)
        for a, b in zip(pruned._nearest(descs), plain._nearest(descs), strict=True):
            assert np.array_equal(a, b)


@pytest.fixture(scope="module")
def replica_recognizer():
    from replica_recognizer import replica_recognizer

    return replica_recognizer()


def _live_events(rec, stream_name: str) -> list:
    """Events of a replica session pushed through ``rec`` from a reset: (label, time,
    dissimilarity)."""
    from framefree.datasets.stream_files import load_stream
    from framefree.replica import replica_path

    stream, _ = load_stream(replica_path(0) / "streams" / stream_name)
    rec.reset()
    events = []
    for k in range(len(stream)):
        events += rec.push(stream.t[k], stream.p[k], stream.q[k])
    return [(e.label, e.time, e.dissimilarity) for e in events]


@pytest.mark.slow
def test_live_events_are_the_same_with_and_without_pruning(replica_recognizer):
    rec = replica_recognizer
    runs = {}
    for prune in (False, True):
        rec.prune = prune
        runs[prune] = (_live_events(rec, "stream_1.csv"), dict(rec.stats))
    assert runs[True][0] == runs[False][0] and len(runs[True][0]) > 5
    assert runs[True][1]["dtw_cells"] <= runs[True][1]["dtw_cells_unpruned"]


@st.composite
def clustered_vocabularies(draw):
    """Many models around a few shapes (as a vocabulary of many people is), thresholds of which
    some are zero (gestures that do not admit the candidate) — where models are deferred."""
    mode = draw(st.sampled_from(sorted(MODES)))
    lo, hi, width = MODES[mode]
    spec = DistanceSpec(lo, hi, mode, draw(st.booleans()))
    rng = np.random.default_rng(draw(st.integers(0, 2**31 - 1)))
    shapes = [rng.normal(size=(int(rng.integers(3, 16)), width)) for _ in range(3)]
    models = [s + rng.normal(scale=rng.uniform(0.0, 0.5), size=s.shape)
              for s in shapes for _ in range(int(rng.integers(1, 7)))]
    k = int(rng.integers(len(shapes)))
    query = shapes[k] + rng.normal(scale=rng.uniform(0.0, 0.5), size=shapes[k].shape)
    if mode != POINTWISE_EUCLIDEAN:
        for seq in (*models, query):
            seq[:, 18:24] = bound_features(seq, spec)
    admits = rng.random(len(models)) < 0.7
    return spec, models, query, admits, draw(st.floats(0.0, 2.0))


@given(vocab=clustered_vocabularies(), chunk=st.integers(1, 9))
def test_deferred_models_keep_rejection_exact(vocab, chunk):
    """While the best model so far cannot be accepted, models that cannot be accepted either are
    put off; if an acceptable one turns up, the put-off ones that may be nearer are searched."""
    spec, models, query, admits, scale = vocab
    full = _full(models, query, spec)
    tau = np.where(admits, scale * np.median(full), 0.0)
    found = pruned_nearest(query, ModelBank(models, spec), chunk=chunk, accept_below=tau)
    j_full, j = int(np.argmin(full)), found.nearest
    accepted_full = full[j_full] < tau[j_full]
    assert (found.values[j] < tau[j]) == accepted_full
    assert np.all(found.values <= full)
    assert np.array_equal(found.values[found.exact], full[found.exact])
    if accepted_full:
        assert j == j_full and found.values[j] == full[j_full]


@pytest.mark.slow
def test_searching_later_candidates_only_for_a_better_one_changes_no_event(replica_recognizer):
    rec = replica_recognizer
    rec.prune = True
    runs = {}
    for tighten in (False, True):
        rec.spotter.tighten = tighten
        # session 1: in session 2 every later candidate that could beat an accepted one has a
        # corner too many for it, so it is not searched either way
        runs[tighten] = (_live_events(rec, "stream_1.csv"), rec.stats["dtw_cells"])
    rec.spotter.tighten = True
    assert runs[True][0] == runs[False][0] and len(runs[True][0]) > 5
    assert runs[True][1] < runs[False][1]
