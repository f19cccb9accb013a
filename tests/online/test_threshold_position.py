"""Where τ_g lies between a gesture's worst take ``P_g`` and its negatives ``N_g``.

With a gap between them (``P_g < N_g``) τ_g leans towards the negatives
(``threshold_position`` 0.7): other people's performances lie farther from the models than one
person's takes lie from each other. Without one (``P_g ≥ N_g``: the takes are spread wider than
the nearest negatives, as many people's examples of one gesture are) there is no gap to lean
into and τ_g is their geometric midpoint (``unseparated_position`` 0.5). On the real Machete
people this finds 4 more gestures of 165 with no false positive more (docs/online-history.md,
v23).
"""

from __future__ import annotations

import numpy as np
import pytest
from drawing import circle_positions, drawn_positions, tracker_poses

from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer, thresholds
from framefree.online.constants import SpottingConstants
from framefree.online.segmentation import SpeedLevels

DT = 0.02
ZIGZAG = np.array([[0, 0, 0], [0.24, 0, 0], [0, -0.18, 0], [0.24, -0.18, 0]], float)


def _trajectory(positions: np.ndarray) -> Trajectory:
    return Trajectory.from_poses(DT * np.arange(positions.shape[0]),
                                 tracker_poses(positions, np.eye(4)))


@pytest.fixture(scope="module")
def vocabulary():
    rng = np.random.default_rng(5)
    zigzags = [_trajectory(drawn_positions(ZIGZAG + rng.uniform(-0.02, 0.02, ZIGZAG.shape) * [1, 1, 0],
                                           stroke_s=rng.uniform(0.5, 0.7)))
               for _ in range(5)]
    circles = [_trajectory(circle_positions(radius=r, duration=d))
               for r, d in ((0.11, 1.8), (0.12, 2.0), (0.13, 2.2), (0.12, 1.9), (0.115, 2.1))]
    takes, labels = zigzags + circles, ["zigzag"] * 5 + ["circle"] * 5
    return Recognizer.from_trajectories(takes, labels, threshold=0.2), takes, labels


def _calibrate(vocabulary, **kwargs) -> thresholds.SegmentThresholds:
    rec, takes, labels = vocabulary
    levels = SpeedLevels(rec.learned_.rest_speed, rec.learned_.move_speed)
    return thresholds.calibrate_segment_thresholds(takes, labels, rec.classifier, levels,
                                                   rec.spotter, rec.config.descriptor.L,
                                                   drawn=False, **kwargs)


def test_a_gesture_without_a_gap_gets_the_geometric_midpoint(vocabulary, monkeypatch):
    real = thresholds.take_scores

    def spread(*args, **kwargs):  # the zigzag's takes as far apart as many people's
        scores = real(*args, **kwargs)
        scores["zigzag"] = [100.0 * s for s in scores["zigzag"]]
        return scores

    monkeypatch.setattr(thresholds, "take_scores", spread)
    cal = _calibrate(vocabulary, position=0.7, unseparated_position=0.5)
    assert not cal.separated["zigzag"] and cal.separated["circle"]
    for g, a in (("zigzag", 0.5), ("circle", 0.7)):
        P, N = max(cal.positives[g]), cal.negatives[g]
        assert cal.thresholds[g] == pytest.approx(P ** (1 - a) * N**a)
        assert min(P, N) < cal.thresholds[g] < max(P, N)
    same = _calibrate(vocabulary, position=0.7)  # None: one position for both
    P, N = max(same.positives["zigzag"]), same.negatives["zigzag"]
    assert same.thresholds["zigzag"] == pytest.approx(P**0.3 * N**0.7)
    assert same.thresholds["circle"] == cal.thresholds["circle"]


@pytest.mark.parametrize("value", [-0.1, 1.5])
def test_the_positions_are_fractions(value):
    for name in ("threshold_position", "unseparated_position"):
        with pytest.raises(ValueError, match=name):
            SpottingConstants(**{name: value})


@pytest.mark.parametrize("q", [0.0, 0.5, 1.0])
def test_the_rival_bound_is_a_quantile_of_the_other_takes_nearest_distances(vocabulary, q):
    """Each take of another gesture is scored by its nearest take of ``g``; ``N_g`` is at most
    the ``rival_quantile`` of those scores (0: the nearest pair, as before)."""
    rec, _, labels = vocabulary
    labels = np.asarray(labels)
    generic = _calibrate(vocabulary, rivals=False).negatives
    cal = _calibrate(vocabulary, rival_quantile=q)
    between = rec.classifier.descriptor.distance_matrix(rec.classifier.models, rec.classifier.models)
    for g in ("zigzag", "circle"):
        nearest_of_g = between[np.ix_(labels == g, labels != g)].min(axis=0)
        assert nearest_of_g.shape == (5,)
        assert cal.negatives[g] == pytest.approx(min(generic[g], np.quantile(nearest_of_g, q)))
        if q == 0.0:  # the nearest pair of whole takes, as before the setting existed
            assert cal.negatives[g] == pytest.approx(min(generic[g], nearest_of_g.min()))


@pytest.mark.parametrize("value", [-0.01, 1.01])
def test_the_rival_quantile_is_a_fraction(value):
    with pytest.raises(ValueError, match="rival_quantile"):
        SpottingConstants(rival_quantile=value)


def test_the_summary_reports_the_worst_finite_take_that_sets_P():
    """A take none of whose candidates is admitted scores infinity and takes no part in ``P_g``;
    the summary (kept in a library file, quoted by ``framefree check``) reports the ``P_g`` the
    threshold used, and ``None`` for a gesture with no finite score, never infinity."""
    result = thresholds.SegmentThresholds(
        {"a": 0.2, "b": 0.3}, {"a": [0.1, np.inf, 0.15], "b": [np.inf, np.inf]},
        {"a": 0.4, "b": 0.5})
    assert result.summary()["positives_max"] == {"a": 0.15, "b": None}
    assert thresholds.worst_take([0.1, np.inf, 0.15]) == 0.15
