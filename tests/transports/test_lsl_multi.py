"""An LSL stream of two trackers (8 channels each, with the valid flag) read whole: one pose of
every tracker per sample, a lost tracker's position NaN. Run in a child process, so that liblsl
loads with framefree's configuration; nothing may leave loopback (``loopback_only``)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

import pytest

_TWO_TRACKERS = """
import threading, time, uuid
import numpy as np
from framefree.io.lsl import LslSource, import_pylsl
pylsl = import_pylsl()
name = f"ff-two-{uuid.uuid4().hex[:8]}"

def send():
    info = pylsl.StreamInfo(name, "MoCap", 16, 90.0, pylsl.cf_double64, name)
    outlet = pylsl.StreamOutlet(info)
    outlet.wait_for_consumers(30.0)
    for k in range(30):
        right = [0.1 * k, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        left = [0.0, 0.4, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0 if k == 7 else 1.0]  # lost at k = 7
        outlet.push_sample(right + left, 50.0 + k / 90.0)
        time.sleep(0.002)
    time.sleep(0.3)
    del outlet

sender = threading.Thread(target=send)
sender.start()
source = LslSource(name, tracker=None, timeout=10.0)
poses = list(source)
sender.join()
t, p, q = poses[7]
print(source.n_trackers, len(poses), p.shape, q.shape, np.isnan(p[1]).all(), p[0, 0], q[1].tolist())
"""


def test_every_tracker_of_an_lsl_stream_at_once(loopback_only):
    if importlib.util.find_spec("pylsl") is None:  # not imported here: liblsl is configured first
        pytest.skip("pip install 'framefree[lsl]'")
    env = {k: v for k, v in os.environ.items() if k != "LSLAPICFG"}
    proc = subprocess.run([sys.executable, "-c", _TWO_TRACKERS], capture_output=True, text=True,
                          env=env, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["2", "30", "(2,", "3)", "(2,", "4)", "True", "0.7000000000000001",
                                   "[0.0,", "0.0,", "0.0,", "1.0]"]


def _publish_two(pylsl, sample, name, ready, done, log) -> None:
    """Outlet of 14 double channels (each controller's x y z qw qx qy qz), time-stamped with the
    session's times; open until ``done``."""
    info = pylsl.StreamInfo(name, "MoCap", 14, 60.0, pylsl.cf_double64, f"test-{name}")
    outlet = pylsl.StreamOutlet(info)
    log["consumer"] = outlet.wait_for_consumers(60.0)
    log["ready"] = ready.wait(60.0)
    for k in range(len(sample)):
        row = [v for tr in sample.trackers for v in (*tr.p[k], *tr.q[k])]
        outlet.push_sample(row, float(sample.t[k]))
    log["sent"] = len(sample)
    done.wait(120.0)
    del outlet


def test_live_from_an_lsl_stream_of_two_controllers_matches_evaluate_stream(tmp_path,
                                                                             loopback_only):
    """`framefree live --models PEOPLE --source lsl://NAME` takes both controllers of the stream
    and gives the events `evaluate-stream` gives the same session from its CSV file."""
    import json
    import threading
    import uuid

    from click.testing import CliRunner

    from framefree.cli import cli
    from framefree.datasets.multi_sessions import continuous_session
    from framefree.datasets.people_layout import load_people
    from framefree.datasets.stream_files import write_labels
    from framefree.io.lsl import import_pylsl
    from framefree.io.multicsv import write_multi_csv
    from real_data import SHIPPED_MACHETE

    pylsl = import_pylsl()
    takes = [r for r in load_people(SHIPPED_MACHETE).of(["Sub_U001"])
             if r.gesture.startswith("hook")]
    sample, segments = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                          rate=60.0, seed=2)
    # liblsl reads a time stamp of exactly 0 as "now": the session starts at 100 s
    from framefree.core.trajectory import Trajectory
    from framefree.datasets.stream_files import Segment

    moved = tuple(Trajectory(tr.t + 100.0, tr.p, tr.q) for tr in sample.trackers)
    sample = type(sample)(moved, ("controller_0", "controller_1"), sample.up, "session")
    segments = [Segment(s.label, s.start_t + 100.0, s.end_t + 100.0) for s in segments]
    session = write_multi_csv(tmp_path / "session.csv", sample)
    write_labels(tmp_path / "session_labels.csv", segments)
    name = f"ff-two-{uuid.uuid4().hex[:8]}"
    ready, done, log, result = threading.Event(), threading.Event(), {}, {}
    pub = threading.Thread(target=_publish_two, args=(pylsl, sample, name, ready, done, log),
                           daemon=True)
    pub.start()

    def run_live():
        result["live"] = CliRunner().invoke(cli, [
            "live", "--models", str(SHIPPED_MACHETE), "--source", f"lsl://{name}", "--timeout",
            "3", "--no-view", "--emit", f"jsonl:{tmp_path / 'live.jsonl'}"])

    live = threading.Thread(target=run_live, daemon=True)
    live.start()
    ready.set()
    live.join(300)
    done.set()
    pub.join(10)
    res = result["live"]
    assert res.exit_code == 0, res.output
    assert log["consumer"] and log["sent"] == len(sample)
    ev = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(SHIPPED_MACHETE), str(session),
                                  "--emit", f"jsonl:{tmp_path / 'eval.jsonl'}"])
    assert ev.exit_code == 0, ev.output
    expected = [json.loads(s) for s in (tmp_path / "eval.jsonl").read_text().splitlines()]
    got = [json.loads(s) for s in (tmp_path / "live.jsonl").read_text().splitlines()]
    assert sum(r["label"].startswith("hook") for r in expected) >= 3
    assert got == expected, res.output
