"""Sources of several trackers beyond CSV and LSL: a ROS 2 bag with a pose topic or a tf frame per
controller, and ZeroMQ messages carrying both controllers (on 127.0.0.1, ending by themselves).
`live` gives the events the multi-tracker CSV of the same session gives; `record` cuts takes."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from cli_helpers import free_port, one_line_error, run
from framefree.core.trajectory import Trajectory
from framefree.datasets.multi_sessions import continuous_session
from framefree.datasets.people_layout import load_people
from framefree.errors import FramefreeError
from framefree.io.multi_bag import bag_items, join_tracks
from framefree.io.sources import decode_pose, encode_pose
from real_data import SHIPPED_MACHETE

NAMES = ("controller_0", "controller_1")  # the shipped people's tracker names


@pytest.fixture(scope="module")
def session(tmp_path_factory) -> dict[str, Path]:
    """Sub_U001's hooks and uppercuts as one two-controller session (times from 1000 s, whole
    nanoseconds, as a bag stores them), its CSV, the library file of the shipped people, and the
    events `live` gives from the CSV."""
    from framefree.io.multicsv import write_multi_csv

    root = tmp_path_factory.mktemp("multi_sources")
    takes = [r for r in load_people(SHIPPED_MACHETE).of(["Sub_U001"])
             if r.gesture.startswith(("hook", "uppercut"))]
    sample, _ = continuous_session([r.sample for r in takes], [r.gesture for r in takes],
                                   rate=60.0, seed=3)
    t = np.rint((sample.t + 1000.0) * 1e9) / 1e9
    sample = type(sample)(tuple(Trajectory(t, tr.p, tr.q) for tr in sample.trackers), NAMES,
                          sample.up, "session")
    csv = write_multi_csv(root / "session.csv", sample)
    res = run("enroll", SHIPPED_MACHETE, "-o", root / "people.npz")
    assert res.exit_code == 0, res.output
    events = _live(root / "people.npz", csv)
    assert sum(e["label"].startswith(("hook", "uppercut")) for e in events) >= 6
    return {"root": root, "csv": csv, "library": root / "people.npz", "sample": sample,
            "events": events}


def _live(models, source, *extra) -> list[dict]:
    res = run("live", "--models", models, "--source", source, "--speed", "0", "--no-view",
              "--emit", "jsonl:-", *extra)
    assert res.exit_code == 0, res.output
    return [{k: v for k, v in json.loads(ln).items() if k != "wall_time"}
            for ln in res.stdout.splitlines() if ln.startswith("{")]


def _same(got: list[dict], want: list[dict]) -> bool:
    """The same events; distances equal to the last few bits (a bag's numbers take another path
    into the trajectory than the CSV's)."""
    keys = ("label", "time", "model", "threshold")
    return (len(got) == len(want)
            and all(all(g[k] == w[k] for k in keys) for g, w in zip(got, want, strict=True))
            and np.allclose([g["distance"] for g in got], [w["distance"] for w in want],
                            rtol=1e-9, atol=0))


# ------------------------------------------------------------------------------------ ZeroMQ
def test_a_message_of_several_trackers_round_trips():
    p = np.array([[0.1, 0.2, 0.3], [1.0, 2.0, 3.0]])
    q = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    msg = encode_pose(4.5, p, q)
    assert len(msg) == 8 + 56 * 2
    t, p2, q2 = decode_pose(msg)
    assert t == 4.5 and np.array_equal(p2, p) and np.array_equal(q2, q)
    one = encode_pose(1.0, p[0], q[0])
    assert len(one) == 64 and decode_pose(one)[1].shape == (3,)  # one tracker: unchanged
    t, p3, q3 = decode_pose(json.dumps({"t": 2.0, "p": p.tolist(), "q": q.tolist()}).encode())
    assert p3.shape == (2, 3) and q3.shape == (2, 4)
    with pytest.raises(FramefreeError, match="8 \\+ 56 per tracker"):
        decode_pose(b"x" * 100)


def _publish(csv: Path, port: int, out: dict, delay: float, fmt: str = "binary"
             ) -> threading.Thread:
    """Publish a CSV file (one tracker or several) at 8x its speed after ``delay`` seconds (the
    subscriber connects first), in a thread: a CliRunner of `stream` here would swap the
    streams of the CliRunner under test."""
    from framefree.io.multicsv import has_tracker_header, read_multi_csv
    from framefree.io.sources import CsvReplay, ZmqPublisher

    def go():
        time.sleep(delay)
        traj = read_multi_csv(csv) if has_tracker_header(csv) else Trajectory.from_csv(csv)
        pub = ZmqPublisher(f"tcp://127.0.0.1:{port}", join_wait=1.0, fmt=fmt)
        try:
            out["sent"] = pub.publish(CsvReplay(traj, speed=8.0))
        finally:
            pub.close()

    th = threading.Thread(target=go, daemon=True)
    th.start()
    return th


def test_stream_publishes_a_multi_tracker_csv_in_one_message_per_sample(session, loopback_only):
    from framefree.io.sources import ZmqSource

    port, got = free_port(), []
    sub = ZmqSource(f"tcp://127.0.0.1:{port}", timeout=20.0, several=True)

    def listen():
        got.extend(sub)

    th = threading.Thread(target=listen, daemon=True)
    th.start()
    res = run("stream", session["csv"], "--port", port, "--speed", "0", "--rate", "2000",
              "--join-wait", "1.0")
    th.join(30)
    assert res.exit_code == 0, res.output
    sample = session["sample"]
    assert len(got) == len(sample) and sub.n_trackers == 2
    t, p, q = got[10]
    assert t == sample.t[10] and np.array_equal(p[1], sample.trackers[1].p[10])
    assert np.array_equal(q[0], sample.trackers[0].q[10])


@pytest.mark.parametrize("fmt", ["binary", "json"])
def test_live_over_zmq_with_two_controllers_gives_the_csv_events(session, fmt, loopback_only):
    port, out = free_port(), {}
    th = _publish(session["csv"], port, out, 2.0, fmt)
    got = _live(session["library"], f"zmq://127.0.0.1:{port}", "--timeout", "15")
    th.join(60)
    assert out["sent"] == len(session["sample"])
    assert got == session["events"]


def test_record_over_zmq_learns_the_trackers_from_the_first_message(session, tmp_path, loopback_only):
    port, out = free_port(), {}
    th = _publish(session["csv"], port, out, 1.0)
    res = run("record", "--source", f"zmq://127.0.0.1:{port}", "--gesture", "mixed", "--library",
              tmp_path / "lib", "--timeout", "15", "--tracker-names", "right,left")
    th.join(60)
    assert res.exit_code == 0, res.output
    assert "2 trackers (right, left)" in res.output
    assert len(list((tmp_path / "lib" / "mixed").glob("trial_*.csv"))) >= 6


def test_zmq_messages_must_bring_the_models_trackers(session, tmp_path, loopback_only):
    """A single-tracker publisher and models of two controllers: one line, exit 2."""
    single = tmp_path / "one.csv"
    session["sample"].trackers[0].slice_time(1000.0, 1003.0).to_csv(single)
    port, out = free_port(), {}
    th = _publish(single, port, out, 2.0)
    res = run("live", "--models", session["library"], "--source", f"zmq://127.0.0.1:{port}",
              "--timeout", "15", "--no-view")
    th.join(60)
    one_line_error(res, "a pose message of 1 tracker(s), but 2 are expected")


# -------------------------------------------------------------------------------------- bags
rosbags = pytest.importorskip("rosbags", reason="pip install 'framefree[ros]'")


def _bag(path: Path, sample, kind: str, shift: float = 0.0) -> Path:
    """A bag of the session: a PoseStamped topic per controller (``pose``) or both in /tf
    (``tf``, with a decoy transform); the second controller's stamps moved by ``shift`` [s]."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    from transports.test_rosbag import _header, _pose, _tf

    ts = get_typestore(Stores.ROS2_HUMBLE)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        conns: dict[str, object] = {}
        for k in range(len(sample)):
            for j, (name, tr) in enumerate(zip(NAMES, sample.trackers, strict=True)):
                t = float(sample.t[k]) + (shift if j else 0.0)
                if kind == "pose":
                    topic, mtype = f"/vive/{name}/pose", "geometry_msgs/msg/PoseStamped"
                    msg = ts.types[mtype](header=_header(t, "world"), pose=_pose(tr.p[k], tr.q[k]))
                else:
                    topic, mtype = "/tf", "tf2_msgs/msg/TFMessage"
                    msg = ts.types[mtype](transforms=[_tf(t, "world", "decoy", -tr.p[k], tr.q[k]),
                                                      _tf(t, "world", name, tr.p[k], tr.q[k])])
                if topic not in conns:
                    conns[topic] = w.add_connection(topic, mtype, typestore=ts)
                w.write(conns[topic], round(t * 1e9), ts.serialize_cdr(msg, mtype))
    return path


@pytest.mark.parametrize("kind,spec", [
    ("pose", "#/vive/controller_0/pose,/vive/controller_1/pose"),
    ("tf", "#/tf:world>controller_0,world>controller_1"),
    ("pose", ""),  # every pose topic of the bag
])
def test_live_from_a_bag_of_two_controllers_gives_the_csv_events(session, tmp_path, kind, spec):
    bag = _bag(tmp_path / "bag", session["sample"], kind)
    assert _same(_live(session["library"], f"{bag}{spec}"), session["events"])


def test_a_bag_whose_controllers_are_stamped_apart_is_joined(session, tmp_path):
    """The second controller stamped half a sample later: ScLERP between its messages; the
    same gestures come out at about the same times."""
    bag = _bag(tmp_path / "bag", session["sample"], "pose", shift=0.5 / 60.0)
    got = _live(session["library"], f"{bag}#/vive/controller_0/pose,/vive/controller_1/pose")
    want = session["events"]
    assert [e["label"] for e in got] == [e["label"] for e in want]
    assert np.allclose([e["time"] for e in got], [e["time"] for e in want], atol=0.1)


def test_record_from_a_bag_of_two_controllers(session, tmp_path):
    bag = _bag(tmp_path / "bag", session["sample"], "tf")
    res = run("record", "--source", f"{bag}#/tf:world>controller_0,world>controller_1",
              "--gesture", "mixed", "--library", tmp_path / "lib")
    assert res.exit_code == 0, res.output
    assert "2 trackers (controller_0, controller_1)" in res.output
    files = sorted((tmp_path / "lib" / "mixed").glob("trial_*.csv"))
    from_csv = run("record", "--source", session["csv"], "--gesture", "mixed", "--library",
                   tmp_path / "csv")
    assert from_csv.exit_code == 0
    assert len(files) == len(list((tmp_path / "csv" / "mixed").glob("trial_*.csv"))) >= 6


def test_bag_mistakes_are_one_line(session, tmp_path):
    bag = _bag(tmp_path / "bag", session["sample"], "tf")
    one_line_error(run("live", "--models", session["library"], "--source", f"{bag}#/tf",
                       "--no-view"), "1 pose topic(s)", "BAG#/right,/left")
    one_line_error(run("live", "--models", session["library"], "--source",
                       f"{bag}#/tf:world>controller_0,world>nobody", "--no-view"),
                   "0 poses")
    one_line_error(run("live", "--models", session["library"], "--source", f"{bag}#world>a,/tf",
                       "--no-view"), "give the topic first")
    # a single-tracker model set and a bag of two trackers
    one_line_error(run("live", "--models", session["library"], "--source", f"{bag}#/nope,/tf",
                       "--no-view"), "no topic /nope")


def test_bag_items_and_join_rules():
    assert bag_items("b#/tf:w>r,w>l,/odom") == [("/tf", ("w", "r")), ("/tf", ("w", "l")),
                                                  ("/odom", None)]
    assert bag_items("b") == []
    t = np.arange(0.0, 1.0, 0.01)
    q = np.tile([1.0, 0.0, 0.0, 0.0], (t.size, 1))
    p = np.column_stack([t, 0 * t, 0 * t])
    gap = (t < 0.4) | (t > 0.7)  # the second tracker lost between 0.4 and 0.7 s
    joined = join_tracks([(t, p, q), (t[gap] + 0.005, p[gap], q[gap])], ("a", "b"), "test")
    assert joined.names == ("a", "b")
    assert not ((joined.t > 0.41) & (joined.t < 0.69)).any()  # those times are left out
    inside = joined.t < 0.39
    assert np.allclose(joined["b"].p[inside, 0], joined.t[inside] - 0.005, atol=1e-9)
