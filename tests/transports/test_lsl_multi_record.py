"""`framefree record --source lsl://NAME` with an LSL stream of two controllers: the takes are cut
live, as the rests arrive, and are those `record` cuts from the same session as a file; enroll
takes them. Loopback only (``loopback_only``)."""

from __future__ import annotations

import importlib.util
import threading
import uuid

import pytest

from framefree.io.multicsv import read_multi_csv

pytestmark = pytest.mark.skipif(importlib.util.find_spec("pylsl") is None,
                                reason="pip install 'framefree[lsl]'")


def _publish(pylsl, sample, name, done, log) -> None:
    """An outlet of 14 channels (each controller's x y z qw qx qy qz), stamped with the session's
    times; it goes when everything is sent and ``done`` is set (the inlet then ends)."""
    info = pylsl.StreamInfo(name, "MoCap", 14, 90.0, pylsl.cf_double64, f"test-{name}")
    outlet = pylsl.StreamOutlet(info)
    log["consumer"] = outlet.wait_for_consumers(60.0)
    for k in range(len(sample)):
        outlet.push_sample([v for tr in sample.trackers for v in (*tr.p[k], *tr.q[k])],
                           float(sample.t[k]))
    log["sent"] = len(sample)
    done.wait(60.0)
    del outlet


def test_record_from_an_lsl_stream_of_two_controllers(tmp_path, loopback_only):
    from click.testing import CliRunner

    from framefree.cli import cli
    from framefree.core.trajectory import Trajectory
    from framefree.datasets.multi_sessions import continuous_session
    from framefree.datasets.people_layout import load_people
    from framefree.io.lsl import import_pylsl
    from framefree.io.multicsv import write_multi_csv
    from real_data import SHIPPED_MACHETE

    pylsl = import_pylsl()
    takes = [r for r in load_people(SHIPPED_MACHETE) if r.gesture == "hook_left"]
    sample, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                          rate=90.0, seed=5)
    moved = tuple(Trajectory(tr.t + 100.0, tr.p, tr.q) for tr in sample.trackers)  # LSL: t > 0
    sample = type(sample)(moved, ("right", "left"), sample.up, "session")
    as_file = write_multi_csv(tmp_path / "session.csv", sample)
    name = f"ff-rec-{uuid.uuid4().hex[:8]}"
    done, log, result = threading.Event(), {}, {}
    pub = threading.Thread(target=_publish, args=(pylsl, sample, name, done, log), daemon=True)
    pub.start()

    def record():
        result["res"] = CliRunner().invoke(cli, [
            "record", "--source", f"lsl://{name}", "--gesture", "hook_left", "--library",
            str(tmp_path / "live"), "--timeout", "2", "--tracker-names", "right,left"])

    rec = threading.Thread(target=record, daemon=True)
    rec.start()
    rec.join(240)
    done.set()
    pub.join(10)
    res = result["res"]
    assert res.exit_code == 0, res.output
    assert log["consumer"] and log["sent"] == len(sample)
    assert "2 trackers (right, left)" in res.output
    from_file = CliRunner().invoke(cli, ["record", "--source", str(as_file), "--gesture",
                                         "hook_left", "--library", str(tmp_path / "file")])
    assert from_file.exit_code == 0, from_file.output
    live = sorted((tmp_path / "live" / "hook_left").glob("trial_*.csv"))
    files = sorted((tmp_path / "file" / "hook_left").glob("trial_*.csv"))
    assert len(live) == len(files) == len(segments) == 4
    # live, the rest level comes from what was recorded so far, so a take's ends may differ
    # from the file's by a few tenths of a second
    for a, b, seg in zip(live, files, segments, strict=True):
        ta, tb = read_multi_csv(a), read_multi_csv(b)
        assert ta.names == tb.names == ("right", "left")
        duration = seg.end_t - seg.start_t
        assert 0.8 * duration < ta.t[-1] - ta.t[0] < duration + 3.0
        assert abs((ta.t[-1] - ta.t[0]) - (tb.t[-1] - tb.t[0])) < 0.5
    enroll = ["enroll", str(tmp_path / "live"), "-o", str(tmp_path / "live.npz")]
    one = CliRunner().invoke(cli, enroll)
    assert one.exit_code == 2 and "at least two" in one.output and "Traceback" not in one.output
    others = [r for r in load_people(SHIPPED_MACHETE) if r.gesture == "uppercut_left"]
    second, _ = continuous_session([r.sample for r in others], [r.gesture for r in others],
                                   rate=90.0, seed=6)
    second = type(second)(second.trackers, ("right", "left"), second.up, "uppercuts")
    res = CliRunner().invoke(cli, ["record", "--source", str(write_multi_csv(
        tmp_path / "uppercuts.csv", second)), "--gesture", "uppercut_left", "--library",
        str(tmp_path / "live")])
    assert res.exit_code == 0, res.output
    enrolled = CliRunner().invoke(cli, enroll)
    assert enrolled.exit_code == 0, enrolled.output
    assert "8 takes of 2 gestures, 2 trackers (right, left)" in enrolled.output


def test_tracker_names_must_fit_the_source():
    from framefree.commands.multi_record import _names
    from framefree.errors import FramefreeError

    class Two:
        n_trackers = 2

    assert _names(Two(), None) == ("tracker_0", "tracker_1")
    assert _names(Two(), "a, b") == ("a", "b")
    for bad in ("a", "a,a", "a,b,c", "a,"):
        with pytest.raises(FramefreeError, match="carries 2 trackers"):
            _names(Two(), bad)
