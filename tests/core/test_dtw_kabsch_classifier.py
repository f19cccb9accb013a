"""DTW (golden values, reference tie rule), Kabsch residual, 1-NN classifier, real data."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import framefree as ff
from framefree.core import se3
from framefree.core.dtw import accumulated_cost, dtw_distance, warping_path, warping_path_kernel
from framefree.core.kabsch import kabsch_residual, kabsch_rotation, max_rotation_trace

from . import spec_reference as ref


def test_dtw_golden_values_by_hand():
    X = np.array([[0.0], [1.0], [2.0]])
    Y = np.array([[0.0], [2.0]])
    C = accumulated_cost(X, Y)
    np.testing.assert_allclose(C, [[0, 2], [1, 1], [3, 1]])
    assert dtw_distance(X, Y) == 1.0
    # at (2,1) the diagonal (C=1) ties with the model step (C=1): the diagonal wins
    np.testing.assert_array_equal(warping_path(X, Y), [[0, 0], [1, 0], [2, 1]])


def test_dtw_tie_between_pure_steps_prefers_model_step():
    # at (1, 1): diagonal 9 is worse than both pure steps, which tie at 1 -> step the model index
    C = np.array([[9.0, 1.0], [1.0, 0.0]])
    np.testing.assert_array_equal(warping_path_kernel(C), [[0, 0], [0, 1], [1, 1]])
    # a strictly better query step is taken instead
    C = np.array([[9.0, 2.0], [1.0, 0.0]])
    np.testing.assert_array_equal(warping_path_kernel(C), [[0, 0], [1, 0], [1, 1]])


@given(
    arrays(np.float64, (7, 2), elements=st.floats(-2, 2)),
    arrays(np.float64, (5, 2), elements=st.floats(-2, 2)),
)
def test_dtw_matches_literal_transcription(X, Y):
    path, cost = ref.matlab_dtw_path(X, Y)
    np.testing.assert_array_equal(warping_path(X, Y), np.array(path))
    assert np.isclose(dtw_distance(X, Y), cost)


@given(arrays(np.float64, (2, 3, 6), elements=st.floats(-5, 5)))
def test_kabsch_residual_equals_svd_solution(AB):
    A, B = AB
    expected = ref.kabsch_svd_residual(A, B)
    scale = np.sum(A**2) + np.sum(B**2)
    assert abs(kabsch_residual(A, B) - expected) <= 1e-10 * max(scale, 1.0)


def test_kabsch_residual_zero_for_rotated_copy_and_rank_deficient_inputs():
    rng = np.random.default_rng(0)
    A = rng.normal(size=(3, 6))
    R = se3.rotation_from_vector(rng.normal(size=3))
    assert kabsch_residual(A, R @ A) < 1e-12
    np.testing.assert_allclose(kabsch_rotation(A, R @ A), R, atol=1e-10)
    line = np.outer([1.0, 2.0, -1.0], rng.normal(size=6))  # rank 1
    assert abs(kabsch_residual(line, R @ line)) < 1e-10
    assert kabsch_residual(np.zeros((3, 6)), np.zeros((3, 6))) == 0.0
    # reflection: the determinant fix forbids mirroring a planar-in-3D point set
    M = np.diag([3.0, 2.0, -1.0])
    assert np.isclose(max_rotation_trace(M), 4.0)


def _kettles(kettle_files):
    return [ff.Trajectory.from_csv(f) for f in kettle_files]


def test_real_data_frame_changes_stay_closer_than_any_other_recording(kettle_files):
    """Random world and body changes of a real recording stay far closer to it than other recordings."""
    trajs = _kettles(kettle_files)
    desc = ff.get_descriptor("bilts+", L=0.5, ds_scale=0.09)
    D = [desc.compute(t) for t in trajs]
    M = desc.distance_matrix(D, D)
    np.fill_diagonal(M, np.inf)
    rng = np.random.default_rng(42)
    for i, traj in enumerate(trajs):
        Tw = se3.pose_from_twist(np.concatenate([rng.normal(size=3), rng.uniform(-3, 3, 3)]))
        Tb = se3.pose_from_twist(np.concatenate([rng.normal(size=3), rng.uniform(-0.05, 0.05, 3)]))
        moved = desc.compute(traj.transformed(world=Tw, body=Tb))
        assert desc.distance(D[i], moved) < 0.5 * M[i].min()


def test_nearest_neighbor_classifier_end_to_end(kettle_files, real_dir):
    trajs = _kettles(kettle_files)
    scoop = ff.Trajectory.from_csv(real_dir / "reference_set" / "ip_scooping_motion.csv")
    clf = ff.NearestNeighborClassifier("bilts+", L=0.5, ds_scale=0.09)
    clf.fit([trajs[0], scoop], ["pour", "scoop"])
    scoop_moved = ff.Trajectory.from_csv(
        real_dir / "reference_set" / "ip_scooping_motion__tfworldbody.csv"
    )
    queries = [*trajs[1:], scoop_moved]
    labels = ["pour"] * 5 + ["scoop"]
    np.testing.assert_array_equal(clf.predict(queries), labels)
    assert clf.distance_matrix(queries).shape == (6, 2)
    assert clf.score(queries, labels) == 1.0
    _, nearest = clf.kneighbors(queries)
    assert np.array_equal(np.argmin(clf.distance_matrix(queries), axis=1), nearest[:, 0])


def test_classifier_ties_go_to_the_first_model_and_rounding_option(kettle_files):
    traj = ff.Trajectory.from_csv(kettle_files[0])
    clf = ff.NearestNeighborClassifier("bilts+", round_digits=5).fit([traj, traj], ["a", "b"])
    assert clf.predict([traj])[0] == "a"
    assert np.all(clf.models_[0] == ff.classifier.round_significant(clf.models_[0], 5))
    with pytest.raises(ValueError, match="not fitted"):
        ff.NearestNeighborClassifier("bilts").predict([traj])
    with pytest.raises(ValueError, match="labels"):
        ff.NearestNeighborClassifier("bilts").fit([traj], ["a", "b"])
