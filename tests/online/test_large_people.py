"""Large people (v10): how much larger than the demonstrations a gesture may be, from real people.

The upper size limit is the largest demonstration times ``size_growth``; real Vive recordings
(``machete_vive``) say how far other people go beyond one person's takes."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from framefree.benchmark.take_geometry import other_peoples, take_geometry
from framefree.datasets.layout import load_model_recordings
from framefree.online import Recognizer, RecognizerConfig, SpottingConstants
from framefree.online.evaluation import run_stream
from framefree.online.limits import size_limits
from framefree.replica import replica_path
from real_data import MACHETE


@given(smallest=st.floats(0.01, 2.0), spread=st.floats(1.0, 3.0), factor=st.floats(1.0, 3.0),
       growth=st.floats(1.0, 4.0))
def test_size_limits_shrink_and_grow_the_demonstrations_range_separately(smallest, spread, factor,
                                                                         growth):
    largest = smallest * spread
    lo, hi = size_limits(smallest, largest, factor, growth)
    assert lo == pytest.approx(smallest / factor)
    assert hi == pytest.approx(largest * growth)
    assert lo <= smallest <= largest <= hi
    assert size_limits(smallest, largest, factor) == size_limits(smallest, largest, factor, factor)


def test_size_growth_must_be_positive():
    with pytest.raises(ValueError, match="size_growth"):
        RecognizerConfig().replace(size_growth=0.0)


@pytest.fixture(scope="module")
def models():
    return load_model_recordings(replica_path(0), "original_1")


def test_the_upper_size_limit_is_the_largest_demonstration_times_the_growth(models):
    grown = Recognizer.from_trajectories(*models)
    plain = Recognizer.from_trajectories(*models, size_growth=1.5).learned_
    growth = grown.config.constants.size_growth
    for g, (lo, hi) in grown.learned_.size_limits.items():
        assert lo == pytest.approx(plain.size_limits[g][0])
        assert hi == pytest.approx(plain.size_limits[g][1] * growth / 1.5)


def test_a_circle_drawn_much_larger_than_the_demonstrations_is_still_taken(models):
    """A *go right* left out of the models and drawn 1.6 times larger is taken with the default
    growth, and refused as too large with the growth of v9 (1.5)."""
    trajs, labels = models
    k = list(labels).index("go_right")
    rest = [t for i, t in enumerate(trajs) if i != k], [g for i, g in enumerate(labels) if i != k]
    large = trajs[k].path_scaled(1.6)
    taken = [e.label for e in run_stream(Recognizer.from_trajectories(*rest), large)[0]]
    refused = [e.label for e in
               run_stream(Recognizer.from_trajectories(*rest, size_growth=1.5), large)[0]]
    assert taken == ["go_right"]
    assert refused == []


def _real_sizes() -> dict:
    """{(controller, person, gesture): [size [m] of each take]} of the real Vive recordings."""
    return {key: [size for _, size, _, _ in takes] for key, takes in take_geometry(MACHETE).items()}


def _larger(sizes: dict, growth: float) -> float:
    over = checked = 0
    for key, own in sizes.items():
        others = other_peoples(sizes, key)
        checked += len(others)
        over += sum(s > max(own) * growth for s in others)
    assert checked > 0
    return over / checked


def test_real_people_stay_below_an_upper_size_limit_from_another_persons_takes():
    """Real Vive recordings: at most 2 % of another person's performances exceed one person's
    largest take times the default growth; more than 5 % exceed it by a quarter."""
    sizes = _real_sizes()
    assert _larger(sizes, SpottingConstants().size_growth) <= 0.02
    assert _larger(sizes, 1.25) > 0.05
