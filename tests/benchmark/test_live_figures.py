"""``benchmarks/live_figures.py``: the comparison with the record, and its usage errors. The rows
themselves run the benchmarks (minutes), so only their verdicts are tested here."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from benchmark_scripts import BENCH, load_benchmark

live_figures = load_benchmark("live_figures")


def _row(tp: int, fp: int, fn: int) -> dict:
    p, r = tp / max(tp + fp, 1), tp / max(tp + fn, 1)
    return {"tp": tp, "fp": fp, "fn": fn, "precision": p, "recall": r,
            "f1": 2 * p * r / (p + r) if p + r else 0.0, "fp_per_minute": 0.1}


def test_a_row_with_the_same_counts_is_the_same():
    assert live_figures.compare({"sfinge": _row(28, 8, 15)},
                                {"sfinge": _row(28, 8, 15)}) == {"sfinge": "same"}


@pytest.mark.parametrize("now", [(29, 8, 14), (28, 9, 15), (28, 8, 16)])
def test_any_count_that_changes_moves_the_row(now):
    assert live_figures.compare({"sfinge": _row(*now)},
                                {"sfinge": _row(28, 8, 15)}) == {"sfinge": "moved"}


def test_the_same_totals_from_other_streams_move_the_row():
    now = {**_row(28, 8, 15), "per_stream": {"seq_01": [1, 0, 0], "seq_02": [27, 8, 15]}}
    record = {**_row(28, 8, 15), "per_stream": {"seq_01": [0, 0, 1], "seq_02": [28, 8, 14]}}
    assert live_figures.compare({"sfinge": now}, {"sfinge": record}) == {"sfinge": "moved"}
    assert live_figures.compare({"sfinge": now}, {"sfinge": now}) == {"sfinge": "same"}
    assert live_figures.compare({"sfinge": now}, {"sfinge": _row(28, 8, 15)}) == {"sfinge": "same"}


def test_a_row_never_recorded_says_so():
    assert live_figures.compare({"replica": _row(1, 0, 0)}, {}) == {"replica": "no record"}


def test_every_row_of_the_record_is_a_row_the_script_measures():
    record = json.loads(live_figures.RECORD.read_text())
    assert set(record) <= set(live_figures.ROWS)
    for row in record.values():
        assert {"tp", "fp", "fn", "f1"} <= set(row) <= set(live_figures.KEYS)


def test_an_unknown_row_is_one_line_and_exit_2():
    proc = subprocess.run([sys.executable, str(BENCH / "live_figures.py"), "--only", "sfinge,nope"],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        "--only: unknown row 'nope' (rows: sfinge, sfinge_no_hand_frame, machete_one, "
        "machete_right_hand, machete_left_hand, machete_two, replica, zigzag, check_mark)"]


def test_a_row_without_its_data_is_skipped(monkeypatch, tmp_path, capsys):
    title, _, measure = live_figures.ROWS["sfinge"]
    monkeypatch.setitem(live_figures.ROWS, "sfinge", (title, tmp_path / "missing", measure))
    record = tmp_path / "record.json"
    assert live_figures.main(["--only", "sfinge", "--record", str(record)]) == 0
    assert f"sfinge: skipped, {tmp_path / 'missing'} is missing" in capsys.readouterr().out
    assert not record.exists()
