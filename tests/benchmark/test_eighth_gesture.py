"""``benchmarks/eighth_gesture.py``: several demonstrators in one command, and its table."""

from __future__ import annotations

import pytest

from benchmark_scripts import load_benchmark


@pytest.fixture(scope="module")
def eighth_gesture():
    return load_benchmark("eighth_gesture")


@pytest.mark.parametrize(("text", "seeds"), [
    ("3", [3]), ("0-4", [0, 1, 2, 3, 4]), ("0,2,5-6", [0, 2, 5, 6]), (" 1 , 4", [1, 4]),
])
def test_demo_seeds_read_one_a_range_or_a_list(eighth_gesture, text, seeds):
    assert eighth_gesture.demo_seeds(text) == seeds


def test_the_demonstrations_table_counts_the_new_gesture_and_the_seven_apart(eighth_gesture, capsys):
    def counts(tp, fp, fn):
        return {"tp": tp, "fp": fp, "fn": fn, "f1": 2 * tp / (2 * tp + fp + fn)}

    per = {"go_left": counts(20, 1, 2), "go_home": counts(10, 0, 12), "stop": counts(30, 0, 1),
           "check_mark": counts(25, 16, 7)}
    runs = {1: {"with_new_gesture": {"per_gesture": per, "total": {"f1": 0.911}},
                "fired_inside": {"go_home": {"check_mark": ["a", "b", "c"]}}},
            2: {"with_new_gesture": {"per_gesture": per, "total": {"f1": 0.911}},
                "fired_inside": {}}}
    eighth_gesture._print_demonstrations("check_mark", runs)
    first, second = (line.split() for line in capsys.readouterr().out.splitlines()[-2:])
    assert first[:6] == ["1", "25", "/", "16", "/", "7"]
    assert first[7:12] == ["30", "/", "1", "/", "14"]  # go_left + go_home, stop apart
    assert first[12:] == ["91.1%", "3", "go_home", "fire", "check_mark"]
    assert second[12:] == ["91.1%", "none"]


@pytest.mark.parametrize("text", ["x", "4-2", "1-"])
def test_a_seed_that_is_no_seed_is_one_line(eighth_gesture, text):
    with pytest.raises(SystemExit, match="--demo-seed"):
        eighth_gesture.demo_seeds(text)
