"""A stroke that settles (v28): real hands seldom rest after a gesture; they slow down and drift
on. A unit whose speed stays below ``valley_ratio`` × its peak for ``settle`` seconds, above the
rest level, ends where the speed fell below, and the segmenter says ``resting`` at that one
pose, so a gesture that ended there fires as after a rest; the drift is the next unit. A
briefer slow stretch that rises into the next stroke (the top of a golf swing) does not
settle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from drawing import DT, LEVELS, min_jerk, swipe_and_circle_takes

from framefree.core.trajectory import Trajectory
from framefree.online import Recognizer
from framefree.online.constants import SpottingConstants
from framefree.online.segmentation import MotionSegmenter, Unit

PEAK = 0.8  # [m/s]


def _positions(speeds: np.ndarray) -> np.ndarray:
    """Positions (n, 3) of a hand moving along x at ``speeds`` [m/s] (n,), one per grid step."""
    P = np.zeros((speeds.size, 3))
    P[:, 0] = np.cumsum(speeds) * DT
    return P


def _bell(duration: float) -> np.ndarray:
    """Speeds of one stroke: ``PEAK`` × sin², ``duration`` [s] long."""
    x = np.arange(round(duration / DT)) / round(duration / DT)
    return PEAK * np.sin(np.pi * x) ** 2


def _stroke_then_drift(drift_s: float, drift: float = 0.25 * PEAK) -> np.ndarray:
    """Rest, a stroke whose speed, once down to ``drift`` [m/s], stays there for ``drift_s``
    seconds, then rises straight into a second stroke as fast as the first (as from the top of
    a golf swing), then rest."""
    bell = _bell(0.8)
    peak = int(np.argmax(bell))
    down = peak + int(np.flatnonzero(bell[peak:] <= drift)[0])
    up = int(np.flatnonzero(bell[:peak] >= drift)[0])
    rest = np.zeros(round(0.5 / DT))
    slow = np.full(round(drift_s / DT), drift)
    return np.concatenate([rest, bell[:down], slow, bell[up:], rest])


def _run(speeds: np.ndarray, settle: float) -> tuple[list[Unit], list[float]]:
    """The units of the motion, and the times at which the segmenter said ``resting`` while a
    unit was in progress (a settle)."""
    P = _positions(speeds)
    poses = np.repeat(np.eye(4)[None], P.shape[0], axis=0)
    poses[:, :3, 3] = P
    seg = MotionSegmenter(LEVELS, L=0.1, settle=settle)
    units, settled_at = [], []
    for k in range(P.shape[0]):
        unit = seg.push(DT * k, poses[k])
        if unit is not None:
            units.append(unit)
        if seg.moving and seg.resting:
            settled_at.append(DT * k)
    return units, settled_at


def test_a_stroke_that_drifts_on_settles_where_its_speed_fell_below_half():
    speeds = _stroke_then_drift(drift_s=0.6)
    units, settled_at = _run(speeds, settle=0.3)
    first = units[0]
    assert first.settled and not first.rest_after
    # the speed is taken over 0.1 s, centred: the unit ends within a lag of where it fell below
    top = int(np.argmax(speeds))
    fell = DT * (top + int(np.flatnonzero(speeds[top:] < PEAK / 2)[0]))
    assert abs(first.end_t - fell) <= 0.06
    # ... and it settles 0.3 s later, seen half a lag after the speed's centre
    assert len(settled_at) == 1
    assert first.end_t + 0.3 - 1e-9 <= settled_at[0] <= first.end_t + 0.3 + 0.06
    # the drift is not lost: the next unit starts where the first ended
    assert units[1].start == first.end and not units[1].settled
    # never settling, the same motion is cut only at the speed minimum before the second
    # stroke, and nothing says the hand rested
    never, none = _run(speeds, settle=math.inf)
    assert not none and not any(u.settled for u in never) and len(never) == 2


@pytest.mark.parametrize("drift_s, settles", [(0.1, False), (0.5, True)])
def test_only_a_slow_stretch_longer_than_the_settle_time_settles(drift_s, settles):
    units, settled_at = _run(_stroke_then_drift(drift_s), settle=0.3)
    assert any(u.settled for u in units) is settles
    assert bool(settled_at) is settles


def test_settle_must_be_positive():
    with pytest.raises(ValueError, match="settle"):
        MotionSegmenter(LEVELS, L=0.1, settle=0.0)
    for bad in (-1.0, 0, "inf"):  # "inf" as a command line's --set gives it: one clear line
        with pytest.raises(ValueError, match="settle must be a positive number of seconds"):
            SpottingConstants(settle=bad)


A = np.array([0.0, 0.0, 0.0])
B = np.array([0.35, 0.0, 0.0])


@pytest.fixture(scope="module")
def takes() -> tuple[list[Trajectory], list[str]]:
    """Takes of a straight swipe and of a circle, each resting before and after."""
    return swipe_and_circle_takes(11, np.array([A, B]))


def _swipe_events(takes: tuple[list[Trajectory], list[str]], **settings) -> tuple[list, float]:
    """A swipe after a rest, after which the hand drifts on the same way at a sixth of the
    swipe's peak speed for two seconds, then rests: the events, and the time [s] where the
    swipe's own speed fell to the drift's."""
    rec = Recognizer.from_trajectories(*takes, **settings)
    rec.background = False
    n = round(0.6 / DT)
    swipe = A + min_jerk(n)[:, None] * (B - A)
    speed = np.linalg.norm(np.diff(swipe, axis=0), axis=1) / DT
    drift = speed.max() / 6
    k = int(np.argmax(speed)) + int(np.flatnonzero(speed[np.argmax(speed):] <= drift)[0])
    way = (B - A) / np.linalg.norm(B - A)
    on = swipe[k] + drift * DT * np.arange(1, round(2.0 / DT))[:, None] * way
    rest = round(1.0 / DT)
    P = np.concatenate([np.repeat(swipe[:1], rest, axis=0), swipe[:k + 1], on,
                        np.repeat(on[-1:], rest, axis=0)])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    events = []
    for j, p in enumerate(P):
        events += rec.push(DT * j, p, q)
    return events + rec.finish(), DT * (rest + k)


def test_a_swipe_the_hand_drifts_on_from_fires_when_it_settles(takes):
    events, end = _swipe_events(takes)
    assert [e.label for e in events] == ["swipe"]
    assert events[0].time - end <= 0.5
    # never settling, the swipe and the drift are one unit: it fires once the hand rests
    late, _ = _swipe_events(takes, settle=math.inf)
    assert [e.label for e in late] == ["swipe"] and late[0].time - end > 1.5
