"""Continuous streams: label consistency, stop signals, scripts, file round trip, determinism."""

from __future__ import annotations

import itertools
import warnings
from pathlib import Path

import numpy as np
import pytest

from framefree.core import se3
from framefree.datasets import GESTURES, STOP, Segment, labels_path, load_stream
from framefree.errors import DatasetError
from framefree.replica import StreamItem, make_stream, save_stream


@pytest.fixture(scope="module")
def stream(replica_root: Path):
    return load_stream(replica_root / "streams" / "stream_1.csv")


def _angular_speed(traj) -> tuple[np.ndarray, np.ndarray]:
    """Times (n-1,) and angular speeds [rad/s] between consecutive samples."""
    w = np.linalg.norm(se3.relative_displacement_twists(traj.poses())[:, :3], axis=1) / np.diff(traj.t)
    return traj.t[1:], w


def test_labels_consistent(stream) -> None:
    traj, segs = stream
    assert 60 < traj.duration < 600  # a few minutes
    assert 20 <= len(segs) <= 22
    labels = [s.label for s in segs]
    assert sum(lab != STOP for lab in labels) == 20
    assert 1 <= labels.count(STOP) <= 2
    assert set(labels) - {STOP} <= set(GESTURES)
    for a, b in itertools.pairwise(segs):
        assert a.end_t < b.start_t  # ordered, no overlap
    for s in segs:
        assert 0 < s.start_t < s.end_t < traj.t[-1]
        assert 0.4 < s.end_t - s.start_t < 8


def test_stop_signals_are_fast_and_gestures_are_not_stop(stream) -> None:
    traj, segs = stream
    t, w = _angular_speed(traj)
    for s in segs:
        inside = (t >= s.start_t) & (t <= s.end_t)
        if s.label == STOP:
            assert w[inside].max() > 5.0
    # the hand is moving during every gesture
    v = np.linalg.norm(np.diff(traj.p, axis=0), axis=1) / np.diff(traj.t)
    for s in segs:
        inside = (t >= s.start_t) & (t <= s.end_t)
        assert (v[inside].max() > 0.15) or (w[inside].max() > 1.0)


def test_world_frame_drifts(stream) -> None:
    traj, _ = stream
    # the user walks around: positions span much more than an arm's reach
    assert np.ptp(traj.p, axis=0).max() > 0.8


def test_round_trip(tmp_path: Path) -> None:
    traj, segs = make_stream(3, n_gestures=3, n_stops=1)
    path = save_stream(tmp_path / "s.csv", traj, segs, np.random.default_rng(0))
    assert labels_path(path).read_text().splitlines()[0] == "label,start_t,end_t"
    traj2, segs2 = load_stream(path)
    assert segs2 == segs
    np.testing.assert_allclose(traj2.p, traj.p)
    np.testing.assert_allclose(np.abs(np.sum(traj2.q * traj.q, axis=1)), 1.0)


def test_deterministic() -> None:
    a, sa = make_stream(11, n_gestures=2)
    b, sb = make_stream(11, n_gestures=2)
    np.testing.assert_array_equal(a.to_array(), b.to_array())
    assert sa == sb


def test_script_with_start_times() -> None:
    script = [StreamItem("go_home", start_t=31.0), "go_left", StreamItem("stop", gap=3.0),
              StreamItem("go_down", start_t=60.0, speed=2.0)]
    traj, segs = make_stream(1, script)
    assert [s.label for s in segs] == ["go_home", "go_left", "stop", "go_down"]
    assert segs[0].start_t == pytest.approx(31.0)
    assert segs[2].start_t == pytest.approx(segs[1].end_t + 3.0)
    assert segs[3].start_t == pytest.approx(60.0)
    assert traj.t[-1] > segs[-1].end_t


def test_impossible_start_time_warns() -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _, segs = make_stream(2, [StreamItem("go_right", start_t=5.0), StreamItem("go_right", start_t=6.0)])
    assert any("as early as possible" in str(w.message) for w in caught)
    assert segs[1].start_t > segs[0].end_t


def test_unknown_label() -> None:
    with pytest.raises(ValueError, match="unknown stream label"):
        make_stream(0, ["go_sideways"])


def test_missing_or_bad_labels(tmp_path: Path) -> None:
    traj, segs = make_stream(4, n_gestures=1, n_stops=0)
    path = save_stream(tmp_path / "s.csv", traj, segs)
    labels_path(path).write_text("label,start,end\n")
    with pytest.raises(DatasetError, match="header"):
        load_stream(path)
    labels_path(path).write_text("label,start_t,end_t\ngo_up,3,x\n")
    with pytest.raises(DatasetError, match="row 2"):
        load_stream(path)
    labels_path(path).unlink()
    with pytest.raises(DatasetError, match="labels file missing"):
        load_stream(path)


def test_segment_is_frozen() -> None:
    s = Segment("go_up", 1.0, 2.0)
    with pytest.raises(AttributeError):
        s.label = "x"  # type: ignore[misc]
