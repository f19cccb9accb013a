"""Several people's examples laid out as ``<person>/<gesture>/`` or as ``<gesture>/<person>/``:
the folders have the same shape, and the motions decide which level names the gestures.
Real takes: two Machete people's right controller (shipped, MIT)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from framefree.datasets import resolve_models
from framefree.datasets.gesture_level import group_recovery
from framefree.datasets.people_layout import load_people
from framefree.library import read_takes
from real_data import SHIPPED_MACHETE

GESTURES = ("cartwheel_left", "golf_swing", "hook_right", "uppercut_right")


@pytest.fixture(scope="module")
def machete_folders(tmp_path_factory) -> tuple[Path, Path]:
    """The same takes as ``<person>/<gesture>/k.csv`` and as ``<gesture>/<person>/k.csv``."""
    root = tmp_path_factory.mktemp("people")
    for r in load_people(SHIPPED_MACHETE):
        if r.gesture not in GESTURES:
            continue
        for folder in (root / "by_person" / r.person / r.gesture,
                       root / "by_gesture" / r.gesture / r.person):
            folder.mkdir(parents=True, exist_ok=True)
            r.sample.trackers[0].to_csv(folder / f"{len(list(folder.glob('*.csv')))}.csv")
    return root / "by_person", root / "by_gesture"


def test_either_layout_of_real_peoples_takes_is_read_with_the_gestures_as_labels(machete_folders):
    by_person, by_gesture = machete_folders
    for folder in machete_folders:
        found = resolve_models(folder)
        assert sorted(set(found.labels)) == sorted(GESTURES)
        assert "from 2 people" in found.description
        takes = read_takes(folder)
        assert list(takes.labels) == found.labels
        assert {name.split("/")[1] for name in takes.names} == {"Sub_U001", "Sub_U002"}
    assert "<label>/<person>/*.csv, as the motions group" in resolve_models(by_gesture).description
    assert "<person>/<label>/*.csv (no" in resolve_models(by_person).description


def test_group_recovery_counts_the_nearest_take_of_another_group():
    # gesture a by people p and q, gesture b by p and q: the takes of a gesture lie together, and
    # across gestures each take lies nearest the other person's
    distances = np.array([[0, 1, 6, 5], [1, 0, 5, 6], [6, 5, 0, 2], [5, 6, 2, 0]], float)
    gestures, people = ["a", "a", "b", "b"], ["p", "q", "p", "q"]
    assert group_recovery(distances, gestures, people) == 1.0  # labels gestures, groups people
    assert group_recovery(distances, people, gestures) == 0.0  # the other way round


def test_a_tie_counts_the_share_of_the_nearest_takes_and_a_lone_group_does_not_count():
    distances = np.ones((3, 3)) - np.eye(3)
    assert group_recovery(distances, ["a", "a", "b"], ["p", "q", "r"]) == pytest.approx(1 / 3)
    assert group_recovery(distances, ["a", "b", "c"], ["p", "p", "p"]) == 0.0
