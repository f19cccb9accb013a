"""The rerun live view: a saved recording holds the expected entities on the source's time line
(read back with rerun's own reader); the view changes no event."""

from __future__ import annotations

import json
import sys
from itertools import pairwise

import pytest
from click.testing import CliRunner

from framefree.cli import cli

rr_chunk = pytest.importorskip("rerun.chunk", reason="pip install 'framefree[view]'")


def _contents(path) -> tuple[dict[str, int], set[str]]:
    """Rows logged per entity path, and every time line, of an .rrd file."""
    reader = rr_chunk.RrdReader(path)
    rows: dict[str, int] = {}
    timelines: set[str] = set()
    for chunk in reader.stream():
        rows[chunk.entity_path] = rows.get(chunk.entity_path, 0) + chunk.num_rows
        timelines.update(chunk.timeline_names)
    return rows, timelines


@pytest.mark.parametrize("command", ["evaluate-stream", "live"])
def test_saved_recording_holds_the_view(tiny, tmp_path, command):
    root, stream = tiny
    rrd, ev = tmp_path / "view.rrd", tmp_path / "ev.jsonl"
    args = (["evaluate-stream", "--stream", str(stream)] if command == "evaluate-stream" else
            ["live", "--source", str(stream), "--speed", "0", "--no-view"])
    res = CliRunner().invoke(cli, [*args, "--models", str(root), "--save", str(rrd),
                                   "--emit", f"jsonl:{ev}"])
    assert res.exit_code == 0, res.output
    rows, timelines = _contents(rrd)
    assert "source_time" in timelines
    gestures = ("go_left", "open_gripper")
    expected = {"/world/tracker", "/world/path", "/speed/motion", "/speed/cut",
                "/stop/angular_speed", "/stop/threshold", "/events",
                *(f"/distance/{g}" for g in gestures), *(f"/threshold/{g}" for g in gestures)}
    missing = expected - set(rows)
    assert not missing, sorted(rows)
    n_events = len(ev.read_text().splitlines())
    assert n_events > 0 and rows["/events"] == n_events
    from framefree.datasets import load_stream

    traj, _ = load_stream(stream)
    assert rows["/world/tracker"] >= len(traj)  # one pose per sample (plus its static part)


def _times(path, entity: str) -> list[float]:
    """Source times [s] of the rows logged on ``entity`` (static rows left out)."""
    out: list[float] = []
    for chunk in rr_chunk.RrdReader(path).stream():
        if chunk.entity_path == entity and not chunk.is_static:
            out += [v.value * 1e-9 for v in chunk.to_record_batch().column("source_time")]
    return sorted(out)


def test_threshold_lines_span_the_stream_without_a_row_per_pose(tiny, tmp_path):
    """A threshold is a constant: logged at the first pose, every 0.5 s of source time and at
    the last pose, so its line spans the stream without costing a row per pose."""
    from framefree.datasets import load_stream
    from framefree.view.rerun_view import RerunView

    root, stream = tiny
    rrd = tmp_path / "view.rrd"
    res = CliRunner().invoke(cli, ["evaluate-stream", "--stream", str(stream), "--models",
                                   str(root), "--save", str(rrd)])
    assert res.exit_code == 0, res.output
    traj, _ = load_stream(stream)
    poses = _times(rrd, "/world/tracker")  # the stream's poses (and the rest held after it)
    span = poses[-1] - poses[0]
    for entity in ("/threshold/go_left", "/stop/threshold"):
        times = _times(rrd, entity)
        assert times[0] == pytest.approx(poses[0]) and times[-1] == pytest.approx(poses[-1])
        assert max(b - a for a, b in pairwise(times)) <= RerunView.CONSTANT_EVERY + 0.05
        assert len(times) <= span / RerunView.CONSTANT_EVERY + 2 < len(traj) / 10


def test_view_does_not_change_the_events(tiny, tmp_path):
    root, stream = tiny
    out = []
    for extra in ([], ["--save", str(tmp_path / "v.rrd")]):
        path = tmp_path / f"ev{len(out)}.jsonl"
        res = CliRunner().invoke(cli, ["evaluate-stream", "--stream", str(stream), "--models",
                                       str(root), "--emit", f"jsonl:{path}", *extra])
        assert res.exit_code == 0, res.output
        out.append([json.loads(s) for s in path.read_text().splitlines()])
    assert out[0] == out[1]


def _listeners(port: int) -> set[str]:
    """Local addresses (hex, as /proc/net/tcp* writes them) of sockets listening on ``port``."""
    from pathlib import Path

    found = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in Path(table).read_text().splitlines()[1:]:
            local, state = line.split()[1], line.split()[3]
            addr, _, hexport = local.partition(":")
            if state == "0A" and int(hexport, 16) == port:
                found.add(addr)
    return found


@pytest.fixture
def loopback_server():
    """The real rerun program, started with the view's own arguments plus ``--serve-grpc`` (a
    server without a window, so it runs here): ``(port, process)``."""
    import subprocess
    import time

    from cli_helpers import free_port
    from framefree.view.viewer import _listening, viewer_command

    port = free_port()
    proc = subprocess.Popen([*viewer_command(port), "--serve-grpc"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        for _ in range(400):
            if _listening(port) or proc.poll() is not None:
                break
            time.sleep(0.05)
        assert proc.poll() is None and _listening(port)
        yield port, proc
    finally:
        proc.terminate()
        proc.wait(timeout=10)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/net")
def test_viewer_listens_on_loopback_only(loopback_server):
    port, _ = loopback_server
    assert _listeners(port) == {"0100007F"}  # 127.0.0.1, and no 0.0.0.0 or :: socket


def test_view_streams_to_a_running_viewer_and_closes(tiny, loopback_server, monkeypatch):
    """``--view rerun`` reuses a viewer already listening on 127.0.0.1 (no display needed) and
    the command ends normally."""
    monkeypatch.delenv("DISPLAY", raising=False)
    port, proc = loopback_server
    monkeypatch.setattr("framefree.view.viewer.DEFAULT_PORT", port)
    root, stream = tiny
    res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", str(stream),
                                   "--speed", "0", "--view", "rerun"])
    assert res.exit_code == 0, res.output
    assert proc.poll() is None  # the viewer is the user's: it keeps running


def _live_rerun(stream, root, env_display: str | None):
    """``framefree live --view rerun`` in a child process (so that a hang cannot hold the suite)."""
    import os
    import subprocess

    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    if env_display is not None:
        env["DISPLAY"] = env_display
    code = "from framefree.cli import main; main()"
    return subprocess.run([sys.executable, "-c", code, "live", "--models", str(root),
                           "--source", str(stream), "--speed", "1", "--view", "rerun"],
                          capture_output=True, text=True, env=env, timeout=120)


@pytest.mark.parametrize("display", [None, ":987"], ids=["no-display", "unreachable-display"])
def test_view_that_cannot_start_is_one_line(tiny, display):
    """No display, or a display the real viewer cannot open: exit 2 with one line naming
    ``--save`` and nothing half-started left behind (the command is never stuck)."""
    root, stream = tiny
    proc = _live_rerun(stream, root, display)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "--view rerun" in lines[0] and "--save" in lines[0], lines
    assert "127.0.0.1" in lines[0]


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_ctrl_c_ends_a_live_view(tiny, loopback_server):
    """Ctrl-C (SIGINT) during a real-time replay into a viewer ends the command normally (the
    signal is sent once the first event shows that the replay loop runs)."""
    import os
    import signal
    import subprocess
    import time

    port, _ = loopback_server
    root, stream = tiny
    code = ("import framefree.view.viewer as v; v.DEFAULT_PORT = int(__import__('sys').argv[1]); "
            "import sys; sys.argv = sys.argv[1:]; from framefree.cli import main; main()")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    proc = subprocess.Popen(
        [sys.executable, "-c", code, str(port), "live", "--models", str(root), "--source",
         str(stream), "--speed", "1", "--view", "rerun"], stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True, env=env,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        first = proc.stdout.readline()  # the first event: poses are being replayed into the view
        assert " s  " in first, first
        time.sleep(0.2)
        assert proc.poll() is None  # still replaying (the session lasts tens of seconds)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    assert " poses; " in err and "Traceback" not in err


def test_threshold_lines_are_logged_again_when_the_source_clock_restarts(tiny, tmp_path):
    """A source whose clock starts again (a replayed file, a restarted publisher) gets its
    threshold lines at once, not 0.5 s after the old clock's last time."""
    from framefree.online import Recognizer
    from framefree.view.rerun_view import RerunView

    root, _ = tiny
    rec = Recognizer.from_dataset(root, model_context="original_1")
    rrd = tmp_path / "restart.rrd"
    view = RerunView(rec, save=rrd)
    p, q = [0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]
    for t in (1000.0, 1000.1, 0.0, 0.1):
        view.update(t, p, q, [])
    view.close()
    for gesture in rec.gestures:
        assert _times(rrd, f"/threshold/{gesture}") == pytest.approx([0.0, 0.1, 1000.0])
