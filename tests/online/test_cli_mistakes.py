"""Mistakes with the live commands: one line, exit status 2, no traceback; the source is checked
before the models are built; either model layout is accepted and named."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
import zmq

from cli_helpers import free_port, one_line_error, run
from framefree.replica import make_stream, save_stream, synthesize_gesture

GESTURES = ("go_left", "open_gripper")





@pytest.fixture(scope="module")
def data(tmp_path_factory) -> dict[str, Path]:
    """A dataset root, the same recordings as a <label>/*.csv folder, and a labelled stream."""
    root = tmp_path_factory.mktemp("live_mistakes")
    rng = np.random.default_rng(11)
    for g in GESTURES:
        (root / "ds" / g / "original_1").mkdir(parents=True)
        (root / "flat" / g).mkdir(parents=True)
        for k in range(3):
            path = root / "ds" / g / "original_1" / f"trial_{k + 1}.csv"
            synthesize_gesture(g, rng).to_csv(path)
            shutil.copy(path, root / "flat" / g / path.name)
    traj, segs = make_stream(5, sequence=list(GESTURES))
    stream = save_stream(root / "stream.csv", traj, segs)
    return {"ds": root / "ds", "flat": root / "flat", "stream": stream}


def test_a_bad_source_is_reported_before_the_models_are_built(data):
    for source, fragment in (
        ("zmq://192.168.1.2:5556", "only loopback endpoints are allowed"),
        ("no_such_file.csv", "not a file, and not zmq://127.0.0.1:PORT"),
    ):
        res = run("live", "--models", data["ds"], "--source", source, "--no-view")
        one_line_error(res, fragment)
        assert "models:" not in res.output and "building" not in res.output


def test_live_says_so_when_no_pose_arrives(data):
    port = free_port()
    res = run("live", "--models", data["ds"], "--source", f"zmq://127.0.0.1:{port}",
              "--timeout", "0.5", "--no-view", "--threshold", "0.5")
    one_line_error(res, f"zmq://127.0.0.1:{port}: no pose arrived within 0.5 s",
                   "framefree stream")


def test_stream_on_a_busy_port(data):
    port = free_port()
    sock = zmq.Context.instance().socket(zmq.PUB)
    sock.bind(f"tcp://127.0.0.1:{port}")
    try:
        res = run("stream", data["stream"], "--port", port, "--join-wait", "0")
    finally:
        sock.close(0)
    one_line_error(res, f"tcp://127.0.0.1:{port}: the port is already in use", "--port")


@pytest.mark.parametrize(("layout", "named"), [
    ("ds", "dataset root, context 'original_1'"),
    ("flat", "folder of <label>/*.csv recordings"),
])
def test_either_model_layout_is_accepted_and_named(data, layout, named):
    res = run("live", "--models", data[layout], "--source", data["stream"], "--speed", "0",
              "--no-view")
    assert res.exit_code == 0, res.output
    assert named in res.output and "6 recordings of 2 labels" in res.output
    # the per-gesture thresholds in force are printed, not one
    assert "thresholds go_left " in res.output and ", open_gripper " in res.output


def test_one_threshold_given_is_printed_as_one(data):
    res = run("live", "--models", data["flat"], "--source", data["stream"], "--speed", "0",
              "--no-view", "--threshold", "0.25")
    assert res.exit_code == 0, res.output
    assert "threshold 0.25," in res.output


def test_evaluate_stream_checks_outputs_first(data, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    res = run("evaluate-stream", "--models", data["ds"], "--stream", data["stream"], "--json",
              blocker / "out.json")
    one_line_error(res, "--json")
    assert "models:" not in res.output


def test_latency_min_help_states_the_real_default():
    res = run("live", "--help")
    assert "smallest latency searched (default: 0)" in " ".join(res.output.split())
    assert "issue" not in res.output.lower()


@pytest.mark.parametrize("flag", ["--hand-frame", "--no-hand-frame"])
def test_hand_frame_is_refused_where_it_does_not_apply(data, flag):
    res = run("evaluate-stream", "--models", data["ds"], "--stream", data["stream"],
              flag, "--method", "paper")
    one_line_error(res, f"{flag} applies to --method segments")


@pytest.mark.parametrize(("flag", "expected"), [(None, True), (True, True), (False, False)])
def test_hand_frame_reaches_the_recognizer(data, flag, expected):
    """``--hand-frame``/``--no-hand-frame`` as the command line passes them (None: neither);
    False is a choice, not an unset flag."""
    from framefree.commands.online import _recognizer

    rec = _recognizer(str(data["ds"]), "original_1", "wxyz", "m", hand_frame=flag)
    assert rec.config.hand_frame is expected


def test_evaluate_stream_runs_without_hand_frame(data):
    res = run("evaluate-stream", "--models", data["ds"], "--stream", data["stream"],
              "--no-hand-frame")
    assert res.exit_code == 0, res.output
    assert "F1" in res.output
