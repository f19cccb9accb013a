"""Open-end DTW (the query may stop anywhere in the model) and the recommended classifier."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import framefree as ff
from framefree.classifier import RECOMMENDED
from framefree.core.dtw import (
    POINTWISE_EUCLIDEAN,
    POINTWISE_KABSCH,
    accumulated_cost,
    open_end_row,
    path_distance_kernel,
)


def test_open_end_row_by_hand() -> None:
    # model (0, 1, 2, 3), query (0, 1): C[:, -1] = (1, 0, 1, 3); divided by (i + 2): the prefix
    # ending at model sample 1 (cost 0) wins; the full model would cost 3/5.
    X = np.array([[0.0], [1.0], [2.0], [3.0]])
    Y = np.array([[0.0], [1.0]])
    C = accumulated_cost(X, Y)
    np.testing.assert_array_equal(C[:, -1], [1.0, 0.0, 1.0, 3.0])
    assert open_end_row(C) == 1
    assert path_distance_kernel(X, Y, 0, 1, POINTWISE_EUCLIDEAN, True) == 0.0
    assert path_distance_kernel(X, Y, 0, 1, POINTWISE_EUCLIDEAN, False) == pytest.approx(3 / 5)


def test_normalization_neither_favours_nor_punishes_length() -> None:
    """Average cost per step: the same constant local cost gives the same distance whatever the
    prefix length, so neither a short nor a long prefix wins by its length alone."""
    X = np.zeros((30, 1))
    for m in (3, 10, 30):
        Y = np.ones((m, 1))
        C = accumulated_cost(X, Y)
        per_step = C[:, -1] / (np.arange(30) + m)
        # every prefix end at or beyond the query length costs exactly 1 per step ... hence the
        # tie rule keeps the first (shortest) of them, and the value is the per-step cost
        assert path_distance_kernel(X, Y, 0, 1, POINTWISE_EUCLIDEAN, True) <= 1.0
        assert per_step.min() == pytest.approx(path_distance_kernel(X, Y, 0, 1, 0, True))


@settings(max_examples=25, deadline=None)
@given(n=st.integers(8, 40), frac=st.floats(0.2, 1.0), seed=st.integers(0, 1000))
def test_a_prefix_of_the_model_matches_it_exactly(n: int, frac: float, seed: int) -> None:
    rng = np.random.default_rng(seed)
    X = np.cumsum(rng.normal(size=(n, 24)), axis=0)
    m = max(2, int(frac * n))
    Y = X[:m].copy()
    for mode, lo in ((POINTWISE_EUCLIDEAN, 0), (POINTWISE_KABSCH, 18)):
        d = path_distance_kernel(X, Y, lo, 24, mode, True)
        assert d == pytest.approx(0.0, abs=1e-9)
    # the closed-end distance charges the model's unvisited remainder
    if m < n - 1:
        assert path_distance_kernel(X, Y, 0, 24, POINTWISE_EUCLIDEAN, False) > 1e-3


def test_open_end_equals_closed_end_for_the_whole_model(kettle_files) -> None:
    desc = ff.get_descriptor("bilts+", open_end=True)
    closed = ff.get_descriptor("bilts+")
    a = desc.compute(ff.Trajectory.from_csv(kettle_files[0]))
    assert desc.distance(a, a) == pytest.approx(0.0, abs=1e-12)
    b = desc.compute(ff.Trajectory.from_csv(kettle_files[1]))
    assert desc.distance(a, b) <= closed.distance(a, b) + 1e-12


def test_recommended_classifier_recognizes_unfinished_motions(real_dir) -> None:
    names = ["ip_pouring_motion", "ip_scooping_motion", "seg_Trial1_coffee_kettle_ref_CoM"]
    models = [ff.Trajectory.from_csv(real_dir / "reference_set" / f"{n}.csv") for n in names]
    clf = ff.NearestNeighborClassifier.recommended().fit(models, names)
    assert clf.descriptor_.name == RECOMMENDED["descriptor"]
    assert clf.descriptor_.params == {
        **clf.descriptor_.params,
        **{k: v for k, v in RECOMMENDED.items() if k != "descriptor"},
    }
    moved = [
        ff.Trajectory.from_csv(real_dir / "reference_set" / f"{n}__tfworldbody.csv") for n in names
    ]
    assert list(clf.predict(moved)) == names
    assert list(clf.predict([m.head(0.6) for m in moved])) == names
    with pytest.raises(ValueError):  # BILTS+ has no arclength progress
        ff.NearestNeighborClassifier.recommended(progress="arclength").fit(models, names)
