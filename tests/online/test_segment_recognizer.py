"""framefree's live recognizer (segment spotting) end to end: offline-identical classification,
held-out people, real non-gesture motion, faults, reproducible configuration."""

from __future__ import annotations

import json

import numpy as np
import pytest

from framefree import Trajectory
from framefree.datasets.layout import load_model_recordings
from framefree.descriptors import get_descriptor
from framefree.online import LearnedSettings, Recognizer, RecognizerConfig, model_settings, spotting
from framefree.online.evaluation import match_events, run_stream
from framefree.online.events import STOP
from framefree.online.limits import pooled_closures
from framefree.online.model_settings import model_window_spacing
from framefree.online.span_shape import closure
from framefree.replica import replica_path
from framefree.replica.faults import FAULT_KINDS, inject
from framefree.replica.people import HELDOUT_PEOPLE, person
from framefree.replica.people_streams import person_stream
from real_data import REAL_MOTIONS

REAL = REAL_MOTIONS


@pytest.fixture(scope="module")
def models() -> tuple[list[Trajectory], list[str]]:
    return load_model_recordings(replica_path(0), "original_1")


@pytest.fixture(scope="module")
def recognizer(models) -> Recognizer:
    rec = Recognizer.from_trajectories(*models)
    rec.warmup()
    return rec


@pytest.fixture(scope="module")
def heldout_stream():
    """A session of a held-out simulated person (never used to choose any parameter)."""
    return person_stream(7, person(HELDOUT_PEOPLE[3]), n_gestures=14, n_stops=2)


def _events_f1(rec: Recognizer, item) -> tuple[list, float]:
    events, _ = run_stream(rec, item.traj)
    return events, match_events(events, item.segments, item.traj.duration).f1


def test_a_segment_is_classified_live_as_offline(recognizer, models, heldout_stream, monkeypatch):
    seen: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    live = spotting.SegmentClassifier.distances

    def record(self, times, poses):
        d, size = live(self, times, poses)
        seen.append((times.copy(), poses.copy(), d))
        return d, size

    monkeypatch.setattr(spotting.SegmentClassifier, "distances", record)
    run_stream(recognizer, heldout_stream.traj)
    assert len(seen) > 10
    c = recognizer.config.descriptor
    offline = get_descriptor("bilts+", progress="screw", L=c.L, ds_scale=c.ds_scale,
                             n_samples=c.n_samples, presmooth=c.presmooth, axis_prior=c.axis_prior,
                             spacing=recognizer.learned_.window_spacing, align=c.align)
    model_desc = [offline.compute(tr) for tr in models[0]]
    for times, poses, d in seen[::5]:
        query = Trajectory.from_poses(times - times[0], poses)
        expected = offline.distance_matrix([offline.compute(query)], model_desc)[0]
        np.testing.assert_allclose(d, expected, rtol=1e-12)
        assert recognizer.labels[int(np.argmin(d))] == models[1][int(np.argmin(expected))]


def test_a_heldout_person_is_recognized(recognizer, heldout_stream):
    events, f1 = _events_f1(recognizer, heldout_stream)
    assert f1 >= 0.85
    assert any(e.label == STOP for e in events)


def test_real_non_gesture_motion_gives_no_event(recognizer):
    """Real pouring, scooping and free motion fires nothing. The folder's synthetic motions
    (``syn_*``, kept for "nothing crashes" tests) only have to run through: one of them is a
    circle, the shape of *go right*."""
    files = sorted(REAL.glob("**/*.csv"))
    if not files:
        pytest.skip("real recordings not available")
    for f in files:
        recognizer.reset()
        events = recognizer.run(Trajectory.from_csv(f))
        if not f.name.startswith("syn_"):
            assert events == [], f.name


@pytest.mark.parametrize("kind", FAULT_KINDS)
def test_each_fault_kind_costs_little(recognizer, heldout_stream, kind):
    _, clean = _events_f1(recognizer, heldout_stream)
    tr = heldout_stream.traj
    t, p, q = inject(kind, tr.t, tr.p, tr.q, np.random.default_rng(5))
    recognizer.reset()
    events = []
    for k in range(t.size):
        events.extend(recognizer.push(t[k], p[k], q[k]))
    faulty = match_events(events, heldout_stream.segments, tr.duration).f1
    assert faulty >= clean - 0.08, (kind, clean, faulty)
    assert recognizer.stats["samples"] == t.size


def test_settings_and_learned_values_rebuild_without_calibration(recognizer, models,
                                                                 heldout_stream, monkeypatch):
    restored = RecognizerConfig.from_dict(recognizer.config.to_dict())
    assert restored == recognizer.config
    learned = LearnedSettings.from_dict(json.loads(json.dumps(recognizer.learned_.to_dict())))
    assert learned == recognizer.learned_

    def fail(*args, **kwargs):
        raise AssertionError("calibration must not run")

    monkeypatch.setattr(model_settings, "calibrate_segment_thresholds", fail)
    rebuilt = Recognizer.from_trajectories(*models, restored, learned)
    assert rebuilt.learned_ == recognizer.learned_
    a, _ = run_stream(recognizer, heldout_stream.traj)
    b, _ = run_stream(rebuilt, heldout_stream.traj)
    assert a == b


def test_memory_stays_bounded(recognizer, heldout_stream):
    rec = recognizer
    rec.reset()
    shapes = rec.segmenter.buffer._poses.shape
    rec.run(heldout_stream.traj)
    assert rec.segmenter.buffer._poses.shape == shapes
    assert len(rec.spotter.units) <= rec.spotter.units.maxlen
    assert rec.segmenter.units.maxlen is not None


def test_unlearned_values_are_refused(recognizer):
    with pytest.raises(ValueError, match="unlearned"):
        Recognizer(recognizer.classifier, recognizer.labels, RecognizerConfig(), LearnedSettings())


def test_configuration_is_validated():
    with pytest.raises(ValueError, match="L must be positive"):
        RecognizerConfig().replace(L=-1.0)
    with pytest.raises(ValueError, match="unknown"):
        RecognizerConfig.from_dict({"nonsense": 1})
    with pytest.raises(ValueError, match=r"unknown recognizer settings \['rest_speed'\]"):
        RecognizerConfig().replace(rest_speed=0.1)  # learned: given to from_trajectories


def test_a_user_sets_few_things_and_every_name_still_reaches_its_place(models):
    """The user's settings are few; a descriptor setting or constant is changed by name, and a
    learned value given by name is kept, with "given" as its rule."""
    assert len(RecognizerConfig.user_names()) <= 20
    c = RecognizerConfig().replace(ds_scale=0.09, size_factor=2.0, confirm=0.3)
    assert (c.descriptor.ds_scale, c.constants.size_factor, c.confirm) == (0.09, 2.0, 0.3)
    assert RecognizerConfig.from_dict(c.flat()) == c == RecognizerConfig.from_dict(c.to_dict())
    rec = Recognizer.from_trajectories(*models, max_units=3, gesture_thresholds=None, threshold=0.2)
    rules = rec.learned_.provenance.rules
    assert rec.learned_.max_units == 3 and rules["max_units"] == "given"
    assert rules["gesture_thresholds"] == "given: threshold"
    assert rules["rest_speed"] == "framefree.online.rest_levels.speed_levels"
    assert rec.learned_.provenance.takes == len(models[0])
    described = rec.describe()
    assert "rest_speed" not in described["config"] and described["learned"]["max_units"] == 3


def test_thresholds_come_from_the_models_and_their_rivals(recognizer, models):
    """τ_g lies between the worst leave-one-out demonstration P_g and N_g, and N_g is never
    larger than the distance from g's recordings to the nearest recording of another gesture."""
    cal = recognizer.calibration
    labels = np.array(models[1])
    between = recognizer.classifier.descriptor.distance_matrix(recognizer.classifier.models,
                                                             recognizer.classifier.models)
    for g, tau in cal.thresholds.items():
        P, N = max(cal.positives[g]), cal.negatives[g]
        rival = between[np.ix_(labels == g, labels != g)].min()
        assert N <= rival
        k = recognizer.config.constants
        a = k.threshold_position if cal.separated[g] else k.unseparated_position
        assert tau == pytest.approx(P ** (1 - a) * N**a) if np.isfinite(N) else tau == 2 * P
        assert min(P, N) <= tau <= max(P, N)


def test_the_window_spacing_is_the_models_and_fixed(recognizer, models):
    c, spacing = recognizer.config.descriptor, recognizer.learned_.window_spacing
    assert c.relative_window and spacing == model_window_spacing(models[0], recognizer.config)
    desc = recognizer.classifier.descriptor
    assert desc.spacing == spacing and desc.axis_prior == c.axis_prior == 1.0
    # a gesture performed half as large keeps its number of descriptor samples (the windows cover
    # the same fraction of it); the reference's window spacing would change with the size
    traj = models[0][models[1].index("go_left")]
    small = traj.path_scaled(0.5)
    assert desc.compute(small).shape == desc.compute(traj).shape
    ref = get_descriptor("bilts+", L=c.L, ds_scale=c.ds_scale, presmooth=c.presmooth)
    assert ref.compute(small).shape != ref.compute(traj).shape


def test_pooled_closure_limits_share_the_returning_gestures_largest_closure(recognizer, models):
    """With ``closure_pooled`` every returning gesture gets the limit of the least precisely
    returning one; a one-way gesture keeps its own; nothing is recalibrated but the limits."""
    assert pooled_closures({"a": 0.02, "b": 0.06, "swipe": 0.9}) == {"a": 0.06, "b": 0.06, "swipe": 0.9}
    assert pooled_closures({"swipe": 0.9}) == {"swipe": 0.9}
    own = recognizer.learned_.closure_limits
    c = recognizer.config.replace(closure_pooled=True)
    pooled = Recognizer.from_trajectories(*models, config=c).learned_.closure_limits
    assert set(pooled.values()) == {max(own.values())}


def test_a_candidates_closure_is_measured_on_the_whole_candidate(recognizer, heldout_stream,
                                                                  monkeypatch):
    """Live, the margin after a unit is not in the buffer yet when the unit ends: the closure must
    still span the candidate from its first to its last pose, as the models' closures do."""
    checked: list[tuple[float, float]] = []
    live = spotting.Spotter.candidates

    def record(self, buffer):
        out = live(self, buffer)
        for c in out:
            _, poses = buffer.slice(c.start, c.end)
            checked.append((c.closure, closure(poses, self.L)))
        return out

    monkeypatch.setattr(spotting.Spotter, "candidates", record)
    run_stream(recognizer, heldout_stream.traj)
    assert len(checked) > 20
    np.testing.assert_allclose(*np.array(checked).T, rtol=0, atol=1e-12)


def test_a_hesitant_person_keeps_the_gestures_whole(recognizer):
    """A person who nearly stops in mid-stroke: the stroke falls into pieces, and the whole
    gesture is still one candidate (the gestures are the models' out-and-back seven)."""
    from dataclasses import replace

    from framefree.replica import make_stream

    who = replace(person(HELDOUT_PEOPLE[3]), hesitation=1.0, hesitation_pause=(0.25, 0.4))
    traj, segments = make_stream(11, person=who, n_gestures=10, n_stops=0)
    events, _ = run_stream(recognizer, traj)
    assert recognizer.learned_.max_units == 5  # two units per model gesture, each may be cut once
    assert match_events(events, segments, traj.duration).f1 >= 0.9


def test_pause_rule_of_two_units_is_the_mean_of_the_two_strokes():
    """The reversal pause of two units is judged against the mean of the two (as always); with
    pieces of hesitant strokes, against the candidate's span without the rest, over two strokes."""
    from framefree.online.segmentation import Unit

    def unit(a: float, b: float) -> Unit:
        return Unit(int(a * 50), int(b * 50), a, b, 1.0, True)

    two = [unit(0.0, 1.0), unit(1.5, 2.5)]  # strokes of 1 s, rest 0.5 s
    spans = spotting.candidate_spans(two, 5, 10.0, 5.0, pause_ratio=0.6, min_pause=0.0)
    assert [n for _, n in spans] == [1, 2]
    assert [n for _, n in spotting.candidate_spans(two, 5, 10.0, 5.0, pause_ratio=0.4)] == [1]
    # the same gesture with each stroke cut in two by a 0.1 s near-stop
    pieces = [unit(0.0, 0.45), unit(0.55, 1.0), unit(1.5, 1.95), unit(2.05, 2.5)]
    spans = spotting.candidate_spans(pieces, 5, 10.0, 5.0, pause_ratio=0.6, min_pause=0.0)
    assert max(n for _, n in spans) == 4


def test_open_and_returning_limits(recognizer):
    """A candidate must not close more than an open stroke's demonstrations (opening limit) and may
    pass the closure limit by ending within a person's return error of its start."""
    from framefree.online.limits import opening_limit

    assert opening_limit(0.3, 0.65) == pytest.approx(0.3 ** (1 / 0.65))
    assert opening_limit(0.01, 0.65) < 0.001
    sp = recognizer.spotter
    j = 0
    lo, hi = sp.size_limits[j]
    size = np.array([(lo + hi) / 2] * 3)
    limit = sp.closure_limits[j]
    closures = np.array([limit * 0.5, limit * 1.5, sp.return_error / size[0] * 0.9])
    ok = sp.admissible(j, closures, size)
    assert ok[0] and ok[2]
    assert ok[1] == (limit * 1.5 * size[0] <= sp.return_error)
    n = len(sp.model_thresholds)
    sp_open = spotting.Spotter(sp.classifier, sp.model_thresholds, closure_limits=np.ones(n),
                               opening_limits=np.full(n, 0.2))
    assert list(sp_open.admissible(j, np.array([0.05, 0.5]), np.ones(2))) == [False, True]
