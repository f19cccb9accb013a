"""The rest level from the takes (v17): the median noise floor, and a guard for takes cut
without a rest. Real data (SFINGE3D's dictionary) is not shipped; the replica's HPM takes, cut
as such examples are cut, stand in for it."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.core.trajectory import Trajectory
from framefree.datasets.layout import load_model_recordings
from framefree.online.limits import recording_units
from framefree.online.rest_levels import speed_levels
from framefree.online.segmentation import motion_speed
from framefree.replica import replica_path

L, DT = 0.1, 0.02


@pytest.fixture(scope="module")
def takes() -> list[Trajectory]:
    return load_model_recordings(replica_path(0), "original_1")[0]


def _moving_part(tr: Trajectory, fraction: float = 0.3) -> Trajectory:
    """The take from where its speed first reaches ``fraction`` of its peak to where it last does:
    a gesture cut from continuous motion, with no rest before or after."""
    t, poses = tr.uniform_poses(DT)
    v = motion_speed(poses, DT, L, 5)
    fast = np.flatnonzero(v >= fraction * np.nanmax(v))
    return tr.slice_time(float(t[fast[0]]), float(t[fast[-1]]))


def _peak(tr: Trajectory) -> float:
    _, poses = tr.uniform_poses(DT)
    return float(np.nanmax(motion_speed(poses, DT, L, 5)[5:]))


def test_one_take_cut_without_a_rest_does_not_move_the_level(takes):
    """Before v17 the largest floor decided: one take cut in mid-motion put the rest level above
    the other takes' peaks (SFINGE3D: 0.58 m/s against swipes of 0.27-1.5)."""
    clean = speed_levels(takes, L, DT)
    mixed = speed_levels([*takes[:-1], _moving_part(takes[-1])], L, DT)
    assert mixed.rest == pytest.approx(clean.rest, rel=0.1)
    assert mixed.move < min(_peak(tr) for tr in takes) / 2


def test_takes_cut_without_a_rest_still_start_units(takes):
    """Where most takes are cut without a rest the median floor is their slow motion; the move
    level is then at most half the median peak, and the takes still start movement units (the
    models are not refused with 'no movement found')."""
    cut = [_moving_part(tr, 0.5) for tr in takes]
    levels = speed_levels(cut, L, DT)
    peaks = [_peak(tr) for tr in cut]
    assert levels.move <= 0.5 * np.median(peaks) + 1e-12
    started = [bool(recording_units(tr, levels, L, DT)[1]) for tr in cut]
    assert np.mean(started) >= 0.9


def test_the_guard_leaves_takes_with_rests_alone(takes):
    """HPM takes rest before and after: the level is 3 x their median floor, far below the guard."""
    levels = speed_levels(takes, L, DT)
    assert levels.move < 0.5 * np.median([_peak(tr) for tr in takes])
    assert levels.rest == pytest.approx(0.061, abs=0.01)
