"""``evaluate-stream`` and ``live`` with two trackers: people folders as models, multi-tracker
CSV streams and sources, and the one-line errors when trackers do not fit."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cli_helpers import one_line_error, run, tiny_dataset
from framefree.datasets.multi_sessions import continuous_session
from framefree.datasets.people_layout import load_people
from framefree.datasets.stream_files import write_labels
from framefree.io.multicsv import write_multi_csv
from real_data import SHIPPED_MACHETE

PEOPLE = str(SHIPPED_MACHETE)


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    """A two-controller session of Sub_U001's hooks and uppercuts (named right and left, as
    ../shared/data/machete_streams names them), and a single-tracker dataset with its stream."""
    root = tmp_path_factory.mktemp("multi_cli")
    takes = [r for r in load_people(SHIPPED_MACHETE).of(["Sub_U001"])
             if r.gesture.startswith(("hook", "uppercut"))]
    sample, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                          rate=60.0, seed=3)
    sample = type(sample)(sample.trackers, ("right", "left"), sample.up, "session")
    session = write_multi_csv(root / "session.csv", sample)
    write_labels(root / "session_labels.csv", segments)
    single = tiny_dataset(root / "single", ("go_left", "open_gripper"), ("go_left",))
    return {"session": session, "single_models": root / "single", "single_stream": single}


def test_evaluate_stream_with_people_as_models_and_a_two_tracker_session(files, tmp_path):
    out = tmp_path / "eval.json"
    res = run("evaluate-stream", "--models", PEOPLE, files["session"], "--json", out,
              "--gestures", "hook_left,hook_right,uppercut_left,uppercut_right")
    assert res.exit_code == 0, res.output
    assert "a folder of 2 people <person>/<gesture>/<recording>" in res.output
    assert "matched by position: right as controller_0, left as controller_1" in res.output
    total = json.loads(out.read_text())["total"]
    assert total["tp"] + total["fn"] == 8
    assert total["tp"] >= 6 and total["fp"] <= 2, total
    assert set(total["gestures"]) == {"hook_left", "hook_right", "uppercut_left", "uppercut_right"}


def test_live_replays_a_two_tracker_csv(files):
    res = run("live", "--models", PEOPLE, "--source", files["session"], "--speed", "0",
              "--no-view", "--emit", "jsonl:-")
    assert res.exit_code == 0, res.output
    records = [json.loads(ln) for ln in res.stdout.splitlines() if ln.startswith("{")]
    assert len(records) >= 6
    hits = [r for r in records if r["label"].startswith(("hook", "uppercut"))]
    assert len(hits) >= 6, records


def test_a_single_tracker_stream_with_two_tracker_models_is_one_line(files):
    res = run("evaluate-stream", "--models", PEOPLE, files["single_stream"])
    one_line_error(res, "stream.csv: 1 tracker, but the models have several")
    assert "building" not in res.output


def test_a_two_tracker_stream_with_single_tracker_models_is_one_line(files):
    res = run("evaluate-stream", "--models", files["single_models"], files["session"])
    one_line_error(res, "session.csv: 2 trackers, but the models have one")
    assert "building" not in res.output


def test_live_from_a_two_tracker_csv_with_single_tracker_models_is_one_line(files):
    res = run("live", "--models", files["single_models"], "--source", files["session"],
              "--no-view")
    one_line_error(res, "session.csv: 2 trackers, but the models have one")
    assert "building" not in res.output


def test_a_one_tracker_source_with_two_tracker_models_is_refused_before_building(files):
    res = run("live", "--models", PEOPLE, "--source", "ros2:///hand_pose", "--no-view")
    one_line_error(res, "this source carries one tracker, and the models have several")
    assert "building" not in res.output


def test_invariance_is_for_several_trackers(files):
    res = run("evaluate-stream", "--models", files["single_models"], files["single_stream"],
              "--invariance", "gravity")
    one_line_error(res, "--invariance applies to models of several trackers")


def test_the_rerun_view_shows_both_trackers(files, tmp_path):
    """`--save` records each controller's frame and path, the combined speed, the stop detector
    and every event; the view changes no event."""
    rr_chunk = pytest.importorskip("rerun.chunk", reason="pip install 'framefree[view]'")
    rrd, ev = tmp_path / "view.rrd", tmp_path / "ev.jsonl"
    res = run("live", "--models", PEOPLE, "--source", files["session"], "--speed", "0",
              "--no-view", "--save", rrd, "--emit", f"jsonl:{ev}")
    assert res.exit_code == 0, res.output
    rows: dict[str, int] = {}
    for chunk in rr_chunk.RrdReader(rrd).stream():
        rows[chunk.entity_path] = rows.get(chunk.entity_path, 0) + chunk.num_rows
    expected = {"/world/controller_0", "/world/controller_0/path", "/world/controller_1",
                "/world/controller_1/path", "/speed/motion", "/speed/cut", "/stop/angular_speed",
                "/events", "/distance/hook_left", "/threshold/uppercut_right"}
    assert expected <= set(rows), sorted(rows)
    assert "/world/tracker" not in rows
    n_events = len(ev.read_text().splitlines())
    assert n_events >= 6 and rows["/events"] == n_events
    plain = run("live", "--models", PEOPLE, "--source", files["session"], "--speed", "0",
                "--no-view", "--emit", f"jsonl:{tmp_path / 'plain.jsonl'}")
    assert plain.exit_code == 0

    def strip(path):
        return [{k: v for k, v in json.loads(ln).items() if k != "wall_time"}
                for ln in path.read_text().splitlines()]

    assert strip(ev) == strip(tmp_path / "plain.jsonl")


def test_record_cuts_a_two_tracker_recording_into_takes_for_live(tmp_path):
    """`framefree record` on a multi-tracker CSV of four real hooks writes four multi-tracker
    takes to LIBRARY/GESTURE/, a --models folder and a source of `enroll`."""
    takes = [r for r in load_people(SHIPPED_MACHETE) if r.gesture == "hook_left"]
    sample, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                          rate=90.0, seed=5)
    recording = write_multi_csv(tmp_path / "hooks.csv", sample)
    library = tmp_path / "lib"
    res = run("record", "--source", recording, "--gesture", "hook_left", "--library", library)
    assert res.exit_code == 0, res.output
    written = sorted((library / "hook_left").glob("trial_*.csv"))
    assert len(written) == len(segments) == 4
    from framefree.io.multicsv import read_multi_csv

    for path, seg in zip(written, segments, strict=True):
        take = read_multi_csv(path)
        assert take.n_trackers == 2
        assert 0.8 * (seg.end_t - seg.start_t) < take.t[-1] - take.t[0] < seg.end_t - seg.start_t + 3.0
    # enroll and check take this folder: tests/library/test_multi_library.py


def test_compare_is_refused_for_two_trackers_before_building(files):
    res = run("evaluate-stream", "--models", PEOPLE, files["session"], "--compare")
    one_line_error(res, "the paper's recognizer takes one tracker")
    assert "building" not in res.output


def test_the_command_line_offers_every_invariance():
    from framefree.commands.online import INVARIANCES as OFFERED
    from framefree.descriptors.canonical import INVARIANCES

    assert OFFERED == INVARIANCES


def test_evaluate_stream_explains_the_misses_of_a_two_tracker_session(files, tmp_path):
    """--explain with two trackers: a threshold no gesture meets, and every miss says why."""
    from framefree.online.diagnosis import MISS_REASONS

    out = tmp_path / "eval.json"
    res = run("evaluate-stream", "--models", PEOPLE, files["session"], "--json", out,
              "--gestures", "hook_left,hook_right", "--threshold", "1e-9", "--explain")
    assert res.exit_code == 0, res.output
    data = json.loads(out.read_text())
    why = next(iter(data["streams"].values()))["explain"]
    assert data["total"]["tp"] == 0 and len(why["missed"]) == data["total"]["fn"] == 4
    assert {m["reason"] for m in why["missed"]} <= set(MISS_REASONS)
    assert any(m["reason"] == "beyond its threshold" for m in why["missed"]), why["missed"]
    assert "misses by reason:" in res.output
