"""``framefree check`` replays a library's takes through its recognizer: a part of one gesture
that fires another (:mod:`framefree.library.inside`); and it names a gesture whose calibration
found no gap between its takes and non-gesture motion (:mod:`framefree.library.separation`)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from benchmark_scripts import load_benchmark
from framefree.cli import cli
from framefree.library import GestureLibrary, TakeSet, enroll, load_library, load_recognizer
from framefree.library.inside import fired_inside, from_rest, inside_findings
from framefree.library.separation import separation_findings
from framefree.replica import replica_path


def _check_mark_takes(seed: int) -> TakeSet:
    """Five check marks as ``framefree record`` cuts one recording of the replica's person (the
    new-gesture benchmark's demonstration ``seed``)."""
    takes = tuple(load_benchmark("eighth_gesture").recorded_takes("check_mark", 5, seed))
    return TakeSet(takes, ("check_mark",) * len(takes),
                   tuple(f"check_mark/own/trial_{k + 1}" for k in range(len(takes))))


@pytest.fixture(scope="module")
def rounded_check_mark(hpm_takes: TakeSet, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The HPM seven and a check mark whose five takes (demonstration seed 1) look like the arc
    out of a *go home*: held-out people's *go home* then gave a check mark 11 times in 29
    (``benchmarks/eighth_gesture.py --gesture check_mark --people 10 --demo-seed 1``)."""
    lib = enroll(hpm_takes + _check_mark_takes(1), built_from=[str(replica_path()), "check mark"])
    return lib.save(tmp_path_factory.mktemp("inside") / "hpm_check.npz")


def test_the_seven_fire_nothing_inside_each_other(hpm_library_file: Path, hpm_takes: TakeSet) -> None:
    assert fired_inside(load_recognizer(hpm_library_file), hpm_takes) == {}


def test_a_check_mark_that_begins_go_home_is_found(rounded_check_mark: Path) -> None:
    takes = load_library(rounded_check_mark).takes
    fired = fired_inside(load_recognizer(rounded_check_mark), takes)
    assert set(fired) == {"go_home"} and set(fired["go_home"]) == {"check_mark"}
    names = fired["go_home"]["check_mark"]
    assert len(names) > 5 / 2 and all(n.startswith("go_home/") for n in names)
    [finding] = inside_findings(fired, takes)
    assert finding.level == "problem" and finding.gesture == "go_home"
    assert "record check_mark again" in finding.message and names[0] in finding.message


def test_check_exits_1_and_writes_the_problem(rounded_check_mark: Path, tmp_path: Path) -> None:
    res = CliRunner().invoke(cli, ["check", str(rounded_check_mark), "--out", str(tmp_path)])
    assert res.exit_code == 1, res.output
    assert "PROBLEM: 3 of go_home's 5 takes, replayed as a stream, fire check_mark" in res.output
    assert "WARNING: check_mark is not apart from motion that is no gesture" in res.output
    report = json.loads((tmp_path / "hpm_check_check.json").read_text())
    assert not report["ok"]
    assert [f["gesture"] for f in report["findings"] if f["level"] == "problem"] == ["go_home"]


def test_a_minority_is_a_warning_that_names_the_take(hpm_takes: TakeSet) -> None:
    fired = {"go_left": {"stop": ["go_left/original_1/trial_2"]},
             "go_up": {"go_left": ["go_up/original_1/trial_1", "go_up/original_1/trial_4"]}}
    stop, left = inside_findings(fired, hpm_takes)
    assert (stop.level, left.level) == ("warning", "warning")
    assert stop.message.startswith("1 of go_left's 5 takes, replayed as a stream, fires a stop signal")
    assert "--remove go_left/original_1/trial_2" in stop.message
    assert left.message.startswith("2 of go_up's 5 takes, replayed as a stream, fire go_left")
    fired["go_up"]["go_left"].append("go_up/original_1/trial_5")
    assert inside_findings(fired, hpm_takes)[1].level == "problem"


def test_a_take_is_replayed_from_a_rest(hpm_takes: TakeSet) -> None:
    """The first pose held still in front, at the take's sampling interval; the take itself as
    it was (and not written into)."""
    take = hpm_takes.takes[0]
    before = take.p.copy()
    padded = from_rest(take, 1.0)
    step = float(np.median(np.diff(take.t)))
    n = len(padded) - len(take)
    assert n == math.ceil(1.0 / step)
    assert np.all(np.diff(padded.t) > 0) and padded.t[n - 1] == pytest.approx(take.t[0] - step)
    np.testing.assert_array_equal(padded.p[:n], np.repeat(take.p[:1], n, axis=0))
    np.testing.assert_array_equal(padded.q[:n], np.repeat(take.q[:1], n, axis=0))
    np.testing.assert_array_equal(padded.p[n:], take.p)
    np.testing.assert_array_equal(take.p, before)
    assert from_rest(take, 0.0) is take


def test_a_check_mark_near_free_motion_is_named(rounded_check_mark: Path,
                                                 hpm_library: GestureLibrary) -> None:
    """Demonstration 1's worst check mark lies 0.065 from the other takes, random shapes and
    moves within 0.058: no gap (``separated`` False); the HPM seven all have one."""
    assert hpm_library.unseparated == [] and separation_findings(hpm_library) == []
    lib = load_library(rounded_check_mark)
    assert lib.unseparated == ["check_mark"]
    [finding] = separation_findings(lib)
    worst = lib.calibration["positives_max"]["check_mark"]
    nearest = lib.calibration["negatives_quantile"]["check_mark"]
    assert finding.level == "warning" and worst >= nearest
    assert f"worst take lies {worst:.3g}" in finding.message and f"within {nearest:.3g}" in finding.message
    assert "check_mark" in lib.summary().splitlines()[-1]
    assert "not apart from other motion" in lib.summary().splitlines()[-1]
    assert "not apart" not in hpm_library.summary()
