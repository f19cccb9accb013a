import numpy as np
import pytest

from framefree.core.kabsch import residual_columns
from framefree.online.paper.matchers import (
    MatcherBank,
    brute_force_dissimilarity,
    latency_bounds,
    residual18,
)


def test_residual18_equals_kabsch():
    rng = np.random.default_rng(0)
    for k in range(500):
        a = rng.normal(size=18)
        b = a + rng.normal(scale=10.0 ** rng.uniform(-4, 1), size=18) if k % 2 else rng.normal(size=18)
        ref = residual_columns(a, b, 6)
        got = residual18(a, a @ a, b, b @ b)
        assert got == pytest.approx(ref, rel=1e-9, abs=1e-10 * (a @ a + b @ b))


def test_latency_bounds():
    assert latency_bounds(50) == (1, 10)
    assert latency_bounds(50, latency_min=0) == (0, 10)
    assert latency_bounds(12) == (1, 2)  # round(2.4)
    assert latency_bounds(13) == (1, 3)  # round(2.6)
    assert latency_bounds(5) == (1, 1)  # round(1.0)
    assert latency_bounds(2) == (1, 1)


@pytest.mark.parametrize("latency_min", [0, 1])
@pytest.mark.parametrize("parallel", [False, True])
def test_incremental_equals_brute_force(latency_min, parallel):
    rng = np.random.default_rng(3)
    models = [rng.normal(size=(int(rng.integers(4, 30)), 18)) for _ in range(7)]
    bank = MatcherBank(models, latency_min=latency_min, parallel_models=1 if parallel else 10**9)
    live = rng.normal(size=(70, 18))
    # a planted copy of model 2 (slightly perturbed) inside the live stream
    live[30 : 30 + len(models[2])] = models[2] + 1e-3 * rng.normal(size=models[2].shape)
    for t in range(live.shape[0]):
        if t == 50:
            bank.reset()
            start = 50
        else:
            start = 50 if t > 50 else 0
        d = bank.update(live[t])
        for j, m in enumerate(models):
            ref = brute_force_dissimilarity(m, live[start : t + 1], latency_min)
            if np.isinf(ref):
                assert np.isinf(d[j])
            else:
                assert d[j] == pytest.approx(ref, rel=1e-9, abs=1e-12)
    assert bank.count == 20


def test_planted_model_is_found():
    rng = np.random.default_rng(4)
    models = [rng.normal(size=(20, 18)) for _ in range(5)]
    bank = MatcherBank(models)
    live = np.concatenate([rng.normal(size=(15, 18)), models[3], rng.normal(size=(5, 18))])
    best = []
    for t, b in enumerate(live):
        d = bank.update(b)
        best.append((t, int(np.argmin(d)), float(np.min(d))))
    t, j, v = min(best, key=lambda x: x[2])
    assert j == 3 and v < 1e-12
    assert 15 + 20 - 4 - 1 <= t <= 15 + 20 - 1  # found within the latency window, before the end


def test_bank_rejects_bad_models():
    with pytest.raises(ValueError):
        MatcherBank([])
    with pytest.raises(ValueError):
        MatcherBank([np.zeros((1, 18))])
    with pytest.raises(ValueError):
        MatcherBank([np.zeros((5, 12))])


@pytest.mark.parametrize("parallel", [False, True])
def test_pruning_is_exact_below_cutoff(parallel):
    """With cutoffs, every d_j below its cutoff is the exact value; above it reads >= cutoff."""
    rng = np.random.default_rng(5)
    models = [rng.normal(size=(int(rng.integers(6, 30)), 18)) for _ in range(9)]
    live = rng.normal(size=(120, 18))
    for j in (1, 4):
        s = 10 + 50 * (j == 4)
        live[s : s + len(models[j])] = models[j] + 0.05 * rng.normal(size=models[j].shape)
    exact = MatcherBank(models, parallel_models=1 if parallel else 10**9)
    ref = np.array([exact.update(b).copy() for b in live])
    cut = np.quantile(ref[np.isfinite(ref)], 0.1) * np.linspace(0.5, 2.0, len(models))
    pruned = MatcherBank(models, parallel_models=1 if parallel else 10**9, cutoffs=cut)
    got = np.array([pruned.update(b).copy() for b in live])
    below = ref < cut[None]
    assert below.sum() > 5
    np.testing.assert_allclose(got[below], ref[below], rtol=1e-12)
    assert np.all(~(got < cut[None]) | below)  # nothing spuriously below the cutoff
    assert np.all(got[~below] >= cut[None].repeat(len(live), 0)[~below])
