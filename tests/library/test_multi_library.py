"""Gesture libraries of several trackers: ``record`` -> ``enroll`` -> ``check`` -> ``live``, on
the shipped real Machete Vive recordings (two controllers), and the one-line errors."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np
import pytest

from cli_helpers import one_line_error, run, tiny_dataset
from framefree.datasets.multi_sessions import continuous_session
from framefree.datasets.people_layout import load_people
from framefree.datasets.stream_files import write_labels
from framefree.io.multicsv import write_multi_csv
from framefree.library import load_library
from framefree.library.long_rests import long_rest
from framefree.library.multi_library import (
    MultiTakeSet,
    enroll_multi,
    load_multi_library,
    multi_fingerprint,
    read_multi_takes,
)
from framefree.online import Recognizer
from framefree.online.multi import MultiRecognizer
from real_data import SHIPPED_MACHETE

GESTURES = ("hook_left", "uppercut_left", "hook_right")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> dict[str, Path]:
    """A library folder written by `framefree record` from multi-tracker recordings of three
    gestures (the two shipped people's takes, played one after another), the library file
    `enroll` makes of it, and a session of Sub_U001's takes of the same gestures."""
    root = tmp_path_factory.mktemp("multi_library")
    people = load_people(SHIPPED_MACHETE)
    library = root / "lib"
    for k, g in enumerate(GESTURES):
        takes = [r for r in people if r.gesture == g]
        sample, _ = continuous_session([r.sample for r in takes], [g] * len(takes), rate=90.0,
                                       seed=11 + k)
        sample = type(sample)(sample.trackers, ("right", "left"), sample.up, g)
        recording = write_multi_csv(root / f"{g}.csv", sample)
        res = run("record", "--source", recording, "--gesture", g, "--library", library)
        assert res.exit_code == 0, res.output
    takes = [r for r in people.of(["Sub_U001"]) if r.gesture in GESTURES]
    session, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                           rate=60.0, seed=3)
    session = type(session)(session.trackers, ("right", "left"), session.up, "session")
    stream = write_multi_csv(root / "session.csv", session)
    write_labels(root / "session_labels.csv", segments)
    res = run("enroll", library, "-o", root / "lib.npz")
    assert res.exit_code == 0, res.output
    return {"root": root, "library": library, "file": root / "lib.npz", "session": stream}


def test_enroll_writes_a_library_of_two_trackers(recorded):
    lib = load_multi_library(recorded["file"])
    assert lib.takes.trackers == ("right", "left")
    assert lib.invariance == "gravity"
    assert set(lib.gestures) == set(GESTURES)
    assert all(n == 4 for n in lib.takes.counts().values())
    assert lib.takes.names[0].split("/")[1].startswith("trial_")
    with zipfile.ZipFile(recorded["file"]) as zf:
        meta = json.loads(zf.read("library.json"))
    assert meta["trackers"] == ["right", "left"] and meta["invariance"] == "gravity"


def test_a_loaded_library_restores_the_recognizer_without_recalibrating(recorded):
    """The library's recognizer equals one built from the recorded folder: same thresholds, stop
    threshold, limits; loading computes no distance matrix of the takes."""
    takes = read_multi_takes(recorded["library"])
    fresh = MultiRecognizer.from_samples(list(takes.as_stored().takes), list(takes.labels))
    lib = load_multi_library(recorded["file"])
    restored = lib.recognizer()
    assert restored.gesture_thresholds == pytest.approx(fresh.gesture_thresholds, rel=1e-12)
    assert restored.stop_threshold == pytest.approx(fresh.stop_threshold)
    assert restored.config == fresh.config
    assert restored.gate_speeds == fresh.gate_speeds
    # nothing is left to derive: the thresholds are never computed again when restoring
    import framefree.online.multi as multi

    before = multi.multi_thresholds, multi.continuation_waits
    multi.multi_thresholds = lambda *a, **k: pytest.fail("recalibrated")
    multi.continuation_waits = lambda *a, **k: pytest.fail("waits measured again")
    try:
        again = lib.recognizer()
    finally:
        multi.multi_thresholds, multi.continuation_waits = before
    assert again.learned_.continuations == fresh.learned_.continuations
    np.testing.assert_array_equal(again.spotter.model_waits, fresh.spotter.model_waits)


def test_a_library_saved_before_the_learned_waits_learns_them_on_loading(recorded, tmp_path):
    """A library file without ``continuations`` (framefree before v24) loads; the waits are
    measured on its takes then, and its provenance says so."""
    older = tmp_path / "older.npz"
    with zipfile.ZipFile(recorded["file"]) as zin, zipfile.ZipFile(older, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "library.json":
                meta = json.loads(data)
                meta["learned"].pop("continuations")
                meta["learned"]["provenance"]["rules"].pop("continuations")
                data = json.dumps(meta).encode()
            zout.writestr(item, data)
    restored = load_multi_library(older).recognizer()
    current = load_multi_library(recorded["file"]).recognizer()
    assert restored.learned_.continuations == current.learned_.continuations
    assert "continuations learned on loading" in restored.learned_.provenance.note


def test_live_with_the_library_file_gives_the_events_of_the_folder(recorded):
    outs = []
    for models in (recorded["library"], recorded["file"]):
        res = run("live", "--models", models, "--source", recorded["session"], "--speed", "0",
                  "--no-view", "--emit", "jsonl:-")
        assert res.exit_code == 0, res.output
        outs.append([json.loads(ln) for ln in res.stdout.splitlines() if ln.startswith("{")])
    assert "several trackers" in res.output
    strip = [[{k: v for k, v in e.items() if k != "wall_time"} for e in o] for o in outs]
    assert strip[0] == strip[1]
    assert sum(e["label"] in GESTURES for e in outs[1]) >= 4


def test_evaluate_stream_takes_the_library_file(recorded, tmp_path):
    out = tmp_path / "eval.json"
    res = run("evaluate-stream", "--models", recorded["file"], recorded["session"], "--json", out)
    assert res.exit_code == 0, res.output
    total = json.loads(out.read_text())["total"]
    assert total["tp"] + total["fn"] == 6 and total["tp"] >= 4, total


def test_enroll_is_up_to_date_then_adds_removes_and_merges(recorded, tmp_path):
    file = tmp_path / "lib.npz"
    assert run("enroll", recorded["library"], "-o", file).exit_code == 0
    res = run("enroll", recorded["library"], "-o", file)
    assert res.exit_code == 0 and "up to date" in res.output
    res = run("enroll", file, "--remove", "hook_right", "--remove", "hook_left/trial_1", "-o", file)
    assert res.exit_code == 0, res.output
    lib = load_multi_library(file)
    assert lib.takes.counts() == {"hook_left": 3, "uppercut_left": 4}
    # the same gestures from a second source need --merge; new ones do not
    res = run("enroll", file, recorded["library"], "-o", file)
    one_line_error(res, "gesture 'hook_left' is in both", "--merge hook_left")
    res = run("enroll", file, recorded["library"], "--merge", "hook_left", "--merge",
              "uppercut_left", "-o", file)
    assert res.exit_code == 2  # now the copies of the same takes are refused
    assert "exact copy" in res.output and "Traceback" not in res.output


def test_enroll_keeps_the_invariance_and_settings_of_a_library_file(recorded, tmp_path):
    file = tmp_path / "full.npz"
    res = run("enroll", recorded["library"], "--invariance", "full", "--set", "max_wait=0.8",
              "-o", file)
    assert res.exit_code == 0, res.output
    res = run("enroll", file, "--remove", "hook_right", "-o", tmp_path / "again.npz")
    assert res.exit_code == 0, res.output
    again = load_multi_library(tmp_path / "again.npz")
    assert again.invariance == "full" and again.settings["max_wait"] == 0.8
    assert again.recognizer_config().max_wait == 0.8


def test_enroll_people_folder_as_published(tmp_path):
    """The Machete people layout, <person>/<gesture>/<recording>, is a source too."""
    file = tmp_path / "people.npz"
    res = run("enroll", SHIPPED_MACHETE, "-o", file, "--invariance", "full")
    assert res.exit_code == 0, res.output
    lib = load_multi_library(file)
    assert len(lib.takes) == 28 and lib.takes.names[0].startswith("Sub_U001/")
    assert lib.invariance == "full"


def test_check_a_library_of_two_trackers(recorded, tmp_path):
    for library in (recorded["library"], recorded["file"]):
        res = run("check", library, "--out", tmp_path)
        assert res.exit_code in (0, 1), res.output
        assert "2 trackers (right, left), invariance gravity" in res.output
        for g in GESTURES:
            assert g in res.output
    report = json.loads((tmp_path / "lib_check.json").read_text())
    assert report["trackers"] == ["right", "left"]
    assert {t["gesture"] for t in report["takes"]} == set(GESTURES)
    assert sum(t["loo"] == t["gesture"] for t in report["takes"]) >= 8
    assert (tmp_path / "lib_gallery_left.png").is_file()
    assert (tmp_path / "lib_distances.png").is_file()


def test_python_readers_of_one_tracker_refuse_a_multi_library(recorded):
    from framefree.errors import FramefreeError

    for load in (load_library, Recognizer.load):
        with pytest.raises(FramefreeError, match="several trackers"):
            load(recorded["file"])


def test_fingerprint_depends_on_invariance(recorded):
    takes = read_multi_takes(recorded["library"])
    from framefree.online.config import RecognizerConfig

    c = RecognizerConfig()
    assert multi_fingerprint(takes, c, "gravity") != multi_fingerprint(takes, c, "full")
    assert multi_fingerprint(takes, c, "gravity") == load_multi_library(recorded["file"]).fingerprint


def test_one_tracker_and_several_do_not_mix(recorded, tmp_path):
    single = tmp_path / "single"
    tiny_dataset(single, ("go_left", "open_gripper"), ("go_left",))
    one_line_error(run("enroll", single, recorded["library"], "-o", tmp_path / "x.npz"),
                   "holds takes of one tracker", "of several")
    one_line_error(run("enroll", single, "--invariance", "full", "-o", tmp_path / "x.npz"),
                   "--invariance applies to takes of several trackers")
    one_line_error(run("enroll", recorded["library"], "--context", "own", "-o", tmp_path / "x.npz"),
                   "--context does not apply")
    one_line_error(run("enroll", recorded["library"], "--up", "+z", "-o", tmp_path / "x.npz"),
                   "not a setting of a library of several trackers")


def test_bad_take_and_bad_library_are_one_line(recorded, tmp_path):
    import shutil

    broken = tmp_path / "broken"
    shutil.copytree(recorded["library"], broken)
    take = broken / "hook_left" / "trial_2.csv"
    lines = take.read_text().splitlines()
    lines[5] = lines[5].replace(",", ",nan", 1)
    take.write_text("\n".join(lines) + "\n")
    one_line_error(run("enroll", broken, "-o", tmp_path / "b.npz"), "trial_2.csv", "row 6")
    other = tmp_path / "other"
    shutil.copytree(recorded["library"], other)
    (other / "odd").mkdir()
    from framefree.core.multitrajectory import MultiTrajectory

    s = read_multi_takes(recorded["library"]).takes[0]
    write_multi_csv(other / "odd" / "trial_1.csv",
                    MultiTrajectory(s.trackers[:1], ("right",), s.up, "one"))
    # a take of one tracker among takes of two
    one_line_error(run("enroll", other, "-o", tmp_path / "b.npz"), "1 trackers", "same trackers")
    # a library file whose rows do not fit its trackers
    bad = tmp_path / "bad.npz"
    with zipfile.ZipFile(recorded["file"]) as zin, zipfile.ZipFile(bad, "w") as zout:
        for item in zin.namelist():
            data = zin.read(item)
            if item == "library.json":
                meta = json.loads(data)
                meta["trackers"] = ["right", "left", "head"]
                data = json.dumps(meta).encode()
            zout.writestr(item, data)
    one_line_error(run("live", "--models", bad, "--source", recorded["session"], "--no-view"),
                   "bad.npz", "22 columns")


def test_enroll_multi_in_python_keeps_bit_identical_takes(recorded, tmp_path):
    takes = read_multi_takes(recorded["library"])
    lib = enroll_multi(takes, invariance="gravity", built_from=[str(recorded["library"])])
    path = lib.save(tmp_path / "py.npz")
    back = load_multi_library(path)
    for a, b in zip(lib.takes.rows(), back.takes.rows(), strict=True):
        assert np.array_equal(a, b)
    for a, b in zip(lib.takes.takes, back.takes.takes, strict=True):
        assert np.array_equal(a.trackers[1].q, b.trackers[1].q)
    assert back.gesture_thresholds == lib.gesture_thresholds


@pytest.mark.parametrize(("item", "named"), [("threshold_position=2", "threshold_position"),
                                             ("rival_quantile=-1", "rival_quantile"),
                                             ("no_such_setting=1", "no_such_setting")])
def test_enroll_refuses_a_bad_setting_in_one_message(recorded, tmp_path, item, named):
    res = run("enroll", recorded["library"], "--set", item, "-o", tmp_path / "bad.npz")
    assert res.exit_code == 2 and named in res.output and "Traceback" not in res.output
    assert not (tmp_path / "bad.npz").exists()


def test_a_take_holding_two_performances_leaves_the_pause_allowance_alone():
    """Several trackers: a take holding two performances and the rest between them is named,
    and its 2.5 s rest does not set how long every gesture may pause (session 42)."""
    people = load_people(SHIPPED_MACHETE)
    recs = [r for r in people if r.gesture in GESTURES]
    samples = [r.sample for r in recs]
    names = tuple(f"{r.gesture}/{r.person}_{k}" for k, r in enumerate(recs))
    labels = tuple(r.gesture for r in recs)
    joined, _ = continuous_session(samples[:2], labels[:2], rate=90.0, seed=5)
    joined = type(joined)(joined.trackers, samples[0].names, joined.up, "two in one")
    lib = enroll_multi(MultiTakeSet((joined, *samples[1:]), labels, names))
    found = long_rest(lib)
    assert labels[0] == labels[1] and found is not None and found.name == names[0]
    assert found.rest > 2.0 > lib.learned_settings().max_pause
