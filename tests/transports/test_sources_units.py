"""Pose sources in other units or quaternion orders are converted, and implausible ones warned of."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.core.posecsv import PlausibilityWarning
from framefree.io.sources import UnitsAndOrder


def _poses(n: int, scale: float):
    for k in range(n):
        t = 0.02 * k
        yield t, np.array([0.5 * t, 0.0, 0.1]) * scale, np.array([0.1, 0.2, 0.3, 0.9])


def test_millimetres_and_scalar_last_are_converted():
    src = UnitsAndOrder(_poses(10, 1000.0), "zmq://127.0.0.1:1", quat_order="xyzw", units="mm")
    out = list(src)
    assert len(out) == 10
    np.testing.assert_allclose(out[3][1], [0.03, 0.0, 0.1])
    np.testing.assert_array_equal(out[3][2], [0.9, 0.1, 0.2, 0.3])


def test_a_source_in_millimetres_read_as_metres_is_warned_of_once():
    with pytest.warns(PlausibilityWarning, match=r"zmq://127.0.0.1:1: positions look like "
                      r"millimetres.*--units mm") as record:
        n = sum(1 for _ in UnitsAndOrder(_poses(300, 1000.0), "zmq://127.0.0.1:1", check_after=100))
    assert n == 300 and len(record) == 1


def test_a_plausible_source_is_not_warned_of(recwarn):
    assert sum(1 for _ in UnitsAndOrder(_poses(300, 1.0), "x", check_after=100)) == 300
    assert not [w for w in recwarn if issubclass(w.category, PlausibilityWarning)]
