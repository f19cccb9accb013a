"""framefree evaluate-people and the comparison behind it, on real Vive recordings."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from framefree.benchmark.people import evaluate_people, reframe
from framefree.datasets.people_layout import load_people
from real_data import SHIPPED_MACHETE

CLI = [sys.executable, "-m", "framefree.cli"]


def test_frames_move_the_world_and_keep_the_stated_vertical():
    sample = load_people(SHIPPED_MACHETE).recordings[0].sample
    for kind in ("turned", "tilted"):
        (moved,) = reframe([sample], kind, seed=3)
        assert np.array_equal(moved.up, sample.up)
        assert not np.allclose(moved.trackers[0].p, sample.trackers[0].p)
    (same,) = reframe([sample], "recorded")
    assert np.array_equal(same.trackers[0].p, sample.trackers[0].p)


def test_gravity_and_full_do_not_move_with_the_frame():
    ds = load_people(SHIPPED_MACHETE)
    gravity = {k: evaluate_people(ds, invariance="gravity", frames=k).accuracy
               for k in ("recorded", "turned")}
    full = {k: evaluate_people(ds, invariance="full", frames=k).accuracy for k in ("recorded", "tilted")}
    assert gravity["recorded"] == gravity["turned"] >= 0.9
    assert full["recorded"] == full["tilted"] >= 0.9
    # the world-frame baseline does move
    base = [evaluate_people(ds, method="baseline", frames=k).accuracy for k in ("recorded", "tilted")]
    assert base[1] < base[0]


def test_command_line(tmp_path: Path):
    out = tmp_path / "r.json"
    run = subprocess.run([*CLI, "evaluate-people", str(SHIPPED_MACHETE), "--invariance", "gravity",
                          "--frames", "turned", "--json", str(out)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "accuracy" in run.stdout and "Sub_U001" in run.stdout
    result = json.loads(out.read_text())
    assert 0.0 <= result["accuracy"] <= 1.0 and set(result["per_person"]) == {"Sub_U001", "Sub_U002"}
    assert len(result["confusion"]) == len(result["labels"]) == 7
    models = subprocess.run([*CLI, "evaluate-people", str(SHIPPED_MACHETE / ".." / "machete_vive"),
                             "--models", str(SHIPPED_MACHETE)], capture_output=True, text=True)
    assert models.returncode == 0 and "models given" in models.stdout


def test_command_line_mistakes(tmp_path: Path):
    (tmp_path / "p" / "g").mkdir(parents=True)
    (tmp_path / "p" / "g" / "x.csv").write_text("not,a,pose\n")
    run = subprocess.run([*CLI, "evaluate-people", str(tmp_path)], capture_output=True, text=True)
    assert run.returncode == 2 and run.stderr.strip().count("\n") == 0 and "x.csv" in run.stderr


def test_classify_takes_multi_tracker_recordings(tmp_path: Path):
    import shutil

    for g in ("hook_right", "uppercut_right"):
        shutil.copytree(SHIPPED_MACHETE / "Sub_U001" / g, tmp_path / g)
    queries = [str(SHIPPED_MACHETE / "Sub_U002" / g / "ex_0_moderate")
               for g in ("hook_right", "uppercut_right")]
    run = subprocess.run([*CLI, "classify", "-m", str(tmp_path), *queries, "--invariance", "gravity"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "multi-tracker recordings of 2 labels" in run.stderr
    lines = run.stdout.splitlines()[1:]
    assert [ln.split()[1] for ln in lines] == ["hook_right", "uppercut_right"]
