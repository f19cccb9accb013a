"""``benchmarks/record_sessions.py``: a session is cut right only when every performance has its
own take and no take reaches into the moves around it (session 42)."""

from __future__ import annotations

import pytest

from benchmark_scripts import load_benchmark
from framefree.library import recorder

record_sessions = load_benchmark("record_sessions")


def test_a_session_whose_takes_hold_their_performances_is_cut_right() -> None:
    ok, found = record_sessions.cut_right("zigzag", 2, (1.2, 2.0), 0.6)
    assert ok and found["takes"] == [0, 1, 2, 3, 4]
    assert found["longest_run_on"] <= record_sessions.RUN_ON


def test_a_take_holding_its_way_back_is_cut_wrong(monkeypatch: pytest.MonkeyPatch) -> None:
    """Development person 2's fourth zigzag, joined with the way back they began soon after it
    (every move taken for a retrace, as before session 42): each take still holds its
    performance, but one reaches 2.9 s past it."""
    monkeypatch.setattr(recorder, "retraces", lambda first, second: True)
    ok, found = record_sessions.cut_right("zigzag", 2, (1.2, 2.0), 0.6)
    assert found["takes"] == [0, 1, 2, 3, 4] and found["joined"] == 1
    assert not ok and found["longest_run_on"] > 2.0
