"""``benchmarks/real_people.py`` from a clone: it runs without ``../shared/data`` (on the sample
in tests/data), never writes a tracked file, titles its figure from the data used, and a missing
``--data`` is one line."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "real_people.py"


def _run(script: Path, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(script), *args], cwd=cwd, capture_output=True,
                          text=True, timeout=600)


def test_a_missing_data_folder_is_one_line(tmp_path):
    proc = _run(SCRIPT, "--data", str(tmp_path / "nowhere"), cwd=tmp_path)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "--data" in lines[0] and "nowhere" in lines[0]


def test_a_clone_without_shared_data_runs_on_the_shipped_sample(tmp_path):
    """A copy of the repository's layout with no ``../shared`` beside it: the script says it uses
    tests/data, writes below benchmarks/results/local/ only, and titles the figure 2 people."""
    clone = tmp_path / "clone"
    (clone / "benchmarks").mkdir(parents=True)
    shutil.copy(SCRIPT, clone / "benchmarks" / SCRIPT.name)
    shutil.copytree(ROOT / "tests" / "data" / "machete_vive", clone / "tests" / "data" / "machete_vive")
    proc = _run(clone / "benchmarks" / SCRIPT.name, "--seeds", "0", cwd=clone)
    assert proc.returncode == 0, proc.stderr
    assert "not found: using the tests/data/machete_vive sample" in proc.stdout.splitlines()[0]
    written = sorted(str(p.relative_to(clone)) for p in clone.rglob("*")
                     if p.is_file() and "data" not in p.parts and p.suffix != ".py")
    assert written == ["benchmarks/results/local/real_people.json",
                       "benchmarks/results/local/real_people.png"]
    out = json.loads((clone / "benchmarks/results/local/real_people.json").read_text())
    assert out["title"].startswith("2 real people, 2 trackers each, 7 gestures")
    assert len(out["people"]) == 2


def test_the_default_output_folder_is_ignored_by_git():
    git = shutil.which("git")
    if git is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    proc = subprocess.run([git, "check-ignore", "-q", "benchmarks/results/local/real_people.json"],
                          cwd=ROOT)
    assert proc.returncode == 0
