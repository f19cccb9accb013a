"""Lab Streaming Layer with pylsl's own liblsl: a replica session goes out of an outlet, `framefree
live` reads it through an inlet and sends events to a marker stream; they match `evaluate-stream`
on the same file. Nothing may leave loopback (the ``loopback_only`` guard)."""

from __future__ import annotations

import json
import os
import threading
import uuid

import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.datasets import load_stream
from framefree.io.lsl import configure_liblsl, import_pylsl, lsl_config


def test_configuration_keeps_discovery_on_this_machine():
    path = configure_liblsl()
    if path is None:
        pytest.skip("LSLAPICFG set by the user: framefree leaves it alone")
    assert os.environ["LSLAPICFG"] == str(path)
    text = path.read_text()
    assert text == lsl_config(path.parent)
    assert "ResolveScope = machine" in text and "KnownPeers = {127.0.0.1}" in text


def _publish(pylsl, traj, name: str, ready: threading.Event, done: threading.Event,
             log: dict) -> None:
    """Outlet of 7 double channels (x y z qw qx qy qz), time-stamped with the file's times; it
    stays open until ``done`` (liblsl drops what an outlet had not sent when it is destroyed)."""
    info = pylsl.StreamInfo(name, "MoCap", 7, 50.0, pylsl.cf_double64, f"test-{name}")
    outlet = pylsl.StreamOutlet(info)
    log["consumer"] = outlet.wait_for_consumers(60.0)
    log["ready"] = ready.wait(60.0)
    for k in range(len(traj)):
        outlet.push_sample([*traj.p[k], *traj.q[k]], float(traj.t[k]))
    log["sent"] = len(traj)
    done.wait(120.0)
    del outlet


def test_lsl_in_markers_out_match_evaluate_stream(tiny, tmp_path, loopback_only):
    pylsl = import_pylsl()
    root, stream = tiny
    traj, _ = load_stream(stream)
    poses, markers = f"ff-poses-{uuid.uuid4().hex[:8]}", f"ff-events-{uuid.uuid4().hex[:8]}"
    ready, done, log, result = threading.Event(), threading.Event(), {}, {}
    pub = threading.Thread(target=_publish, args=(pylsl, traj, poses, ready, done, log),
                           daemon=True)
    pub.start()

    def run_live():
        result["live"] = CliRunner().invoke(cli, [
            "live", "--models", str(root), "--source", f"lsl://{poses}", "--timeout", "5",
            "--no-view", "--emit", f"lsl://{markers}", "--emit", f"jsonl:{tmp_path / 'live.jsonl'}"])

    live = threading.Thread(target=run_live, daemon=True)
    live.start()
    found = pylsl.resolve_byprop("name", markers, 1, 60.0)
    assert found, "the marker stream did not appear"
    inlet = pylsl.StreamInlet(found[0])
    inlet.open_stream(10.0)
    ready.set()
    got = []
    while True:  # until `live` has ended (5 s after the last pose) and no marker is left
        sample, ts = inlet.pull_sample(timeout=0.5)
        if ts is not None:
            got.append((json.loads(sample[0]), ts))
        elif not live.is_alive():
            break
    live.join(60)
    done.set()
    pub.join(10)
    assert not live.is_alive() and not pub.is_alive()
    res = result["live"]
    assert res.exit_code == 0, res.output
    assert log["consumer"] and log["sent"] == len(traj)

    ev = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(root), "--stream", str(stream),
                                  "--emit", f"jsonl:{tmp_path / 'eval.jsonl'}"])
    assert ev.exit_code == 0, ev.output
    expected = [json.loads(s) for s in (tmp_path / "eval.jsonl").read_text().splitlines()]
    assert any(r["label"] != "stop" for r in expected), "the session should hold gestures"
    markers_got = [m for m, _ in got]
    assert markers_got == expected, res.output
    assert [ts for _, ts in got] == [r["time"] for r in expected]
    live_lines = [json.loads(s) for s in (tmp_path / "live.jsonl").read_text().splitlines()]
    assert live_lines == markers_got
    for r in expected:
        if r["label"] != "stop":
            assert r["distance"] <= r["threshold"]


#: a sender that ends its outlet after 40 poses while framefree's source still reads (the normal
#: end of a stream); run in a child process, so that liblsl loads with framefree's configuration
_SENDER_ENDS = """
import sys, threading, time, uuid
from framefree.io.lsl import LslSource, import_pylsl
pylsl = import_pylsl()
name = f"ff-end-{uuid.uuid4().hex[:8]}"

def send():
    outlet = pylsl.StreamOutlet(pylsl.StreamInfo(name, "MoCap", 7, 50.0, pylsl.cf_double64, name))
    outlet.wait_for_consumers(30.0)
    for k in range(40):
        outlet.push_sample([0.0, 0.0, 0.01 * k, 1.0, 0.0, 0.0, 0.0], 100.0 + 0.02 * k)
        time.sleep(0.002)
    time.sleep(0.3)
    del outlet

sender = threading.Thread(target=send)
sender.start()
source = LslSource(name, timeout=10.0)
print(sum(1 for _ in source), source.timed_out)
sender.join()
time.sleep(0.5)
"""


def test_the_normal_end_of_a_stream_prints_no_error(loopback_only):
    """liblsl's 'Stream transmission broke off' at a sender's normal end goes to framefree's
    liblsl log, not to the console; every pose arrived and the source ended without a timeout."""
    import importlib.util
    import subprocess
    import sys

    if importlib.util.find_spec("pylsl") is None:  # not imported here: liblsl is configured first
        pytest.skip("pip install 'framefree[lsl]'")
    env = {k: v for k, v in os.environ.items() if k != "LSLAPICFG"}
    proc = subprocess.run([sys.executable, "-c", _SENDER_ENDS], capture_output=True, text=True,
                          env=env, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["40", "False"]
    assert "ERR|" not in proc.stderr and "broke off" not in proc.stderr, proc.stderr
