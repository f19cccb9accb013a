"""NearestNeighborClassifier as a scikit-learn estimator, on the replica (seed 7)."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.base import clone, is_classifier
from sklearn.exceptions import NotFittedError
from sklearn.model_selection import GridSearchCV, StratifiedKFold, cross_val_score
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import FunctionTransformer
from sklearn.utils.validation import check_is_fitted

from framefree import NearestNeighborClassifier, get_descriptor
from framefree.classifier import RECOMMENDED


@pytest.fixture(scope="module")
def xy(replica):
    """70 trials: the 7 gestures in original_1 and original_2 (5 trials each)."""
    trials = replica.select(context=("original_1", "original_2"))
    return [t.trajectory for t in trials], np.array([t.gesture for t in trials])


def test_parameters_are_stored_as_given_and_round_trip():
    clf = NearestNeighborClassifier("bilts+", L=1, ds_scale=0.1)
    assert clf.L == 1 and type(clf.L) is int  # not converted, not validated, until fit
    params = clf.get_params()
    assert params["descriptor"] == "bilts+" and params["ds_scale"] == 0.1
    assert params["progress"] is None and params["round_digits"] is None
    assert clf.set_params(L=0.3, progress="angle") is clf
    assert (clf.L, clf.progress) == (0.3, "angle")
    with pytest.raises(ValueError, match="invalid parameter 'window'"):
        clf.set_params(window=3)
    assert repr(clf) == "NearestNeighborClassifier(progress='angle', L=0.3, ds_scale=0.1)"
    assert is_classifier(clf)


def test_the_bare_classifier_is_the_recommended_one_and_the_paper_is_one_option_away():
    bare = NearestNeighborClassifier().build_descriptor()
    assert bare.params == NearestNeighborClassifier.recommended().build_descriptor().params
    assert NearestNeighborClassifier("bilts+").build_descriptor().params == bare.params
    paper = NearestNeighborClassifier(preset="paper").build_descriptor()
    assert paper.params == get_descriptor("bilts+").params != bare.params
    assert NearestNeighborClassifier.paper().get_params()["preset"] == "paper"
    assert (paper.L, paper.ds_scale, paper.open_end) == (0.5, 0.09, False)
    # another descriptor keeps its own defaults; an unknown preset is refused at fit
    assert (NearestNeighborClassifier("dhb").build_descriptor().params
            == get_descriptor("dhb").params)
    with pytest.raises(ValueError, match="unknown preset 'best'"):
        NearestNeighborClassifier(preset="best").build_descriptor()


def test_fit_builds_the_descriptor_from_the_parameters(xy):
    X, y = xy
    clf = NearestNeighborClassifier("bilts+", L=0.4, ds_scale=0.07).fit(X[:14], y[:14])
    # the parameters left unset come from the recommended settings (the default preset)
    expected = {**RECOMMENDED, "L": 0.4, "ds_scale": 0.07}
    assert clf.descriptor_.params == get_descriptor(expected.pop("descriptor"), **expected).params
    assert list(clf.classes_) == sorted(set(y[:14]))
    paper = NearestNeighborClassifier.paper(L=0.4, ds_scale=0.07).fit(X[:14], y[:14])
    assert paper.descriptor_.params == get_descriptor("bilts+", L=0.4, ds_scale=0.07).params
    # a descriptor instance plus an override: the instance is not modified
    desc = get_descriptor("bilts+", L=0.5)
    clf2 = NearestNeighborClassifier(desc, L=0.3).fit(X[:14], y[:14])
    assert desc.L == 0.5 and clf2.descriptor_.L == 0.3 and clf2.descriptor is desc


def test_clone_gives_an_unfitted_copy_with_equal_parameters(xy):
    X, y = xy
    clf = NearestNeighborClassifier("bilts+", L=0.5, ds_scale=0.09).fit(X, y)
    copy = clone(clf)
    assert copy.get_params() == clf.get_params()
    assert not hasattr(copy, "models_") and not hasattr(copy, "descriptor_")
    with pytest.raises(NotFittedError, match="fit"):
        copy.predict(X[:1])
    check_is_fitted(clf)
    with pytest.raises(NotFittedError):
        check_is_fitted(copy)


def test_cross_val_score_on_the_replica(xy):
    X, y = xy
    cv = StratifiedKFold(5, shuffle=True, random_state=0)
    scores = cross_val_score(NearestNeighborClassifier("bilts+"), X, y, cv=cv)
    assert scores.shape == (5,)
    # 14 test trials per fold, 7 classes: far above chance (1/7) on every fold
    assert scores.min() >= 0.5, scores


def test_grid_search_over_L_and_ds_scale(xy):
    X, y = xy
    grid = {"L": [0.3, 0.5], "ds_scale": [0.05, 0.09]}
    search = GridSearchCV(
        NearestNeighborClassifier("bilts+"), grid, cv=StratifiedKFold(3, shuffle=True, random_state=0)
    )
    search.fit(X, y)
    assert len(search.cv_results_["params"]) == 4
    assert search.best_params_ in search.cv_results_["params"]
    best = search.best_estimator_
    assert (best.L, best.ds_scale) == (search.best_params_["L"], search.best_params_["ds_scale"])
    assert best.descriptor_.L == best.L
    assert search.score(X, y) == best.score(X, y)


def test_pipeline_with_a_trajectory_transformer(xy):
    X, y = xy

    def slow_down(trajs):
        return [t.time_scaled(2.0) for t in trajs]

    pipe = Pipeline([("slower", FunctionTransformer(slow_down)), ("nn", NearestNeighborClassifier())])
    pipe.fit(X[::2], y[::2])
    bare = NearestNeighborClassifier().fit(slow_down(X[::2]), y[::2])
    np.testing.assert_array_equal(pipe.predict(X[1::2]), bare.predict(slow_down(X[1::2])))
    # screw progress ignores speed: the slowed-down motions are still recognized
    assert pipe.score(X[1::2], y[1::2]) >= 0.6
    assert pipe.get_params()["nn__L"] is None
    pipe.set_params(nn__L=0.3)
    assert pipe.named_steps["nn"].L == 0.3


def test_arrays_are_trajectories_and_predicting_changes_nothing(xy):
    X, y = xy
    arrays = [t.to_array() for t in X]
    clf = NearestNeighborClassifier.recommended().fit(arrays, y)
    same = NearestNeighborClassifier.recommended().fit(X, y)
    assert list(clf.predict(arrays[:5])) == list(same.predict(X[:5]))
    before = dict(vars(clf))
    clf.predict(arrays[:3])
    assert vars(clf).keys() == before.keys()
    with pytest.raises(TypeError, match=r"sample 0: an array of shape \(5, 7\)"):
        clf.predict([np.zeros((5, 7))])
    with pytest.raises(TypeError, match="samples must be"):
        clf.predict("trial_1.csv")


def test_kneighbors_decision_function_and_predict_proba(xy):
    X, y = xy
    clf = NearestNeighborClassifier.recommended().fit(X[5:], y[5:])
    dist, ind = clf.kneighbors(X[:5], n_neighbors=3)
    D = clf.distance_matrix(X[:5])
    assert np.array_equal(dist, np.sort(D, axis=1)[:, :3])
    assert np.array_equal(clf.labels_[ind[:, 0]], clf.predict(X[:5]))
    scores = clf.decision_function(X[:5])
    assert scores.shape == (5, len(clf.classes_))
    assert np.array_equal(clf.classes_[np.argmax(scores, axis=1)], clf.predict(X[:5]))
    proba = clf.predict_proba(X[:5])
    assert np.allclose(proba.sum(axis=1), 1.0)
    assert np.array_equal(clf.classes_[np.argmax(proba, axis=1)], clf.predict(X[:5]))


def test_rejection_says_no_gesture_for_motion_that_is_none(xy, real_dir):
    from framefree import Trajectory

    X, y = xy
    held_out = np.arange(len(X)) % 4 == 0
    Xm = [x for x, h in zip(X, held_out, strict=True) if not h]
    clf = NearestNeighborClassifier.recommended(thresholds="auto").fit(Xm, y[~held_out])
    assert set(clf.thresholds_) == set(clf.classes_)
    pour = Trajectory.from_csv(real_dir / "kettle_pour_trial1_ref_com.csv")
    assert clf.predict([pour])[0] == "no_gesture"
    queries = [x for x, h in zip(X, held_out, strict=True) if h]
    assert (clf.predict(queries) == y[held_out]).mean() >= 0.8


def test_auto_thresholds_keep_genuine_gestures_and_reject_everyday_motion(replica, real_dir):
    """``thresholds="auto"`` with the default settings, models = original_1: at most 2 % of the
    held-out trials of seven other contexts (moved world frames, other speeds, another person)
    are rejected, and most recorded everyday motions (pouring, scooping, free motion) are."""
    from framefree import Trajectory

    models = replica.select(context="original_1")
    clf = NearestNeighborClassifier(thresholds="auto").fit(
        [t.trajectory for t in models], [t.gesture for t in models])
    held = replica.select(context=("original_2", "slower", "faster", "world_frame_1",
                                   "world_frame_2", "world_frame_3", "other_person"))
    predicted = clf.predict([t.trajectory for t in held])
    assert np.mean(predicted == "no_gesture") <= 0.02
    assert np.mean(predicted == np.array([t.gesture for t in held])) >= 0.95
    everyday = [*sorted(real_dir.glob("kettle_pour_*.csv")),
                *(real_dir / "reference_set" / f"ip_{n}_motion.csv"
                  for n in ("pouring", "recorded", "scooping"))]
    said = clf.predict([Trajectory.from_csv(f) for f in everyday])
    assert np.mean(said == "no_gesture") >= 0.75, dict(zip([f.name for f in everyday], said, strict=True))
