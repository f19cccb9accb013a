"""Gestures the tracker does not follow: when another limb performs a gesture, most of its takes
give the spotter no candidate of itself, and the recognizer never fires it (docs/online.md).
Real Vive recordings: the right controller in the left hand's *hook left*."""

from __future__ import annotations

import math

import numpy as np
import pytest

from framefree.core.trajectory import Trajectory
from framefree.datasets.people_layout import load_people
from framefree.online import Recognizer
from framefree.online.evaluation import run_stream
from framefree.online.model_settings import unseen_advice
from framefree.online.thresholds import unseen_gestures
from real_data import SHIPPED_MACHETE


@pytest.fixture(scope="module")
def right() -> tuple[list[Trajectory], list[str]]:
    """The right controller's recordings of the shipped real people (two takes of seven gestures
    each)."""
    people = load_people(SHIPPED_MACHETE)
    return [r.sample.trackers[0] for r in people], [r.gesture for r in people]


def test_a_gesture_is_unseen_when_at_most_the_given_share_of_its_takes_is_found():
    scores = {"wave": [0.1, 0.2, 0.3, 0.2], "idle": [0.4, math.inf, math.inf, 0.3],
              "lost": [math.inf] * 3}
    assert unseen_gestures(scores, 0.5) == ["idle", "lost"]
    assert unseen_gestures(scores, 0.0) == ["lost"]  # only a gesture none of whose takes is found
    assert unseen_gestures(scores, 0.75) == ["idle", "lost"]
    assert unseen_gestures(scores, 1.0) == list(scores)


def test_the_right_controller_does_not_follow_the_left_hands_hook(right):
    trajs, labels = right
    rec = Recognizer.from_trajectories(trajs, labels)
    assert rec.learned_.unseen == ["hook_left"]
    assert rec.learned_.provenance.rules["unseen"].endswith("unseen_gestures")
    spotter = rec.spotter
    hook = np.asarray(rec.labels) == "hook_left"
    assert spotter.unseen[hook].all() and not spotter.unseen[~hook].any()
    assert not spotter.admitting_models(0.5, 1.0)[hook].any()  # whatever its shape
    assert rec.learned_.to_dict()["unseen"] == ["hook_left"]  # a library keeps it
    advice = unseen_advice(rec.learned_.unseen)
    assert advice is not None and advice.startswith("hook_left will never fire")
    assert unseen_advice([]) is None


def test_an_unseen_gesture_never_fires_even_below_its_threshold(right):
    trajs, labels = right
    hooks = [t for t, g in zip(trajs, labels, strict=True) if g == "hook_left"]
    loose = dict.fromkeys(set(labels), 1e-6) | {"hook_left": 10.0}  # hook_left accepts anything
    fired = {}
    for fraction in (0.5, 0.0):
        rec = Recognizer.from_trajectories(trajs, labels, gesture_thresholds=loose,
                                           seen_fraction=fraction)
        rec.warmup()
        rec.background = False
        events = []
        for take in hooks:
            rec.reset()
            events += run_stream(rec, take)[0]
        fired[fraction] = [e.label for e in events if not e.is_stop]
        # thresholds given: the unseen gestures are still learned from the takes
        assert rec.learned_.unseen == (["hook_left"] if fraction else [])
    assert fired[0.5] == []
    assert "hook_left" in fired[0.0]  # the same takes fire it once the rule is off


def test_enroll_and_check_name_the_gestures_the_tracker_does_not_follow(right, tmp_path):
    from click.testing import CliRunner

    from framefree.cli import cli

    trajs, labels = right
    count: dict[str, int] = {}
    for traj, g in zip(trajs, labels, strict=True):
        count[g] = count.get(g, 0) + 1
        folder = tmp_path / "takes" / g / "right"
        folder.mkdir(parents=True, exist_ok=True)
        traj.to_csv(folder / f"trial_{count[g]}.csv")
    lib = tmp_path / "right.npz"
    res = CliRunner().invoke(cli, ["enroll", str(tmp_path / "takes"), "-o", str(lib)])
    assert res.exit_code == 0, res.output
    assert "note: hook_left will never fire" in res.output
    hook = next(line for line in res.output.splitlines() if line.strip().startswith("hook_left"))
    assert "never fires" in hook
    res = CliRunner().invoke(cli, ["check", str(lib), "--out", str(tmp_path / "report")])
    assert "note: hook_left will never fire" in res.output
