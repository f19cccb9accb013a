"""Which way the path turns, for a sensor of positions only (v32): a tracker that never turns
has the turn of its path as the motion's turn, so a gesture and its mirror image, which no
frame-free distance tells apart, run round opposite axes of the sensor's frame.

The tests check the measure (unchanged by the world frame, turned by the tracker's place in the
hand, reversed by a mirror, none for a straight stroke), that ``hand_turn`` gives it only where
the orientation never changes, the real Vive cartwheels without their orientation, and a
recognizer that tells a circle drawn one way from the other only through it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.core import se3
from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.hand_direction import (
    FIXED_FRAME_FACTOR,
    MIN_TURN,
    OFF_CONE_FACTOR,
    cone_factor,
    farther,
    fixed_frame,
    hand_turn,
    path_turn,
)
from framefree.online.noisy_orientation import constant_orientation
from real_data import MACHETE

DT = 0.02
frames = st.builds(lambda xi: se3.pose_from_twist(np.asarray(xi)),
                   st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6))


def _circle(sense: float = 1.0, n: int = 80, radius: float = 0.15, degrees: float = 360.0
            ) -> np.ndarray:
    """Poses (n, 4, 4) of a tracker that keeps its orientation while its position runs round a
    circle in the xy plane, anticlockwise about +z for ``sense`` 1, clockwise for −1."""
    s = np.linspace(0.0, 1.0, n)
    a = sense * math.radians(degrees) * (10 * s**3 - 15 * s**4 + 6 * s**5)
    P = np.repeat(np.eye(4)[None], n, axis=0)
    P[:, 0, 3] = radius * np.cos(a)
    P[:, 1, 3] = radius * np.sin(a)
    return P


def _stroke(degrees: float, n: int = 60) -> np.ndarray:
    """Poses of a 30 cm arc whose heading turns ``degrees`` in the xy plane, orientation fixed."""
    heading = np.radians(np.linspace(0.0, degrees, n - 1))
    steps = 0.3 / (n - 1) * np.c_[np.cos(heading), np.sin(heading), np.zeros(n - 1)]
    P = np.repeat(np.eye(4)[None], n, axis=0)
    P[1:, :3, 3] = np.cumsum(steps, axis=0)
    return P


def test_a_circle_runs_round_the_axis_of_its_sense():
    assert path_turn(_circle(1.0)) == pytest.approx([0, 0, 1], abs=1e-9)
    assert path_turn(_circle(-1.0)) == pytest.approx([0, 0, -1], abs=1e-9)
    # half a circle, an arc of a swing: the same axis
    assert path_turn(_circle(1.0, degrees=180.0)) == pytest.approx([0, 0, 1], abs=1e-9)


def test_a_mirror_image_runs_round_the_opposite_axis():
    P = _circle(1.0, radius=0.1)
    P[:, 2, 3] = 0.05 * np.sin(np.linspace(0, 2 * np.pi, P.shape[0]))  # not quite planar
    mirrored = P.copy()
    mirrored[:, 0, 3] *= -1.0
    axis, image = path_turn(P), path_turn(mirrored)
    assert axis @ np.array([0, 0, 1.0]) > 0.9
    assert image @ np.array([0, 0, 1.0]) < -0.9


@settings(max_examples=10, deadline=None)
@given(X=frames, scale=st.floats(0.2, 5.0))
def test_the_path_turn_does_not_depend_on_the_world_frame_or_the_size(X, scale):
    P = _circle(1.0)
    Q = P.copy()
    Q[:, :3, 3] *= scale
    assert path_turn(X @ Q) == pytest.approx(path_turn(P), abs=1e-9)


@settings(max_examples=10, deadline=None)
@given(G=frames)
def test_a_tracker_turned_in_the_hand_turns_the_path_axis(G):
    P = _circle(1.0)
    P[:, 2, 3] = 0.1 * np.linspace(0.0, 1.0, P.shape[0])  # a helix, not in the tracker's plane
    assert path_turn(P @ G) == pytest.approx(G[:3, :3].T @ path_turn(P), abs=1e-9)


def test_the_pace_does_not_change_the_axis():
    slow, fast = _circle(1.0, n=200), _circle(1.0, n=40)
    assert path_turn(slow) == pytest.approx(path_turn(fast), abs=1e-9)


def test_no_axis_for_a_straight_stroke():
    assert path_turn(_stroke(0.0)) is None
    assert path_turn(_stroke(0.9 * MIN_TURN)) is None
    assert path_turn(_stroke(1.5 * MIN_TURN)) == pytest.approx([0, 0, 1], abs=1e-9)
    assert path_turn(_stroke(90.0)[:2]) is None
    assert path_turn(np.repeat(np.eye(4)[None], 10, axis=0)) is None  # no motion


def test_hand_turn_takes_the_path_only_where_the_tracker_never_turns():
    P = _circle(-1.0)
    assert hand_turn(P) == pytest.approx([0, 0, -1], abs=1e-9)
    # any one orientation held throughout is a sensor of positions only
    R = se3.rotation_from_vector(np.array([0.3, -1.0, 0.4]))
    held = P.copy()
    held[:, :3, :3] = R
    assert hand_turn(held) == pytest.approx(R.T @ np.array([0, 0, -1.0]), abs=1e-9)
    # a tracker that turns a little (a hand-held one, a tenth of a degree) is no such sensor:
    # it turns less than MIN_TURN, so it has no axis, as before
    wobbling = P.copy()
    for k, a in enumerate(np.radians(0.1) * np.sin(np.linspace(0, 6, P.shape[0]))):
        wobbling[k, :3, :3] = se3.rotation_from_vector(np.array([a, 0.0, 0.0]))
    assert hand_turn(wobbling) is None


def test_real_cartwheels_without_orientation_run_round_opposite_axes():
    """The right controller's cartwheels of the real Vive people (all six next to the checkout,
    the two shipped ones otherwise), every quaternion the identity: each *cartwheel left* runs
    round the opposite axis of the *cartwheel right*s (measured: every dot product with their
    mean axis below −0.93 and above 0.92 on all 60 takes)."""
    from framefree.datasets.people_layout import load_people

    axes: dict[str, list[np.ndarray]] = {}
    for r in load_people(MACHETE):
        if r.gesture in ("cartwheel_left", "cartwheel_right"):
            axis = hand_turn(constant_orientation(r.sample.trackers[0]).poses())
            axes.setdefault(r.gesture, []).append(axis)
    right = np.array(axes["cartwheel_right"])
    mean = right.sum(axis=0) / np.linalg.norm(right.sum(axis=0))
    assert (right @ mean).min() > 0.8
    assert (np.array(axes["cartwheel_left"]) @ mean).max() < -0.8


def _circle_take(sense: float, rng: np.random.Generator) -> Trajectory:
    """A circle drawn with a position-only sensor: rests before and after, a little spread in
    size, pace and the circle's plane, sensor noise; the world frame is the sensor's."""
    n = int(rng.integers(70, 90))
    P = _circle(sense, n=n, radius=rng.uniform(0.12, 0.18))
    tilt = se3.rotation_from_vector(0.15 * rng.standard_normal(3))
    P[:, :3, 3] = P[:, :3, 3] @ tilt.T + rng.uniform(-0.5, 0.5, 3)
    P[:, :3, :3] = np.eye(3)
    rest = 25
    P = np.concatenate([np.repeat(P[:1], rest, axis=0), P, np.repeat(P[-1:], rest, axis=0)])
    P[:, :3, 3] += 0.0005 * rng.standard_normal((P.shape[0], 3))
    return Trajectory.from_poses(DT * np.arange(P.shape[0]), P)


@pytest.fixture(scope="module")
def mirror_pair():
    """Twelve takes each of a circle drawn anticlockwise and clockwise (about the sensor's z),
    enrolled with the cones (the default) and without; and a stream of one of each.

    The threshold is given: the calibration's rival bound puts a mirror pair's thresholds near
    zero (each gesture's takes lie as near the other's as their own), which the cones, evidence
    and not a gate, do not lift."""
    rng = np.random.default_rng(7)
    takes = [_circle_take(s, rng) for s in (1.0, -1.0) for _ in range(12)]
    labels = ["anticlockwise"] * 12 + ["clockwise"] * 12
    recs = [Recognizer.from_trajectories(takes, labels, cone_takes=12, hand_frame=flag,
                                         threshold=0.01)
            for flag in (True, False)]
    return recs, _stream([_circle_take(-1.0, rng), _circle_take(1.0, rng)])


def _stream(parts: list[Trajectory]) -> Trajectory:
    """The takes ``parts`` one after the other, as one stream of a sensor of positions only."""
    t0 = 0.0
    stream_t, stream_p = [], []
    for part in parts:
        stream_t.append(part.t + t0)
        stream_p.append(part.p)
        t0 = stream_t[-1][-1] + DT
    t, p = np.concatenate(stream_t), np.concatenate(stream_p)
    return Trajectory(t, p, np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1)))


def test_the_recognizer_learns_opposite_cones_for_a_mirror_pair(mirror_pair):
    (rec, without), _ = mirror_pair
    cones = rec.learned_.rotation_limits
    assert np.array(cones["anticlockwise"][:3]) @ [0, 0, 1] > 0.9
    assert np.array(cones["clockwise"][:3]) @ [0, 0, 1] < -0.9
    assert without.learned_.rotation_limits is None


def test_a_circle_is_told_from_its_mirror_image_by_the_way_it_turns(mirror_pair):
    (rec, without), stream = mirror_pair

    def labels(r: Recognizer) -> list[str]:
        r.reset()
        return [e.label for k in range(len(stream))
                for e in r.push(stream.t[k], stream.p[k], stream.q[k])]

    assert labels(rec) == ["clockwise", "anticlockwise"]
    # the descriptor alone took the clockwise circle for the anticlockwise one
    assert labels(without) != ["clockwise", "anticlockwise"]


def test_takes_of_positions_only_are_in_a_fixed_frame(mirror_pair):
    """No take of a sensor of positions only turns its tracker; a hand-held tracker's do."""
    rng = np.random.default_rng(3)
    still = [_circle_take(1.0, rng) for _ in range(3)]
    assert fixed_frame(still)
    q = still[0].q.copy()
    q[-1] = [math.cos(0.01), math.sin(0.01), 0.0, 0.0]  # one sample turned by 1.1°
    assert not fixed_frame([*still, Trajectory(still[0].t, still[0].p, q)])
    (rec, without), _ = mirror_pair
    assert rec.learned_.fixed_frame is True
    assert without.learned_.fixed_frame is None  # no cones, nothing to weigh


def test_a_zero_distance_outside_a_fixed_frame_cone_is_refused():
    assert list(farther(np.array([0.0, 0.2, 0.3]), np.array([math.inf, 1.0, 1.5]))) == [
        math.inf, 0.2, pytest.approx(0.45)]
    assert cone_factor(True) == FIXED_FRAME_FACTOR == math.inf
    assert cone_factor(False) == cone_factor(None) == OFF_CONE_FACTOR


def test_in_a_fixed_frame_a_mirror_pair_calibrates_its_own_thresholds():
    """With the sensor's frame fixed, the calibration no longer bounds each circle's threshold by
    its mirror image, which moves outside its cone: learned without a threshold given, the pair
    finds both circles of the stream; weighed 1.5 times farther (v32) the thresholds stay near
    zero and it finds neither."""
    rng = np.random.default_rng(7)
    takes = [_circle_take(s, rng) for s in (1.0, -1.0) for _ in range(12)]
    labels = ["anticlockwise"] * 12 + ["clockwise"] * 12
    fixed = Recognizer.from_trajectories(takes, labels, cone_takes=12)
    weighed_only = Recognizer.from_trajectories(takes, labels, cone_takes=12, fixed_frame=False)
    assert min(fixed.learned_.gesture_thresholds.values()) > 3 * max(
        weighed_only.learned_.gesture_thresholds.values())
    stream = _stream([_circle_take(-1.0, rng), _circle_take(1.0, rng)])

    def labels_of(r: Recognizer) -> list[str]:
        return [e.label for k in range(len(stream))
                for e in r.push(stream.t[k], stream.p[k], stream.q[k])]

    assert labels_of(fixed) == ["clockwise", "anticlockwise"]
    assert labels_of(weighed_only) == []


def test_real_takes_turn_their_tracker_unless_their_orientation_is_removed():
    """The real Vive right controller's takes all turn it (a hand-held tracker: the factor of
    v27 stays), and the same takes with every quaternion the identity lie in a fixed frame."""
    from framefree.datasets.people_layout import load_people

    takes = [r.sample.trackers[0] for r in load_people(MACHETE)][:40]
    assert not any(fixed_frame([take]) for take in takes)
    assert fixed_frame([constant_orientation(take) for take in takes])


def test_a_library_saved_before_keeps_the_factor_it_was_calibrated_with():
    """Learned values without ``fixed_frame`` (a library saved before v33) are restored with
    the factor of v32, whose thresholds they hold; saved now, the value goes to JSON and back."""
    import json

    from framefree.online.learned import LearnedSettings

    rng = np.random.default_rng(7)
    takes = [_circle_take(s, rng) for s in (1.0, -1.0) for _ in range(12)]
    labels = ["anticlockwise"] * 12 + ["clockwise"] * 12
    rec = Recognizer.from_trajectories(takes, labels, cone_takes=12)
    old = rec.learned_.replace(fixed_frame=None)
    restored = Recognizer.from_trajectories(takes, labels, rec.config, old)
    assert restored.learned_.fixed_frame is False
    assert "saved before" in restored.learned_.provenance.rules["fixed_frame"]
    assert restored.spotter.directions.factor == OFF_CONE_FACTOR
    again = LearnedSettings.from_dict(json.loads(json.dumps(rec.learned_.to_dict())))
    assert again.fixed_frame is True
    assert rec.spotter.rotations.factor == FIXED_FRAME_FACTOR
