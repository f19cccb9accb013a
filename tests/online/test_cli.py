"""Command-line tests: ``framefree stream``, ``live`` (ZeroMQ on 127.0.0.1) and ``evaluate-stream``.

A tiny dataset (2 gestures × 3 synthetic recordings) and a short labelled stream are written to a
temporary folder; every ZeroMQ command stops by itself (end message or timeout).
"""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli_helpers import free_port, tiny_dataset
from framefree.cli import cli

GESTURES = ("go_left", "open_gripper")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory) -> tuple[Path, Path]:
    """``(dataset folder, stream CSV)``: 3 recordings per gesture, a stream of both gestures."""
    root = tmp_path_factory.mktemp("tiny")
    return root, tiny_dataset(root, GESTURES, GESTURES)


def test_evaluate_stream(tiny, tmp_path):
    root, stream = tiny
    out = tmp_path / "eval.json"
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(root), "--stream", str(stream),
                                   "--json", str(out), "--figures", str(tmp_path / "figs")])
    assert res.exit_code == 0, res.output
    assert "precision" in res.output and "F1" in res.output
    data = json.loads(out.read_text())
    tot = data["total"]
    assert tot["tp"] + tot["fn"] == len(GESTURES)
    assert 0.0 <= tot["f1"] <= 1.0
    assert set(data["recognizer"]["gesture_thresholds"]) == set(GESTURES)
    assert (tmp_path / "figs" / "stream_timeline.png").is_file()


def test_live_from_csv_file(tiny):
    root, stream = tiny
    res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream),
                                   "--speed", "0", "--no-view"])
    assert res.exit_code == 0, res.output
    assert "poses" in res.output


def test_live_classifies_in_background_by_default_with_the_inline_events(tiny):
    root, stream = tiny
    outputs = {}
    for how in ("background", "inline"):
        res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream),
                                       "--speed", "0", "--no-view", "--classify", how])
        assert res.exit_code == 0, res.output
        outputs[how] = sorted(line for line in res.output.splitlines() if " s  " in line)
    default = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream),
                                       "--speed", "0", "--no-view"])
    assert sorted(line for line in default.output.splitlines() if " s  " in line) == outputs["inline"]
    assert outputs["background"] == outputs["inline"] and len(outputs["inline"]) >= 2
    paper = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream),
                                     "--speed", "0", "--no-view", "--method", "paper",
                                     "--classify", "background"])
    assert paper.exit_code == 2 and "--method segments" in paper.output


def test_stream_and_live_over_zmq(tiny):
    """``stream`` publishes on 127.0.0.1 while ``live`` subscribes; both end by themselves."""
    root, stream = tiny
    port = free_port()
    out: dict[str, object] = {}

    def publish():
        time.sleep(1.0)  # let the subscriber build its models first (slow joiner on top)
        out["stream"] = CliRunner().invoke(cli, ["stream", str(stream), "--port", str(port),
                                                 "--speed", "0", "--join-wait", "1.0"])

    th = threading.Thread(target=publish, daemon=True)
    th.start()
    res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source",
                                   f"zmq://127.0.0.1:{port}", "--timeout", "8", "--no-view"])
    th.join(30)
    assert not th.is_alive()
    pub = out["stream"]
    assert pub.exit_code == 0, pub.output
    assert "sent" in pub.output
    assert res.exit_code == 0, res.output
    n_sent = int(pub.output.split("sent ")[-1].split()[0])
    n_got = int(res.output.strip().splitlines()[-1].split()[0])
    assert n_got > 0 and n_got <= n_sent


def test_live_rejects_non_loopback(tiny):
    root, _ = tiny
    res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", "zmq://192.168.1.2:5556",
                                   "--timeout", "0.2", "--no-view"])
    assert res.exit_code != 0


def test_live_drives_the_simulated_robot(tiny, tmp_path):
    pytest.importorskip("mujoco")
    root, stream = tiny
    fig = tmp_path / "robot.png"
    res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream), "--speed", "0",
                                   "--no-view", "--robot", "sim", "--robot-plot", str(fig),
                                   "--robot-settle", "0.5"])
    assert res.exit_code == 0, res.output
    assert "robot:" in res.output and "simulated" in res.output
    assert fig.is_file()


def test_evaluate_stream_restricted_to_some_gestures(tiny, tmp_path):
    """--gestures keeps only those models, and the other labels become non-gesture motion."""
    root, stream = tiny
    out = tmp_path / "eval.json"
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(root), "--stream", str(stream),
                                   "--gestures", "go_left", "--json", str(out)])
    assert res.exit_code == 0, res.output
    data = json.loads(out.read_text())
    assert data["recognizer"]["gestures"] == ["go_left"]
    tot = data["total"]
    assert tot["tp"] + tot["fn"] == 1  # open_gripper is no longer a labelled gesture
    assert set(tot["gestures"]) <= {"go_left"}
    assert "go_left: TP" in res.output and "latency median" in res.output


def test_evaluate_stream_names_a_gesture_without_models(tiny):
    root, stream = tiny
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(root), "--stream", str(stream),
                                   "--gestures", "go_left,wave"])
    assert res.exit_code == 2
    assert "no model recordings of wave" in res.output
    assert "Traceback" not in res.output


def test_live_emits_in_time_order_with_a_slow_classifier(tmp_path, monkeypatch):
    """``live --speed 0`` with every classification 50 ms slower: the worker falls behind the
    replay, and still every output gets the events in time order (a stop never overtakes the
    gesture before it), the same events as inline classification."""
    from cli_helpers import tiny_dataset
    from framefree.online import spotting

    root = tmp_path / "data"
    root.mkdir()
    stream = tiny_dataset(root, GESTURES, ["go_left", "stop", "open_gripper", "go_left", "stop"])
    search = spotting.SegmentClassifier.search_described

    def slow(self, descriptor, accept_below=None):
        time.sleep(0.05)
        return search(self, descriptor, accept_below)

    runs = {}
    for how in ("inline", "background"):
        if how == "background":
            monkeypatch.setattr(spotting.SegmentClassifier, "search_described", slow)
        out = tmp_path / f"{how}.jsonl"
        res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream),
                                       "--speed", "0", "--no-view", "--classify", how,
                                       "--emit", f"jsonl:{out}"])
        assert res.exit_code == 0, res.output
        runs[how] = [json.loads(line) for line in out.read_text().splitlines()]
    times = [e["time"] for e in runs["background"]]
    assert times == sorted(times)
    assert runs["background"] == runs["inline"]
    labels = [e["label"] for e in runs["inline"]]
    assert "stop" in labels and "go_left" in labels
