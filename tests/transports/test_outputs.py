"""Event outputs: the record, JSON lines, OSC received by a python-osc server on 127.0.0.1."""

from __future__ import annotations

import json
import threading

import pytest

from framefree.errors import FramefreeError
from framefree.io.osc import parse_osc_spec
from framefree.io.outputs import Emitters, event_record, open_emitter
from framefree.online import Event


def test_event_record_carries_label_time_distance_threshold():
    rec = event_record(Event("go_left", 12.5, 0.031, 4), {"go_left": 0.05})
    assert rec == {"label": "go_left", "time": 12.5, "distance": 0.031, "threshold": 0.05, "model": 4}
    stop = event_record(Event("stop", 3.0, -1.0), {"go_left": 0.05})
    assert stop["distance"] is None and stop["threshold"] is None and stop["label"] == "stop"


def test_jsonl_file(tmp_path):
    out = Emitters([f"jsonl:{tmp_path / 'ev.jsonl'}"], {"a": 0.1})
    out(Event("a", 1.0, 0.05, 0))
    out(Event("stop", 2.0, -1.0))
    out.close()
    lines = [json.loads(s) for s in (tmp_path / "ev.jsonl").read_text().splitlines()]
    assert [r["label"] for r in lines] == ["a", "stop"] and lines[0]["threshold"] == 0.1


@pytest.mark.parametrize("bad", ["udp://x", "osc://127.0.0.1/x", "osc://host:99999/a",
                                 "osc://255.255.255.255:9000/a", "osc://224.0.0.1:9000/a", "jsonl:"])
def test_bad_specs_are_one_line_errors(bad):
    with pytest.raises(FramefreeError):
        open_emitter(bad)


def test_osc_spec():
    assert parse_osc_spec("osc://127.0.0.1:9000/gesture") == ("127.0.0.1", 9000, "/gesture")
    assert parse_osc_spec("osc://localhost:9000") == ("localhost", 9000, "/framefree/event")


def test_osc_server_on_loopback_receives_events(loopback_only):
    from pythonosc.dispatcher import Dispatcher
    from pythonosc.osc_server import ThreadingOSCUDPServer

    got: list[tuple] = []
    done = threading.Event()

    def handler(address, *args):
        got.append((address, *args))
        if len(got) == 2:
            done.set()

    disp = Dispatcher()
    disp.map("/gesture", handler)
    server = ThreadingOSCUDPServer(("127.0.0.1", 0), disp)
    port = server.server_address[1]
    th = threading.Thread(target=server.serve_forever, daemon=True)
    th.start()
    try:
        out = Emitters([f"osc://127.0.0.1:{port}/gesture"], {"go_left": 0.05})
        out(Event("go_left", 12.5, 0.03125, 1))
        out(Event("stop", 13.0, -1.0))
        out.close()
        assert done.wait(5.0), got
    finally:
        server.shutdown()
        server.server_close()
        th.join(5)
    assert got[0] == ("/gesture", "go_left", 12.5, pytest.approx(0.03125), pytest.approx(0.05))
    assert got[1][:2] == ("/gesture", "stop") and got[1][3] == -1.0


@pytest.mark.parametrize("bad", ["udp://x", "osc://127.0.0.1/x", "osc://224.0.0.1:9000/a", "jsonl:",
                                 "lsl://"])
def test_bad_emit_is_refused_before_the_models(tiny, bad):
    from click.testing import CliRunner

    from framefree.cli import cli

    root, stream = tiny
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(root), "--stream", str(stream),
                                   "--emit", bad])
    assert res.exit_code == 2 and "--emit" in res.output
    assert "building the gesture models" not in res.output


@pytest.mark.parametrize("command", ["evaluate-stream", "live"])
def test_jsonl_to_stdout_keeps_stdout_pure_json(tiny, command):
    """With ``--emit jsonl:-`` every stdout line parses as an event; the summary goes to stderr."""
    from click.testing import CliRunner

    from framefree.cli import cli

    root, stream = tiny
    args = (["evaluate-stream", "--stream", str(stream)] if command == "evaluate-stream" else
            ["live", "--source", str(stream), "--speed", "0"])
    res = CliRunner().invoke(cli, [*args, "--models", str(root), "--emit", "jsonl:-"])
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    assert lines, res.stderr
    records = [json.loads(line) for line in lines]
    assert {"go_left", "open_gripper"} <= {r["label"] for r in records}
    summary = "all: TP" if command == "evaluate-stream" else " poses; "
    assert summary in res.stderr and summary not in res.stdout
