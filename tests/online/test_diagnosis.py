"""Why a gesture was missed (``framefree evaluate-stream --explain``,
:mod:`framefree.online.diagnosis`): each reason from a candidate log built for it, and the
command on a labelled stream."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest
from click.testing import CliRunner

from cli_helpers import tiny_dataset
from framefree.cli import cli
from framefree.online.candidate import Candidate
from framefree.online.diagnosis import MISS_REASONS, explain
from framefree.online.evaluation import StreamResult
from framefree.online.spotting import Spotter

LABELS = ["swipe", "circle"]  # the gesture of each of two models
SEGMENT = SimpleNamespace(label="swipe", start_t=10.0, end_t=11.0)


def _spotter() -> Spotter:
    classifier = SimpleNamespace(models=[np.zeros((5, 1))] * len(LABELS))
    return Spotter(classifier, np.ones(len(LABELS)), travel_limits=np.array([0.2, 0.0]))


def _candidate(start_t: float, end_t: float, model: int, ratio: float, accepted: bool = False,
               travel: float = 0.5) -> Candidate:
    return Candidate(int(start_t * 50), int(end_t * 50), start_t, end_t, model, ratio, ratio, 1,
                     size=0.4, accepted=accepted, travel=travel)


def _why(log: list[Candidate]) -> dict:
    res = StreamResult(fn=1, missed=[{"segment": 0, "label": "swipe", "start_t": 10.0,
                                      "end_t": 11.0}])
    return explain(res, [SEGMENT], log, LABELS, _spotter())["missed"][0]


@pytest.mark.parametrize(("log", "reason"), [
    ([_candidate(2.0, 3.0, 0, 0.5, True)], "no candidate"),
    ([_candidate(7.0, 10.5, 0, 0.5)], "cut elsewhere"),  # starts at a rest 3 s early
    ([_candidate(10.0, 11.1, 1, 0.5)], "another gesture"),
    ([_candidate(10.0, 11.1, 0, 1.4), _candidate(9.9, 11.0, 0, 1.2)], "beyond its threshold"),
    ([_candidate(10.0, 11.1, 0, 0.7, travel=0.1)], "refused by a limit"),
    ([_candidate(10.0, 11.1, 0, 0.7, True)], "accepted, not fired"),
])
def test_each_reason_is_the_first_stage_the_gesture_did_not_pass(log, reason):
    why = _why(log)
    assert why["reason"] == reason
    assert reason in MISS_REASONS
    if reason == "no candidate":
        assert why["candidate"] is None
    if reason == "beyond its threshold":
        assert why["candidate"]["ratio"] == 1.2  # the candidate that came closest
    if reason == "refused by a limit":
        assert why["limits"] == ["travel"]


def test_a_false_positive_is_explained_by_the_candidate_that_fired():
    fired = _candidate(20.0, 20.8, 0, 0.6, True)
    res = StreamResult(fp=1, details=[{"time": 21.0, "label": "swipe", "dissimilarity": 0.6,
                                       "model": 0, "segment": None, "verdict": "fp"}])
    why = explain(res, [SEGMENT], [_candidate(19.0, 20.5, 0, 0.8, True), fired], LABELS, _spotter())
    fp = why["false_positives"][0]
    assert fp["candidate"]["start_t"] == 20.0 and fp["candidate"]["gesture"] == "swipe"
    assert fp["overlaps"] == []


def test_the_spotter_names_the_limits_that_refuse_a_candidate():
    spotter = _spotter()
    assert spotter.refusals(_candidate(0.0, 1.0, 0, 0.5, travel=0.1)) == ["travel"]
    assert spotter.refusals(_candidate(0.0, 1.0, 0, 0.5, travel=0.3)) == []


def test_evaluate_stream_explains_every_miss(tmp_path):
    gestures = ("go_left", "open_gripper")
    stream = tiny_dataset(tmp_path, gestures, gestures)
    out = tmp_path / "eval.json"
    # a threshold no gesture can meet: every gesture is missed, and says why
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(tmp_path), "--stream",
                                   str(stream), "--threshold", "1e-9", "--explain",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    data = json.loads(out.read_text())
    why = next(iter(data["streams"].values()))["explain"]
    assert len(why["missed"]) == data["total"]["fn"] == len(gestures)
    assert all(m["reason"] in MISS_REASONS for m in why["missed"])
    assert sum(data["total"]["miss_reasons"].values()) == len(gestures)
    assert "misses by reason:" in res.output and "missed go_left" in res.output


def test_only_the_segment_recognizer_explains(tmp_path):
    gestures = ("go_left",)
    stream = tiny_dataset(tmp_path, gestures, gestures)
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(tmp_path), "--stream",
                                   str(stream), "--method", "paper", "--explain"])
    assert res.exit_code == 2
    assert "--explain" in res.output and "Traceback" not in res.output
