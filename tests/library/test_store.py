"""Gesture library files: round trip, no recalibration on load, versions, updates."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import numpy as np
import pytest

import framefree.online.model_settings as model_settings
from framefree.library import (
    FORMAT_VERSION,
    GestureLibrary,
    LibraryError,
    TakeSet,
    check_takes,
    enroll,
    load_library,
    load_recognizer,
    read_takes,
)
from framefree.library.store import combine_takes
from framefree.online import Recognizer
from framefree.online.evaluation import run_stream
from framefree.replica import make_stream, synthesize_gesture

#: Everything the recognizer derives from its models (each must not run when a library loads);
#: names of earlier and later versions of the recognizer module, those present are patched.
DERIVATIONS = ("calibrate_segment_thresholds", "speed_levels", "candidate_limits", "gesture_closures",
               "gesture_geometry", "size_limits", "closure_limit", "sustained_peak_speed")


@pytest.fixture(scope="module")
def stream():
    """A short session with every HPM gesture and a stop signal."""
    return make_stream(7, n_gestures=7, n_stops=1)


def test_round_trip_gives_identical_decisions(hpm_takes: TakeSet, hpm_library_file: Path, stream) -> None:
    traj, segments = stream
    stored = hpm_takes.as_stored()
    calibrated = Recognizer.from_trajectories(list(stored.takes), list(stored.labels))
    loaded = load_recognizer(hpm_library_file)
    assert loaded.gesture_thresholds == calibrated.gesture_thresholds
    assert loaded.stop_threshold == calibrated.stop_threshold
    assert loaded.config == calibrated.config
    assert loaded.learned_.values() == calibrated.learned_.values()
    for a, b in zip(loaded.classifier.models, calibrated.classifier.models, strict=True):
        np.testing.assert_array_equal(a, b)
    events_a, _ = run_stream(calibrated, traj)
    events_b, _ = run_stream(loaded, traj)
    assert len(events_a) >= len(segments) // 2  # the stream is recognized at all
    assert events_b == events_a


def test_loading_calibrates_nothing(hpm_library_file: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def forbidden(*args, **kwargs):
        raise AssertionError("a library load must not derive or calibrate anything")

    present = [name for name in DERIVATIONS if hasattr(model_settings, name)]
    assert {"calibrate_segment_thresholds", "speed_levels", "sustained_peak_speed"} <= set(present)
    for name in present:
        monkeypatch.setattr(model_settings, name, forbidden)
    rec = Recognizer.load(hpm_library_file)
    assert len(rec.labels) == 35 and len(rec.gestures) == 7
    with pytest.raises(AssertionError, match="must not"):  # the patch is in effect
        Recognizer.from_trajectories(*_first_two(hpm_library_file))


def _first_two(path: Path):
    lib = load_library(path)
    keep = [k for k, g in enumerate(lib.takes.labels) if g in lib.gestures[:2]]
    return [lib.takes.takes[k] for k in keep], [lib.takes.labels[k] for k in keep]


def test_file_is_plain_arrays_and_json(hpm_library_file: Path, hpm_takes: TakeSet) -> None:
    with np.load(hpm_library_file, allow_pickle=False) as npz:
        offsets = npz["offsets"]
        samples = npz["samples"]
    assert offsets.dtype == np.int64 and samples.shape == (offsets[-1], 8)
    np.testing.assert_array_equal(samples[offsets[0]:offsets[1]], hpm_takes.takes[0].to_array())
    with zipfile.ZipFile(hpm_library_file) as zf:
        meta = json.loads(zf.read("library.json"))
    assert meta["format_version"] == FORMAT_VERSION
    assert meta["names"][0] == hpm_takes.names[0] and len(meta["labels"]) == 35
    assert set(meta["learned"]["gesture_thresholds"]) == set(hpm_takes.gestures)
    rules = meta["learned"]["provenance"]["rules"]
    assert rules["gesture_thresholds"].endswith("thresholds.calibrate_segment_thresholds")
    assert meta["learned"]["provenance"]["takes"] == 35 and "rest_speed" not in meta["config"]


def test_loaded_library_keeps_everything(hpm_library: GestureLibrary, hpm_library_file: Path) -> None:
    lib = load_library(hpm_library_file)
    assert lib.fingerprint == hpm_library.fingerprint
    assert lib.takes.names == hpm_library.takes.names
    assert lib.gesture_thresholds == hpm_library.gesture_thresholds
    assert lib.config == hpm_library.config and lib.settings == hpm_library.settings
    assert lib.learned == hpm_library.learned
    assert "35 takes of 7 gestures" in lib.summary()


def _rewrite(src: Path, dst: Path, change) -> Path:
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for item in zin.namelist():
            data = zin.read(item)
            if item == "library.json":
                meta = json.loads(data)
                change(meta)
                data = json.dumps(meta).encode()
            zout.writestr(item, data)
    return dst


def test_other_format_version_says_how_to_rebuild(hpm_library_file: Path, tmp_path: Path) -> None:
    old = _rewrite(hpm_library_file, tmp_path / "old.npz", lambda m: m.update(format_version=0))
    hint = r"format 0 .*enroll it again: framefree enroll .*-o .*old\.npz"
    with pytest.raises(LibraryError, match=hint) as exc:
        load_library(old)
    assert "\n" not in str(exc.value)


def test_settings_of_another_version_say_how_to_rebuild(hpm_library_file: Path, tmp_path: Path) -> None:
    def alien(meta):
        meta["config"]["latency_fraction"] = 0.2

    bad = _rewrite(hpm_library_file, tmp_path / "alien.npz", alien)
    with pytest.raises(LibraryError, match=r"latency_fraction.*enroll it again") as exc:
        load_library(bad)
    assert "\n" not in str(exc.value)


def test_a_new_library_aligns_on_gram_and_limits_pauses_of_gestures_drawn_in_one_go(
        hpm_library_file: Path) -> None:
    """The defaults: gram alignment, and per-gesture pause limits, *go right* (a circle drawn in
    one go) limited and the out-and-back gestures, whose demonstrator pauses, not. (Libraries
    saved before either existed: tests/library/test_library_versions.py.)"""
    library = load_library(hpm_library_file)
    assert library.recognizer_config().descriptor.align == "gram"
    new = library.recognizer()
    assert new.config.gesture_pauses and new.learned_.one_go == ["go_right"]
    one_go = [line.split()[0] for line in library.summary().splitlines() if "in one go" in line]
    assert one_go == ["go_right"]


def test_not_a_library(tmp_path: Path) -> None:
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a zip")
    with pytest.raises(LibraryError, match="not a framefree gesture library"):
        load_library(junk)
    with pytest.raises(LibraryError):
        load_library(tmp_path / "missing.npz")


def test_remove_gesture_and_take(hpm_takes: TakeSet) -> None:
    fewer = hpm_takes.without(["go_up", "go_left/trial_3", "go_home/original_1/trial_1"])
    assert "go_up" not in fewer.gestures
    assert fewer.counts()["go_left"] == 4 and fewer.counts()["go_home"] == 4
    assert "go_left/original_1/trial_3" not in fewer.names
    assert len(fewer.rows()) == len(fewer)
    with pytest.raises(LibraryError, match="no such gesture or take"):
        hpm_takes.without(["wave"])


def test_one_take_is_enrolled_on_larger_and_smaller_copies(hpm_takes: TakeSet) -> None:
    """A gesture of one take has no leave-one-out distance; copies of it 1.3 times smaller and
    larger stand in for other performances, and its threshold is finite."""
    one = hpm_takes.without([f"go_up/trial_{k}" for k in range(2, 6)])
    lib = enroll(one)
    assert 0 < lib.gesture_thresholds["go_up"] < np.inf
    assert set(lib.calibration["positives_max"]) == set(one.gestures)
    rec = Recognizer.from_trajectories(list(one.takes), list(one.labels))
    assert len(rec.calibration.positives["go_up"]) == 2  # the smaller and the larger copy
    report = check_takes(one)
    assert any("go_up has only 1 takes" in f.message for f in report.findings)


def test_read_takes_prefers_own_and_explains_layout_errors(tmp_path: Path, hpm_takes: TakeSet) -> None:
    for ctx in ("own", "other"):
        d = tmp_path / "lib" / "wave" / ctx
        d.mkdir(parents=True)
        hpm_takes.takes[0].to_csv(d / "trial_1.csv")
        hpm_takes.takes[1].to_csv(d / "trial_2.csv")
    ts = read_takes(tmp_path / "lib")
    assert ts.names == ("wave/own/trial_1", "wave/own/trial_2")
    assert read_takes(tmp_path / "lib", "other").names[0] == "wave/other/trial_1"
    with pytest.raises(LibraryError, match="no such library folder"):
        read_takes(tmp_path / "nope")
    (tmp_path / "lib" / "wave" / "own").rename(tmp_path / "lib" / "wave" / "third")
    with pytest.raises(LibraryError, match="--context"):
        read_takes(tmp_path / "lib")


def test_one_gesture_name_in_two_sources_is_refused_unless_merged(tmp_path: Path) -> None:
    """A folder go_up/ of other takes enrolled with the replica must not silently become go_up."""
    import shutil

    from click.testing import CliRunner

    from framefree.cli import cli
    from framefree.replica import replica_path

    mine = tmp_path / "mine" / "go_up" / "own"
    mine.mkdir(parents=True)
    rng = np.random.default_rng(3)
    for k in range(3):
        synthesize_gesture("figure_eight", rng).to_csv(mine / f"trial_{k + 1}.csv")
    vocab = tmp_path / "hpm"
    for g in ("go_up", "go_left"):
        shutil.copytree(replica_path() / g / "original_1", vocab / g / "original_1")
    res = CliRunner().invoke(cli, ["enroll", str(vocab), str(tmp_path / "mine"), "-o",
                                   str(tmp_path / "x.npz")])
    assert res.exit_code == 2, res.output
    assert "'go_up' is in both" in res.output and "--merge go_up" in res.output
    assert not (tmp_path / "x.npz").exists()
    combined = combine_takes([("a", read_takes(vocab)), ("b", read_takes(tmp_path / "mine"))],
                             merge=["go_up"])
    assert combined.counts()["go_up"] == 8


def test_a_copied_take_is_refused(hpm_takes: TakeSet) -> None:
    a = TakeSet(hpm_takes.takes[:2], ("wave", "wave"), ("wave/own/trial_1", "wave/own/trial_2"))
    b = TakeSet(hpm_takes.takes[1:3], ("circle", "circle"),
                ("circle/own/trial_1", "circle/own/trial_2"))
    with pytest.raises(LibraryError, match="circle/own/trial_1 is an exact copy of take wave/own/trial_2"):
        enroll(a + b)
