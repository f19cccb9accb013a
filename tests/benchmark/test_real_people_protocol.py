"""``benchmarks/real_people_protocol.py``: the choice of each fold is made on its model people
only, and a clone without the shared data is told so in one line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np

from benchmark_scripts import load_benchmark

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "real_people_protocol.py"


def _module():
    return load_benchmark("real_people_protocol")


def _perfect_on(people: list[str], persons: np.ndarray, gestures: np.ndarray) -> np.ndarray:
    """Distances under which a recording of ``people`` is nearest to one of its own gesture and
    every other recording is nearest to one of another gesture."""
    same = gestures[:, None] == gestures[None, :]
    good = np.isin(persons, people)[:, None]
    D = np.where(same == good, 1.0, 2.0)
    np.fill_diagonal(D, 0.0)
    return D


def test_each_fold_chooses_on_its_model_people_only():
    """Candidate PS is right only for people a and b, the others only for c to f: the fold whose
    queries are a and b must choose P (right on its four model people, and first) and score 0."""
    mod = _module()
    people = ["a", "b", "c", "d", "e", "f"]
    persons = np.repeat(people, 6)
    gestures = np.tile(np.repeat(["x", "y", "z"], 2), len(people))
    names = {c for parts in mod.CANDIDATES.values() for c in parts}
    comps = {name: _perfect_on(["c", "d", "e", "f"], persons, gestures) for name in names}
    comps["PS"] = _perfect_on(["a", "b"], persons, gestures)
    res = mod.nested(comps, gestures, persons, people)
    fold = next(f for f in res["folds"] if f["queries"] == ["a", "b"])
    assert fold["chosen"] == "P" and fold["outer_chosen"] == 0.0 and fold["outer"]["PS"] == 1.0
    assert res["times_chosen"]["PS"] == 0 and res["all_people_choice"] == "P"


def test_a_missing_data_folder_is_one_line(tmp_path):
    proc = subprocess.run([sys.executable, str(SCRIPT), "--data", str(tmp_path / "nowhere")],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "nowhere" in proc.stderr
