"""``framefree record``, ``enroll`` and ``check``, and library files in ``evaluate-stream``/``live``.

The whole path on a small vocabulary: two gestures recorded from one long CSV recording each
(and one over ZeroMQ on 127.0.0.1), enrolled, checked, and used on a labelled stream.
"""

from __future__ import annotations

import json
import socket
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.replica import make_stream, save_stream, synthesize_gesture
from real_data import REAL_MOTIONS

from .conftest import chain

GESTURES = ("go_right", "open_gripper")


def _session_csv(path: Path, gesture: str, seed: int, n: int = 3) -> Path:
    rng = np.random.default_rng([seed, 99])
    traj = chain([synthesize_gesture(gesture, rng) for _ in range(n)])
    traj.to_csv(path)
    return path


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> tuple[Path, Path]:
    """``(library folder, stream CSV)`` after ``framefree record`` of both gestures."""
    root = tmp_path_factory.mktemp("vocab")
    lib = root / "mine"
    for k, g in enumerate(GESTURES):
        csv = _session_csv(root / f"{g}_session.csv", g, k)
        res = CliRunner().invoke(cli, ["record", "--source", str(csv), "--gesture", g, "--library", str(lib)])
        assert res.exit_code == 0, res.output
    traj, segs = make_stream(11, sequence=[*GESTURES, *GESTURES])
    stream = save_stream(root / "stream.csv", traj, segs)
    return lib, stream


def test_record_writes_takes_with_cues(recorded, tmp_path) -> None:
    lib, _ = recorded
    for g in GESTURES:
        assert sorted(f.name for f in (lib / g / "own").iterdir()) == [f"trial_{k}.csv" for k in (1, 2, 3)]
    csv = _session_csv(tmp_path / "again.csv", "go_right", 5)
    res = CliRunner().invoke(cli, ["record", "--source", str(csv), "--gesture", "go_right", "--library",
                                   str(tmp_path / "lib"), "--takes", "2", "--context", "today"])
    assert res.exit_code == 0, res.output
    assert "take 2 recorded (" in res.output and "rest, then perform the next" in res.output
    assert len(list((tmp_path / "lib" / "go_right" / "today").glob("*.csv"))) == 2


def test_record_joins_a_performance_that_hesitated(tmp_path) -> None:
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    take_session("go_left", person(6), n_takes=5, seed=6).traj.to_csv(tmp_path / "hesitant.csv")
    res = CliRunner().invoke(cli, ["record", "--source", str(tmp_path / "hesitant.csv"), "--gesture",
                                   "go_left", "--library", str(tmp_path / "lib")])
    assert res.exit_code == 0, res.output
    assert "joined as one performance" in res.output
    assert len(list((tmp_path / "lib" / "go_left" / "own").glob("*.csv"))) == 5


def test_record_without_motion_fails_clearly(tmp_path) -> None:
    n = 200
    still = np.column_stack([0.02 * np.arange(n), np.zeros((n, 3)), np.tile([1.0, 0, 0, 0], (n, 1))])
    np.savetxt(tmp_path / "still.csv", still, delimiter=",")
    res = CliRunner().invoke(cli, ["record", "--source", str(tmp_path / "still.csv"), "--gesture", "wave",
                                   "--library", str(tmp_path / "lib")])
    assert res.exit_code == 1 and "no take found" in res.output
    assert not (tmp_path / "lib").exists()


def test_record_over_zmq(tmp_path) -> None:
    csv = _session_csv(tmp_path / "s.csv", "go_down", 3, n=2)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    out: dict[str, object] = {}

    def publish() -> None:
        time.sleep(0.5)
        out["pub"] = CliRunner().invoke(cli, ["stream", str(csv), "--port", str(port), "--speed", "0",
                                              "--join-wait", "1.0"])

    th = threading.Thread(target=publish, daemon=True)
    th.start()
    res = CliRunner().invoke(cli, ["record", "--source", f"zmq://127.0.0.1:{port}", "--gesture", "go_down",
                                   "--library", str(tmp_path / "lib"), "--timeout", "8"])
    th.join(30)
    assert res.exit_code == 0, res.output
    assert len(list((tmp_path / "lib" / "go_down" / "own").glob("*.csv"))) == 2


@pytest.fixture(scope="module")
def enrolled(recorded) -> Path:
    lib, _ = recorded
    res = CliRunner().invoke(cli, ["enroll", str(lib)])
    assert res.exit_code == 0, res.output
    out = lib.parent / "mine.npz"
    assert out.is_file() and f"wrote {out}" in res.output
    return out


def test_enroll_again_is_up_to_date_and_updates_on_change(recorded, enrolled, tmp_path) -> None:
    lib, _ = recorded
    res = CliRunner().invoke(cli, ["enroll", str(lib)])
    assert res.exit_code == 0 and "up to date" in res.output
    smaller = tmp_path / "smaller.npz"
    res = CliRunner().invoke(cli, ["enroll", str(enrolled), "--remove", "go_right/trial_3",
                                   "-o", str(smaller)])
    assert res.exit_code == 0, res.output
    assert "go_right" in res.output and smaller.is_file()
    res = CliRunner().invoke(cli, ["enroll", str(enrolled)])
    assert res.exit_code == 2 and "-o" in res.output


def test_enroll_adds_a_gesture_to_a_library_file(recorded, enrolled, tmp_path) -> None:
    extra = tmp_path / "extra"
    csv = _session_csv(tmp_path / "d.csv", "go_down", 8)
    assert CliRunner().invoke(cli, ["record", "--source", str(csv), "--gesture", "go_down",
                                    "--library", str(extra)]).exit_code == 0
    bigger = tmp_path / "bigger.npz"
    res = CliRunner().invoke(cli, ["enroll", str(enrolled), str(extra), "-o", str(bigger)])
    assert res.exit_code == 0, res.output
    assert "new library" in res.output
    assert "go_down" in res.output and "9 takes of 3 gestures" in res.output


def test_enroll_with_a_vertical(recorded, enrolled, tmp_path) -> None:
    """``--up`` stores the axis (the replica's worlds are y-up) and its limits in the library."""
    from framefree.library import load_library

    upright = tmp_path / "upright.npz"
    res = CliRunner().invoke(cli, ["enroll", str(enrolled), "--up", "+y", "-o", str(upright)])
    assert res.exit_code == 0, res.output
    assert "up +y" in res.output and "vertical 0." in res.output
    lib = load_library(upright)
    assert lib.recognizer_config().up == "+y"
    assert set(lib.learned_settings().vertical_limits) == set(load_library(enrolled).gestures)
    res = CliRunner().invoke(cli, ["enroll", str(enrolled), "--up", "north", "-o", str(upright)])
    assert res.exit_code == 2 and "north" in res.output


def test_check_writes_report_and_figures(recorded, enrolled, tmp_path) -> None:
    lib, _ = recorded
    res = CliRunner().invoke(cli, ["check", str(enrolled), "--out", str(tmp_path / "chk")])
    assert res.exit_code in (0, 1), res.output
    report = json.loads((tmp_path / "chk" / "mine_check.json").read_text())
    assert set(report["gestures"]) == set(GESTURES)
    assert len(report["distances"]) == len(report["takes"]) == 6
    assert res.exit_code == (0 if report["ok"] else 1)
    assert (tmp_path / "chk" / "mine_distances.png").is_file()
    assert (tmp_path / "chk" / "mine_gallery.png").is_file()
    inside = CliRunner().invoke(cli, ["check", str(lib), "--out", str(lib / "report")])
    assert inside.exit_code == 2 and "inside the library" in inside.output


def test_evaluate_stream_and_live_use_the_library(recorded, enrolled, tmp_path) -> None:
    _, stream = recorded
    out = tmp_path / "eval.json"
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(enrolled), "--stream", str(stream),
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    assert "loading gesture library" in res.output
    data = json.loads(out.read_text())
    assert data["total"]["tp"] + data["total"]["fn"] == 2 * len(GESTURES)
    live = CliRunner().invoke(cli, ["live", "--models", str(enrolled), "--source", str(stream),
                                    "--speed", "0", "--no-view"])
    assert live.exit_code == 0, live.output
    bad = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(enrolled), "--stream", str(stream),
                                   "--threshold", "0.5"])
    assert bad.exit_code == 2 and "enroll" in bad.output


def test_evaluate_stream_scores_a_library_s_gestures_only(recorded, enrolled, tmp_path) -> None:
    """A stream that also labels a gesture the library lacks: without ``--gestures`` it counts as
    a miss, with a note; with the library's gestures named, as non-gesture motion. A list that is
    not the library's vocabulary is one line."""
    traj, segs = make_stream(12, sequence=[*GESTURES, "go_left"])
    stream = save_stream(tmp_path / "three.csv", traj, segs)
    args = ["evaluate-stream", "--models", str(enrolled), "--stream", str(stream)]
    plain = CliRunner().invoke(cli, [*args, "--json", str(tmp_path / "plain.json")])
    assert plain.exit_code == 0, plain.output
    assert "note: the streams label go_left, which" in plain.output
    named = CliRunner().invoke(cli, [*args, "--gestures", ",".join(reversed(GESTURES)),
                                     "--json", str(tmp_path / "named.json")])
    assert named.exit_code == 0, named.output
    assert "note: the streams label" not in named.output
    total = {k: json.loads((tmp_path / f"{k}.json").read_text())["total"] for k in ("plain", "named")}
    assert total["plain"]["fn"] == total["named"]["fn"] + 1
    assert total["plain"]["tp"] == total["named"]["tp"]
    wrong = CliRunner().invoke(cli, [*args, "--gestures", GESTURES[0]])
    assert wrong.exit_code == 2 and "Traceback" not in wrong.output
    assert wrong.output.strip().splitlines()[-1].startswith("error: --gestures go_right:")
    assert f"holds {', '.join(sorted(GESTURES))}" in wrong.output and "--remove" in wrong.output


def test_enroll_and_check_read_a_dictionary_without_contexts(recorded, tmp_path) -> None:
    """``<folder>/<gesture>/<trial>.csv``, as a benchmark's dictionary of examples is laid out and
    as ``--models`` reads it, enrolls as the same takes under shorter names."""
    lib, _ = recorded
    flat = tmp_path / "dictionary"
    for g in GESTURES:
        (flat / g).mkdir(parents=True)
        for f in (lib / g / "own").glob("*.csv"):
            (flat / g / f.name).write_bytes(f.read_bytes())
    res = CliRunner().invoke(cli, ["enroll", str(flat), "-o", str(tmp_path / "flat.npz")])
    assert res.exit_code == 0, res.output
    from framefree.library import load_library, read_takes

    takes = load_library(tmp_path / "flat.npz").takes
    assert sorted(takes.names) == sorted(f"{g}/trial_{k}" for g in GESTURES for k in (1, 2, 3))
    assert [t.p.tolist() for t in takes.takes] == [t.p.tolist() for t in read_takes(lib).takes]
    (flat / "empty").mkdir()
    bad = CliRunner().invoke(cli, ["enroll", str(flat), "-o", str(tmp_path / "bad.npz")])
    assert bad.exit_code == 2
    assert "empty: no takes (expected empty/<context>/<trial>.csv or empty/<trial>.csv)" in bad.output


def test_old_library_is_one_line_error(enrolled, tmp_path) -> None:
    import zipfile

    old = tmp_path / "old.npz"
    with zipfile.ZipFile(enrolled) as zin, zipfile.ZipFile(old, "w") as zout:
        for item in zin.namelist():
            data = zin.read(item)
            if item == "library.json":
                meta = json.loads(data)
                meta["format_version"] = 99
                data = json.dumps(meta).encode()
            zout.writestr(item, data)
    res = CliRunner().invoke(cli, ["check", str(old), "--out", str(tmp_path)])
    assert res.exit_code == 2
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and "framefree enroll" in lines[0]
    assert "Traceback" not in res.output


def test_enroll_keeps_settings(recorded, tmp_path) -> None:
    lib, _ = recorded
    out = tmp_path / "strict.npz"
    res = CliRunner().invoke(cli, ["enroll", str(lib), "-o", str(out), "--set", "negative_quantile=0.1",
                                   "--set", "confirm=0.3", "--set", "max_units=4"])
    assert res.exit_code == 0, res.output
    from framefree.library import load_library

    loaded = load_library(out)
    assert loaded.config["constants"]["negative_quantile"] == 0.1 and loaded.config["confirm"] == 0.3
    assert loaded.learned["max_units"] == 4 and loaded.settings["max_units"] == 4
    again = CliRunner().invoke(cli, ["enroll", str(out), "-o", str(out)])  # the settings carry over
    assert again.exit_code == 0 and "up to date" in again.output, again.output
    unknown = CliRunner().invoke(cli, ["enroll", str(lib), "-o", str(out), "--set", "nonsense=1"])
    assert unknown.exit_code == 2 and "nonsense" in unknown.output
    bad = CliRunner().invoke(cli, ["enroll", str(lib), "-o", str(out), "--set", "nonsense"])
    assert bad.exit_code == 2 and "KEY=VALUE" in bad.output


def test_classify_takes_a_library_file_and_rejects(tmp_path, hpm_library_file) -> None:
    from framefree.replica import replica_path

    root = replica_path()
    query = root / "go_up" / "world_frame_1" / "trial_3.csv"
    pour = REAL_MOTIONS / "kettle_pour_trial1_ref_com.csv"
    res = CliRunner().invoke(cli, ["classify", "-m", str(hpm_library_file), str(query), str(pour)])
    assert res.exit_code == 0, res.output
    lines = [ln.split() for ln in res.output.splitlines() if ln.startswith(("/", str(tmp_path)))]
    assert [ln[1] for ln in lines[-2:]] == ["go_up", "no_gesture"]
    assert "gesture library" in res.output


def test_classify_takes_a_record_folder_without_model_context(recorded) -> None:
    lib, _ = recorded
    take = next(lib.glob("*/own/*.csv"))
    res = CliRunner().invoke(cli, ["classify", "-m", str(lib), str(take)])
    assert res.exit_code == 0, res.output
    assert "the only context" in res.output


def test_classify_stops_on_millimetres(tmp_path) -> None:
    from framefree.replica import replica_path

    root = replica_path()
    data = np.loadtxt(root / "go_up" / "world_frame_1" / "trial_3.csv", delimiter=",")
    data[:, 1:4] *= 1000.0
    mm = tmp_path / "mm.csv"
    np.savetxt(mm, data, delimiter=",")
    res = CliRunner().invoke(cli, ["classify", "-m", str(root), str(mm)])
    assert res.exit_code == 2 and "--units mm" in res.output and "--force" in res.output
    # --units applies to the models too: the replica read in millimetres is a thousand times too
    # small, and the query is said to be far larger than any gesture, with a hint at the units
    res = CliRunner().invoke(cli, ["classify", "-m", str(root), str(mm), "--units", "mm"])
    assert res.exit_code == 0 and "no_gesture" in res.stdout
    assert "far larger than any gesture" in res.stderr and "same units" in res.stderr
    models = tmp_path / "models_mm"
    for f in root.glob("*/original_1/*.csv"):
        trial = np.loadtxt(f, delimiter=",")
        trial[:, 1:4] *= 1000.0
        (models / f.parent.parent.name / "original_1").mkdir(parents=True, exist_ok=True)
        np.savetxt(models / f.parent.parent.name / "original_1" / f.name, trial, delimiter=",")
    res = CliRunner().invoke(cli, ["classify", "-m", str(models), str(mm), "--units", "mm"])
    assert res.exit_code == 0 and "go_up" in res.stdout, res.output


def test_record_leaves_out_the_way_back_of_an_open_stroke(tmp_path) -> None:
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    session = take_session("letter_v", person(4), n_takes=3, seed=4)
    session.traj.to_csv(tmp_path / "v.csv")
    res = CliRunner().invoke(cli, ["record", "--source", str(tmp_path / "v.csv"), "--gesture", "v",
                                   "--library", str(tmp_path / "lib")])
    assert res.exit_code == 0, res.output
    assert res.output.count("went back to where the last take began") == 2
    assert "3 takes of v written" in res.output and "2 moves between takes left out" in res.output
    assert len(list((tmp_path / "lib" / "v" / "own").glob("*.csv"))) == 3
