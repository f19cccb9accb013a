"""Simulated people: the population's ranges, seeds, and that a person's style shows in the motion;
the two extra shapes (figure eight, push with a twist) have the geometry they claim."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.datasets import GESTURES
from framefree.replica import (
    DEFAULT_PERSON,
    DEV_PEOPLE,
    EXTRA_SHAPES,
    HELDOUT_PEOPLE,
    Person,
    draw_person,
    person,
    plan_gesture,
    synthesize_gesture,
)
from framefree.replica.gestures import GESTURE_SHAPES
from framefree.replica.people import person_grip
from framefree.replica.population import ANTHROPOMETRY, VARIATION

PEOPLE = [person(s) for s in range(200)]


def _values(name: str) -> np.ndarray:
    return np.array([getattr(p, name) for p in PEOPLE], dtype=np.float64)


def test_population_ranges() -> None:
    size, tempo = _values("size"), _values("tempo")
    assert size.min() >= 0.7 and size.max() <= 1.3 and np.ptp(size) > 0.5
    assert tempo.min() >= 0.6 and tempo.max() <= 1.6 and np.ptp(tempo) > 0.8
    skew = _values("skew")
    assert np.abs(skew).max() <= 0.4 + 1e-12 and skew.std() > 2 * VARIATION["skew"]
    assert (skew < -0.2).any() and (skew > 0.2).any()  # both directions
    pauses = np.array([p.pause for p in PEOPLE])
    assert pauses[:, 0].min() < 0.03 and 0.6 < pauses[:, 1].max() <= 0.8
    rests = np.array([p.rest for p in PEOPLE])
    assert rests[:, 0].min() < 0.12 and rests[:, 1].max() > 1.2
    assert np.all(pauses[:, 0] <= pauses[:, 1]) and np.all(rests[:, 0] <= rests[:, 1])
    tremor = _values("tremor")
    assert tremor.min() >= 0.4 - 1e-12 and tremor.max() <= 2.5 + 1e-12 and np.ptp(tremor) > 1.0
    elbow = _values("elbow_to_palm")
    assert 0.27 < elbow.min() and elbow.max() < 0.42 and elbow.std() > 0.01
    stature = _values("stature")
    assert 1.45 <= stature.min() and stature.max() <= 2.05
    assert np.corrcoef(stature, elbow)[0, 1] > 0.7  # limbs scale with body height
    rotation = np.degrees(_values("forearm_rotation"))
    assert 135 <= rotation.min() and rotation.max() <= 180
    assert np.degrees(np.abs(_values("heading"))).max() <= 30 + 1e-9
    assert {p.grip for p in PEOPLE} == {"random", "habitual"}
    var = _values("variability")
    assert var.min() >= 0.6 and var.max() <= 1.6


def test_seeds_are_deterministic_and_people_differ() -> None:
    assert person(3) == person(3)
    assert person(3) != person(4)
    assert person(3).seed == 3 and DEFAULT_PERSON.seed is None
    a = draw_person(np.random.default_rng(9))
    assert a == draw_person(np.random.default_rng(9))
    assert len({dataclasses.astuple(p) for p in PEOPLE}) == len(PEOPLE)


def test_dev_and_heldout_people_are_disjoint() -> None:
    dev, held = set(DEV_PEOPLE), set(HELDOUT_PEOPLE)
    assert len(dev) >= 10 and len(held) >= 10
    assert not dev & held
    assert {person(s) for s in dev}.isdisjoint({person(s) for s in held})


def test_nominal_person_is_the_replica() -> None:
    assert Person.nominal() == DEFAULT_PERSON and DEFAULT_PERSON.is_nominal
    assert DEFAULT_PERSON.elbow_to_palm == ANTHROPOMETRY["elbow_to_palm"][0]
    assert DEFAULT_PERSON.pause == VARIATION["pause"] and DEFAULT_PERSON.rest == VARIATION["rest"]
    assert not person(0).is_nominal


def test_invalid_person() -> None:
    with pytest.raises(ValueError, match="tempo"):
        Person(tempo=0.0)
    with pytest.raises(ValueError, match="grip"):
        Person(grip="sideways")
    with pytest.raises(ValueError, match="pause"):
        Person(pause=(0.5, 0.1))
    with pytest.raises(ValueError, match="non-negative"):
        person(-1)


def _movement_time(gesture: str, who: Person, n: int = 8) -> float:
    return float(np.mean([plan_gesture(gesture, np.random.default_rng(k), person=who).duration
                          for k in range(n)]))


def test_tempo_sets_movement_time() -> None:
    quick = dataclasses.replace(DEFAULT_PERSON, tempo=1.6, pause=(0.1, 0.1))
    slow = dataclasses.replace(DEFAULT_PERSON, tempo=0.6, pause=(0.1, 0.1))
    for g in ("go_left", "go_right", "open_gripper"):
        ratio = _movement_time(g, slow) / _movement_time(g, quick)
        assert 2.2 < ratio < 3.0  # 1.6 / 0.6 on the strokes, the pause unchanged


def test_size_sets_extent() -> None:
    def extent(who: Person) -> float:
        plan = plan_gesture("go_left", np.random.default_rng(1), person=who)
        return float(np.linalg.norm(plan.strokes[0].end[:3, 3] - plan.start[:3, 3]))

    big = extent(dataclasses.replace(DEFAULT_PERSON, size=1.3))
    small = extent(dataclasses.replace(DEFAULT_PERSON, size=0.7))
    assert big / small == pytest.approx(1.3 / 0.7, rel=0.02)


def _peak_time(who: Person) -> float:
    """Mean normalized time of the speed peak of the first stroke of go_left."""
    tau = np.linspace(0.0, 1.0, 401)
    peaks = []
    for k in range(10):
        first = plan_gesture("go_left", np.random.default_rng(k), person=who).strokes[0]
        p = first.fn(tau * first.duration)[:, :3, 3]
        peaks.append(tau[np.argmax(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    return float(np.mean(peaks))


def test_skew_moves_the_speed_peak_both_ways() -> None:
    early = _peak_time(dataclasses.replace(DEFAULT_PERSON, skew=-0.4))
    late = _peak_time(dataclasses.replace(DEFAULT_PERSON, skew=0.4))
    assert early < 0.42 < 0.5 < 0.58 < late


def test_pause_at_the_reversal_follows_the_person() -> None:
    for lo, hi in ((0.02, 0.03), (0.7, 0.8)):
        who = dataclasses.replace(DEFAULT_PERSON, pause=(lo, hi))
        plan = plan_gesture("go_up", np.random.default_rng(2), person=who)
        assert lo <= plan.strokes[1].duration <= hi


def test_habitual_grip_is_consistent() -> None:
    habit = dataclasses.replace(DEFAULT_PERSON, grip="habitual", grip_rotation=(0.3, -1.0, 0.4))
    rng = np.random.default_rng(0)
    grips = [person_grip(habit, rng) for _ in range(10)]
    ang = [np.linalg.norm(se3.vector_from_rotation(grips[0][:3, :3].T @ g[:3, :3])) for g in grips]
    assert np.degrees(max(ang)) < 60
    for g in grips:
        assert 0.005 < np.linalg.norm(g[:3, 3]) < 0.09
    randoms = [person_grip(DEFAULT_PERSON, rng) for _ in range(10)]
    ang = [np.linalg.norm(se3.vector_from_rotation(randoms[0][:3, :3].T @ g[:3, :3])) for g in randoms]
    assert np.degrees(max(ang)) > 90


@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 10_000), gesture=st.sampled_from([*GESTURES, *EXTRA_SHAPES]))
def test_any_person_makes_valid_trials(seed: int, gesture: str) -> None:
    traj = synthesize_gesture(gesture, np.random.default_rng(seed), person=person(seed))
    assert np.all(np.isfinite(traj.p)) and np.all(np.diff(traj.t) > 0)
    assert np.allclose(np.linalg.norm(traj.q, axis=1), 1.0)
    assert 1.0 < traj.duration < 12.0
    step = np.linalg.norm(np.diff(traj.p, axis=0), axis=1)
    assert step.max() < 0.08  # < 4 m/s between 50 Hz samples: human hand speeds


def test_extra_shapes_are_not_hpm_gestures() -> None:
    assert set(EXTRA_SHAPES) == {"figure_eight", "push_twist"}
    assert not set(EXTRA_SHAPES) & set(GESTURES) and list(GESTURE_SHAPES) == list(GESTURES)


def _segments_cross(xy: np.ndarray) -> bool:
    """True if the polyline ``xy`` (n, 2) crosses itself (non-adjacent segments intersect)."""
    a, b = xy[:-1], xy[1:]
    n = len(a)

    def orient(p, q, r):
        return np.sign((q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1])
                       - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0]))

    for i in range(n):
        j = np.arange(i + 2, n)
        if j.size == 0:
            continue
        d1, d2 = orient(a[i], b[i], a[j]), orient(a[i], b[i], b[j])
        d3, d4 = orient(a[j], b[j], a[i]), orient(a[j], b[j], b[i])
        if np.any((d1 * d2 < 0) & (d3 * d4 < 0)):
            return True
    return False


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_figure_eight_crosses_itself_and_returns(seed: int) -> None:
    plan = plan_gesture("figure_eight", np.random.default_rng(seed), person=person(seed))
    (loop,) = plan.strokes
    T = loop.fn(np.linspace(0.0, loop.duration, 400))
    p = T[:, :3, 3] - plan.start[:3, 3]
    width = np.ptp(p, axis=0).max()
    assert 0.15 < width < 0.5
    assert np.linalg.norm(p[-1]) < 0.25 * width  # back near the start
    centred = p - p.mean(axis=0)
    _, sv, Vt = np.linalg.svd(centred)
    assert sv[2] < 0.25 * sv[1]  # planar
    assert abs(Vt[2] @ plan.start[:3, :3] @ [0.0, 0.0, 1.0]) < 0.9  # plane is not horizontal
    xy = centred @ Vt[:2].T
    # a figure eight: self-crossing, with the two lobes on opposite sides of the crossing
    assert _segments_cross(xy[::4])
    ang = np.degrees(np.linalg.norm(se3.vector_from_rotation(
        plan.start[:3, :3].T @ T[:, :3, :3]), axis=1)).max()
    assert ang < 40  # nearly pure translation


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_push_twist_advances_while_turning_about_90_degrees(seed: int) -> None:
    plan = plan_gesture("push_twist", np.random.default_rng(seed))
    out = plan.strokes[0]
    T0, T1 = plan.start, out.end
    xi = se3.twist_from_pose(se3.transform_inverse(T0) @ T1)
    angle = float(np.linalg.norm(xi[:3]))
    assert 70 < np.degrees(angle) < 110
    advance = float(xi[:3] @ xi[3:]) / angle  # translation along the screw axis [m]
    assert 0.15 < advance < 0.3
    axis_world = T0[:3, :3] @ xi[:3] / angle
    assert abs(axis_world[2]) < 0.4  # about a horizontal (forearm) axis
    assert np.linalg.norm(plan.end[:3, 3] - T0[:3, 3]) < 0.06  # and back
    assert len(plan.strokes) == 3


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_every_person_is_within_the_documented_population(seed: int) -> None:
    p = person(seed)
    assert 0.7 <= p.size <= 1.3 and 0.6 <= p.tempo <= 1.6 and abs(p.skew) <= 0.4
    assert 0.0 < p.pause[0] <= p.pause[1] <= 0.8 and 0.0 < p.rest[0] <= p.rest[1] <= 1.7
    assert 0.4 - 1e-9 <= p.tremor <= 2.5 + 1e-9 and 0.6 <= p.variability <= 1.6
    assert 1.45 <= p.stature <= 2.05 and 0.24 < p.elbow_to_palm < 0.46
    assert 0.015 <= p.pronation_axis_offset <= 0.05
    assert np.radians(135) <= p.forearm_rotation <= np.radians(180)
    assert np.radians(35) <= p.elbow_flexion <= np.radians(65)
    assert 0.015 <= p.grip_offset[0] < p.grip_offset[1] <= 0.065
    assert 1.0 <= p.walk_speed <= 1.5
    assert max(abs(x) for x in p.hand_tilt) <= np.radians(25) + 1e-12
