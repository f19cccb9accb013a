"""The acceptance gate's plausible speeds come from the takes (v35).

A whole-arm stroke sampled at a skeleton tracker's 30 Hz moves farther between two samples than
a hand-held tracker's limits allow (5 m/s, 30 rad/s), and the gate took such strokes for
glitches and relocations, restarting the stream. The tests check the rule (three times the
takes' fastest, at least the hand-held limits; a sensor of positions only keeps the angular
floor, and one tracker keeps it), that real Vive takes read faster than a hand-held tracker,
that a real fast person's strokes at 30 Hz pass a gate learned from other people where the
hand-held limits cut them, that a recognizer taught fast strokes keeps a 30 Hz stream of them
whole, and that a library saved before learns the value from its takes.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.acceptance import GATE_FACTOR, HAND_HELD_SPEEDS, SampleGate, gate_limits
from framefree.online.learned import LearnedSettings
from framefree.online.noisy_orientation import constant_orientation
from real_data import SHIPPED_FAST_MACHETE, SHIPPED_MACHETE

RATE = 30.0


def _swing(peak: float, bend: float, rng: np.random.Generator, rest: float = 0.6) -> Trajectory:
    """A fast arc at ``RATE`` Hz: 1.2 m (± 5 %) travelled with a minimum-jerk profile whose
    peak speed is about ``peak`` [m/s], its heading turning by ``bend`` [rad], the tracker
    turning by a quarter turn and back with it; ``rest`` seconds still before and after."""
    length = 1.2 * rng.uniform(0.95, 1.05)
    duration = 1.875 * length / peak  # a minimum-jerk stroke peaks at 1.875 × its mean speed
    n_rest, n_move = round(rest * RATE), round(duration * RATE)
    s = np.linspace(0.0, 1.0, n_move)
    s = 10 * s**3 - 15 * s**4 + 6 * s**5
    s = np.concatenate([np.zeros(n_rest), s, np.ones(n_rest)])
    radius = length / bend
    p = np.c_[radius * np.sin(bend * s), radius * (1 - np.cos(bend * s)), 0.1 * s]
    half = 0.125 * np.pi * np.sin(np.pi * s)  # an eighth of a turn out and back
    q = np.c_[np.cos(half), np.zeros_like(s), np.zeros_like(s), np.sin(half)]
    return Trajectory(np.arange(s.size) / RATE, p + 0.0005 * rng.standard_normal(p.shape), q)


def _joined(parts: list[Trajectory]) -> Trajectory:
    """The takes one after the other, as one stream."""
    t0, ts, ps, qs = 0.0, [], [], []
    for part in parts:
        ts.append(part.t - part.t[0] + t0)
        ps.append(part.p - part.p[0] + (ps[-1][-1] if ps else 0.0))
        qs.append(part.q)
        t0 = ts[-1][-1] + 1.0 / RATE
    return Trajectory(np.concatenate(ts), np.concatenate(ps), np.concatenate(qs))


@pytest.fixture(scope="module")
def swings():
    """Six fast wide swings and six fast tight ones (peaks of about 9 m/s), and a stream of two of
    each sampled at 30 Hz."""
    rng = np.random.default_rng(3)
    takes = [_swing(9.0, bend, rng) for bend in (0.8, 2.4) for _ in range(6)]
    labels = ["wide"] * 6 + ["tight"] * 6
    stream = _joined([_swing(9.0, bend, rng) for bend in (0.8, 2.4, 2.4, 0.8)])
    return takes, labels, stream


def test_slow_takes_keep_the_hand_held_limits():
    rng = np.random.default_rng(0)
    assert gate_limits([_swing(1.0, 1.0, rng) for _ in range(3)]) == HAND_HELD_SPEEDS


def test_fast_takes_raise_the_limits_to_three_times_their_fastest(swings):
    takes, _, _ = swings
    speed, turn = gate_limits(takes)
    fastest = max(np.percentile(np.linalg.norm(np.diff(tr.p, axis=0), axis=1) * RATE, 99)
                  for tr in takes)
    assert speed == pytest.approx(GATE_FACTOR * fastest)
    assert speed > 3 * HAND_HELD_SPEEDS[0]
    assert turn > HAND_HELD_SPEEDS[1]  # a quarter turn and back in a quarter of a second
    assert gate_limits([constant_orientation(tr) for tr in takes])[1] == HAND_HELD_SPEEDS[1]
    assert gate_limits(takes, turns=False) == (speed, HAND_HELD_SPEEDS[1])


def test_real_vive_takes_move_faster_than_a_hand_held_tracker():
    """The Machete controllers in hooks, uppercuts and golf swings (the shipped people)."""
    from framefree.datasets.people_layout import load_people

    takes = [r.sample.trackers[0] for r in load_people(SHIPPED_MACHETE)]
    speed, turn = gate_limits(takes)
    assert speed > 3 * HAND_HELD_SPEEDS[0] and turn > HAND_HELD_SPEEDS[1]


def _gate_events(traj: Trajectory, speeds: tuple[float, float]) -> int:
    """Samples a gate with ``speeds`` drops as glitches, and relocations, over ``traj``."""
    gate = SampleGate(nominal_period=0.02, max_speed=speeds[0], max_angular_speed=speeds[1])
    for t, p, q in zip(traj.t, traj.p, traj.q, strict=True):
        gate.push(float(t), p, q)
    return gate.stats["outliers"] + gate.stats["relocations"]


def test_a_real_fast_person_at_30_hz_passes_a_gate_learned_from_other_people():
    """Sub_U005's golf swing and uppercut at a skeleton tracker's 30 Hz: the hand-held limits
    take their strokes for glitches and a relocation; the limits learned from two other people's
    takes (the shipped Vive people, also at 30 Hz) let them through."""
    from framefree.datasets.people_layout import load_people

    others = [r.sample.trackers[0].resampled(1 / RATE) for r in load_people(SHIPPED_MACHETE)]
    learned = gate_limits(others, turns=False)
    for r in load_people(SHIPPED_FAST_MACHETE):
        take = r.sample.trackers[0].resampled(1 / RATE)
        assert _gate_events(take, HAND_HELD_SPEEDS) > 0, r.gesture
        assert _gate_events(take, learned) == 0, r.gesture


def test_a_stream_of_fast_strokes_at_30_hz_is_kept_whole(swings):
    takes, labels, stream = swings
    learned = Recognizer.from_trajectories(takes, labels)
    hand_held = Recognizer.from_trajectories(takes, labels, gate_speeds=HAND_HELD_SPEEDS)
    assert learned.learned_.gate_speeds == gate_limits(takes, turns=False)
    assert learned.learned_.gate_speeds[1] == HAND_HELD_SPEEDS[1]  # catches a palm flip
    counts = {}
    for name, rec in (("learned", learned), ("hand-held", hand_held)):
        rec.background = False
        for t, p, q in zip(stream.t, stream.p, stream.q, strict=True):
            rec.push(float(t), p, q)
        rec.finish()
        counts[name] = rec.stats["outliers"] + rec.stats["restarts"]
    assert counts["learned"] == 0
    assert counts["hand-held"] > 0  # the hand-held limits take the strokes for glitches


def test_a_library_saved_before_learns_the_limits_from_its_takes(swings):
    takes, labels, _ = swings
    rec = Recognizer.from_trajectories(takes, labels)
    old = rec.learned_.replace(gate_speeds=None)
    restored = Recognizer.from_trajectories(takes, labels, rec.config, old)
    assert restored.learned_.gate_speeds == rec.learned_.gate_speeds
    assert restored.gate.max_speed == rec.learned_.gate_speeds[0]
    again = LearnedSettings.from_dict(json.loads(json.dumps(rec.learned_.to_dict())))
    assert again.gate_speeds == rec.learned_.gate_speeds


def test_several_trackers_learn_both_limits_and_keep_them_with_the_rest():
    """The recognizer of several trackers learns the speed and the angular speed from every
    tracker's takes, keeps them among its learned values, and takes given ones."""
    from framefree.datasets.people_layout import load_people
    from framefree.online.multi import MultiRecognizer

    people = load_people(SHIPPED_MACHETE)
    samples, labels = [r.sample for r in people], [r.gesture for r in people]
    rec = MultiRecognizer.from_samples(samples, labels)
    expected = gate_limits([tr for s in samples for tr in s.trackers])
    assert rec.learned_.gate_speeds == rec.gate_speeds == expected
    assert expected[1] > HAND_HELD_SPEEDS[1]  # the controllers turn faster than a hand-held tracker
    given = MultiRecognizer.from_samples(samples, labels, learned=rec.learned_.replace(
        gate_speeds=HAND_HELD_SPEEDS))
    assert given.gate_speeds == HAND_HELD_SPEEDS
    assert given.gates[0].max_speed == HAND_HELD_SPEEDS[0]
