"""The closed-loop person: requests decided on the fly, one continuous, deterministic stream."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.errors import DatasetError
from framefree.replica import LivePerson


def _session(person: LivePerson, chunks: bool):
    out = []
    person.perform("go_left", start_t=4.0)
    person.hold(1.5)
    if chunks:
        out.append(person.samples_until(3.0))
        out.append(person.samples_until())
    person.perform("go_left", gap=0.0)  # a repeat, as soon as possible
    person.perform("stop")
    person.perform("go_up", start_t=30.0)
    out.append(person.samples_until())
    t, p, q = (np.concatenate(parts) for parts in zip(*out, strict=True))
    return t, p, q


def test_chunked_emission_equals_one_shot_and_is_deterministic():
    t1, p1, q1 = _session(LivePerson(5), chunks=True)
    t2, p2, q2 = _session(LivePerson(5), chunks=False)
    np.testing.assert_array_equal(t1, t2)
    np.testing.assert_allclose(p1, p2, atol=1e-12)
    np.testing.assert_allclose(q1, q2, atol=1e-12)
    assert np.all(np.diff(t1) > 0)
    # ~50 Hz and no jumps at chunk boundaries: steps stay at hand-motion scale
    assert 0.015 < np.median(np.diff(t1)) < 0.025
    assert np.max(np.linalg.norm(np.diff(p1, axis=0), axis=1)) < 0.1
    assert np.min(np.sum(q1[1:] * q1[:-1], axis=1)) > 0.9  # sign-continuous


def test_segments_follow_the_requests():
    person = LivePerson(1)
    a = person.perform("go_home", start_t=6.0)
    person.hold(2.0)
    b = person.perform("go_home", gap=0.0)
    assert a.label == b.label == "go_home"
    assert abs(a.start_t - 6.0) < 1e-9
    assert b.start_t > a.end_t + 2.0
    assert [s.label for s in person.segments] == ["go_home", "go_home"]
    t, _, _ = person.samples_until()
    assert t[-1] <= person.time and t[-1] > b.end_t - 0.05
    empty_t, empty_p, _ = person.samples_until()
    assert empty_t.size == 0 and empty_p.shape == (0, 3)


def test_session_longer_than_max_duration_is_an_error():
    person = LivePerson(2, max_duration=8.0)
    with pytest.raises(DatasetError, match="max_duration"):
        person.perform("go_left", start_t=20.0)
