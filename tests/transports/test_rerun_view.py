"""The rerun live view: a saved recording holds the expected entities on the source's time line
(read back with rerun's own reader); the view changes no event."""

from __future__ import annotations

import json

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
