"""Library files of an older format: format 3 is migrated to the same settings and decisions,
anything that cannot be migrated fails with one line saying how to enroll again.

``tests/data/libraries/hpm_three_v3.npz`` was written by framefree before the learned values
left ``RecognizerConfig`` (format 3: one flat configuration of 69 fields): three takes each of
*close gripper*, *go right* and *go up* of the replica (seed 0, ``original_1``).
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path

import pytest

from framefree.library import LibraryError, enroll, load_library
from framefree.online import Recognizer, RecognizerConfig
from framefree.online.acceptance import HAND_HELD_SPEEDS
from framefree.online.evaluation import run_stream
from framefree.replica import make_stream

V3 = Path(__file__).parents[1] / "data" / "libraries" / "hpm_three_v3.npz"


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


def _meta(path: Path) -> dict:
    with zipfile.ZipFile(path) as zf:
        return json.loads(zf.read("library.json"))


@pytest.fixture(scope="module")
def old():
    return load_library(V3)


@pytest.fixture(scope="module")
def enrolled_again(old):
    """The same takes enrolled by this framefree, with the starts of its time (a library saved
    before ``valley_starts`` existed restores without them)."""
    return enroll(old.takes, RecognizerConfig().replace(valley_starts=False))


def test_a_format_3_library_loads_with_what_enrolling_again_learns(old, enrolled_again) -> None:
    meta = _meta(V3)
    assert meta["format_version"] == 3 and len(meta["config"]) == 69
    assert old.recognizer_config() == enrolled_again.recognizer_config()
    assert not old.recognizer_config().constants.valley_starts
    stored, learned = old.learned_settings().values(), enrolled_again.learned_settings().values()
    # newer than format 3: learned when it is loaded (the smoothing as it was built: none)
    for newer in ("travel_limits", "unseen", "smoothing", "proportion_limits", "direction_limits",
                  "rotation_limits", "fixed_frame", "positions_only", "gate_speeds"):
        assert stored.pop(newer) is None
    assert learned.pop("fixed_frame") is False  # the replica's takes turn the tracker
    assert learned.pop("positions_only") is False  # and their orientation is precise
    assert learned.pop("gate_speeds") == HAND_HELD_SPEEDS  # a hand-held tracker's pace
    assert learned.pop("direction_limits") == {}  # three takes a gesture set no cone
    assert learned.pop("rotation_limits") == {}
    learned.pop("travel_limits")
    assert set(learned.pop("proportion_limits")) <= set(enrolled_again.takes.labels)
    assert learned.pop("unseen") == []  # the replica's takes are all found
    assert learned.pop("smoothing") == 0.0  # the replica's tracker is precise
    # the thresholds are sums of DTW costs: another CPU may add them in another order
    thresholds = stored.pop("gesture_thresholds")
    assert learned.pop("gesture_thresholds") == pytest.approx(thresholds, rel=1e-9)
    assert stored == learned
    assert old.gesture_thresholds == meta["gesture_thresholds"]
    provenance = old.learned_settings().provenance
    assert provenance.takes == 9 and "migrated from library format 3" in provenance.note
    assert provenance.rules["closure_limits"] == "learned by framefree 0.1.0 (library format 3)"


def test_a_migrated_library_decides_as_before(old, enrolled_again, tmp_path: Path) -> None:
    traj, segments = make_stream(3, n_gestures=6, n_stops=1, gestures=old.gestures)
    before = Recognizer.load(V3)
    events, _ = run_stream(before, traj)
    assert len(events) >= len(segments) // 2  # the stream is recognized at all
    assert run_stream(enrolled_again.recognizer(), traj)[0] == events
    saved = old.save(tmp_path / "v4.npz")  # written again, in the current format
    assert _meta(saved)["format_version"] == 4
    assert run_stream(Recognizer.load(saved), traj)[0] == events


def test_a_format_3_library_from_before_the_gram_alignment_keeps_its_alignment(tmp_path) -> None:
    """A library saved before ``align`` existed was calibrated on the singular values: it is
    restored with them, so its thresholds fit."""
    older = _rewrite(V3, tmp_path / "before.npz", lambda m: m["config"].pop("align"))
    restored = load_library(older).recognizer()
    assert restored.config.descriptor.align == "singular"
    assert restored.classifier.descriptor.align == "singular"


def test_a_format_3_library_from_before_the_one_go_rule_keeps_the_common_pauses(tmp_path) -> None:
    """A library saved before ``gesture_pauses`` existed restores without per-gesture pause
    limits (what it was measured with)."""
    assert Recognizer.load(V3).spotter.one_go.any()

    def forget(meta: dict) -> None:
        meta["config"].pop("gesture_pauses")
        meta["config"].pop("one_go")

    restored = load_library(_rewrite(V3, tmp_path / "before.npz", forget)).recognizer()
    assert not restored.config.gesture_pauses
    assert not restored.spotter.one_go.any()


def test_a_format_3_library_without_turn_limits_learns_them_on_loading(tmp_path) -> None:
    """A value a library lacks is learned from its takes when it loads, and its provenance
    says so."""
    older = _rewrite(V3, tmp_path / "before.npz", lambda m: m["config"].pop("forbidden_turns"))
    rec = Recognizer.load(older)
    assert rec.learned_.forbidden_turns == Recognizer.load(V3).learned_.forbidden_turns
    assert rec.learned_.provenance.rules["forbidden_turns"].endswith("limits.forbidden_turns")
    assert ("forbidden_turns, direction_limits, rotation_limits, unseen, travel_limits learned on loading"
            in rec.learned_.provenance.note)
    assert rec.learned_.unseen == []


@pytest.mark.parametrize("change, why", [
    (lambda m: m["config"].update(latency_fraction=0.2), "latency_fraction"),
    (lambda m: m.update(format_version=2), "format 2"),
    (lambda m: m["config"].update(corner_slack=-1), "corner_slack"),
])
def test_what_cannot_be_migrated_says_in_one_line_to_enroll_again(change, why, tmp_path) -> None:
    bad = _rewrite(V3, tmp_path / "bad.npz", change)
    for load in (load_library, Recognizer.load):
        with pytest.raises(LibraryError, match=why) as exc:
            load(bad)
        message = str(exc.value)
        assert "\n" not in message
        assert "enroll it again: framefree enroll hpm-replica/original_1 -o " in message


def test_a_format_4_library_from_before_the_valley_starts_keeps_its_starts(old, tmp_path) -> None:
    """A library saved before ``valley_starts`` existed (v28 and before) was calibrated with
    candidates that start only after a rest or a dip: it restores so; one that names the
    constant keeps its value."""
    saved = old.save(tmp_path / "v4.npz")

    def forget(meta: dict) -> None:
        meta["config"]["constants"].pop("valley_starts")

    before = load_library(_rewrite(saved, tmp_path / "before.npz", forget))
    assert before.recognizer_config().constants.valley_starts is False
    on = _rewrite(saved, tmp_path / "on.npz",
                  lambda m: m["config"]["constants"].update(valley_starts=True))
    assert load_library(on).recognizer_config().constants.valley_starts is True
