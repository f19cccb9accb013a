"""The replica's person is pinned: without a ``person`` every generator gives exactly what it gave
before people were introduced (the Table I figures on the replica depend on it).

The reference digests were computed with the generators as they were before ``people.py`` existed.
Values are rounded to 1e-9 before hashing, so a last-bit difference of a math library does not
matter but any change of the random draws or of the geometry does.
"""

from __future__ import annotations

import hashlib
import warnings

import numpy as np
import pytest

from framefree.datasets import GESTURES
from framefree.replica import (
    DEFAULT_PERSON,
    LivePerson,
    StreamItem,
    make_stream,
    synthesize_gesture,
)

SYNTHESIZED = {
    "go_left": "e6ff7861c92a325c",
    "go_right": "1e7b6d3a70ea1f90",
    "go_up": "5d83692881e055ca",
    "go_down": "e220fd851a6d513b",
    "open_gripper": "7fb27be6022cc6d3",
    "close_gripper": "001e4a798b6e18c2",
    "go_home": "157fd891f82d3b30",
}


def _digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(np.round(np.asarray(a, dtype=np.float64), 9)).tobytes())
    return h.hexdigest()[:16]


def _spans(segments) -> list[list[float]]:
    return [[s.start_t, s.end_t] for s in segments]


@pytest.mark.parametrize("gesture", GESTURES)
def test_synthesized_trial_unchanged(gesture: str) -> None:
    traj = synthesize_gesture(gesture, np.random.default_rng([5, len(gesture)]))
    assert _digest(traj.to_array()) == SYNTHESIZED[gesture]


@pytest.mark.parametrize("gesture", ["go_right", "go_up", "close_gripper"])
def test_default_person_is_the_replica_person(gesture: str) -> None:
    a = synthesize_gesture(gesture, np.random.default_rng(21))
    b = synthesize_gesture(gesture, np.random.default_rng(21), person=DEFAULT_PERSON)
    np.testing.assert_array_equal(a.to_array(), b.to_array())


def test_random_stream_unchanged() -> None:
    traj, segs = make_stream(11, n_gestures=6)
    assert [s.label for s in segs] == [
        "close_gripper", "go_left", "stop", "go_home", "go_down", "go_right", "go_up"
    ]
    assert _digest(traj.to_array(), _spans(segs)) == "ae206313cf2052ed"


def test_scripted_stream_unchanged() -> None:
    script = [StreamItem("go_home", start_t=31.0), "go_left", StreamItem("stop", gap=3.0),
              StreamItem("go_down", start_t=60.0, speed=2.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traj, segs = make_stream(1, script)
    assert _digest(traj.to_array(), _spans(segs)) == "80e03f1b7e0b6863"


def test_live_person_unchanged() -> None:
    lp = LivePerson(5)
    lp.perform("go_left", start_t=4.0)
    lp.hold(1.5)
    lp.perform("go_left", gap=0.0)
    lp.perform("stop")
    lp.perform("go_up", start_t=30.0)
    t, p, q = lp.samples_until()
    assert _digest(t, p, q, _spans(lp.segments)) == "aa66a828d5d24240"
