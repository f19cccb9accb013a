"""``benchmarks/multi_people_streams.py`` and ``benchmarks/bench_multi.py`` on the shipped sample
(tests/data/machete_vive: two people, seven gestures, two takes each): they run, hold each person
out of the models, and write what they print."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from framefree.datasets.multi_sessions import continuous_session
from framefree.datasets.people_layout import load_people
from framefree.datasets.stream_files import write_labels
from framefree.io.multicsv import write_multi_csv

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "tests" / "data" / "machete_vive"


def _run(name: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(ROOT / "benchmarks" / name), *args],
                          capture_output=True, text=True, timeout=600)


def test_held_out_sessions_on_the_shipped_sample(tmp_path):
    people = load_people(SAMPLE)
    for person in people.people:
        takes = people.of([person])
        sample, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                              rate=60.0)
        write_multi_csv(tmp_path / f"{person}_s1.csv", sample)
        write_labels(tmp_path / f"{person}_s1_labels.csv", segments)
    out = tmp_path / "result.json"
    proc = _run("multi_people_streams.py", "--data", str(SAMPLE), "--streams", str(tmp_path),
                "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    result = json.loads(out.read_text())
    assert set(result["per_person"]) == set(people.people)
    held = result["held_out"]
    assert held["tp"] + held["fn"] == len(people)  # every take of both sessions, once
    assert held["tp"] >= 0.8 * len(people), held
    assert "all people, each held out" in proc.stdout


def test_speed_on_the_shipped_sample(tmp_path):
    out = tmp_path / "speed.json"
    proc = _run("bench_multi.py", "--data", str(SAMPLE), "--rate", "60", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    result = json.loads(out.read_text())
    assert result["models"] == 28 and result["trackers"] == 2
    for mode in ("inline", "background"):
        assert 0 < result[mode]["p99_ms"] <= result[mode]["max_ms"]
    assert result["inline"]["events"] == result["background"]["events"] > 0
    assert result["inline"]["slowest_classification_ms"] > 0
    assert "slowest" in proc.stdout


def test_a_missing_data_folder_is_one_line(tmp_path):
    for name in ("multi_people_streams.py", "bench_multi.py"):
        proc = _run(name, "--data", str(tmp_path / "nowhere"))
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
        assert proc.stderr.strip().splitlines() == [
            f"--data {tmp_path / 'nowhere'}: not a folder of people <person>/<gesture>/<recording>"]
