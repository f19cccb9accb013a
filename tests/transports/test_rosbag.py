"""ROS 2 bags without ROS: a replica session written with ``rosbags`` (sqlite3 and MCAP; PoseStamped,
tf with a chosen parent/child, Odometry) replays into the same events as the CSV."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.datasets import load_stream
from framefree.errors import FramefreeError
from framefree.io.rosbag import RosbagSource

rosbags = pytest.importorskip("rosbags", reason="pip install 'framefree[ros]'")
from rosbags.rosbag2 import StoragePlugin, Writer  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

TS = get_typestore(Stores.ROS2_HUMBLE)
M = TS.types


def _header(t: float, frame: str):
    ns = round(t * 1e9)
    return M["std_msgs/msg/Header"](stamp=M["builtin_interfaces/msg/Time"](
        sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000), frame_id=frame)


def _pose(p, q):
    return M["geometry_msgs/msg/Pose"](position=M["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2]),
                                       orientation=M["geometry_msgs/msg/Quaternion"](
                                           x=q[1], y=q[2], z=q[3], w=q[0]))


def _tf(t, parent, child, p, q):
    tr = M["geometry_msgs/msg/Transform"](
        translation=M["geometry_msgs/msg/Vector3"](x=p[0], y=p[1], z=p[2]),
        rotation=M["geometry_msgs/msg/Quaternion"](x=q[1], y=q[2], z=q[3], w=q[0]))
    return M["geometry_msgs/msg/TransformStamped"](header=_header(t, parent), child_frame_id=child,
                                                   transform=tr)


def _message(kind: str, t: float, p, q):
    if kind == "pose":
        return "/tracker/pose", "geometry_msgs/msg/PoseStamped", M["geometry_msgs/msg/PoseStamped"](
            header=_header(t, "world"), pose=_pose(p, q))
    if kind == "odom":
        cov = np.zeros(36)
        return "/odom", "nav_msgs/msg/Odometry", M["nav_msgs/msg/Odometry"](
            header=_header(t, "world"), child_frame_id="tracker",
            pose=M["geometry_msgs/msg/PoseWithCovariance"](pose=_pose(p, q), covariance=cov),
            twist=M["geometry_msgs/msg/TwistWithCovariance"](
                twist=M["geometry_msgs/msg/Twist"](linear=M["geometry_msgs/msg/Vector3"](x=0, y=0, z=0),
                                                   angular=M["geometry_msgs/msg/Vector3"](x=0, y=0, z=0)),
                covariance=cov))
    # tf: the tracker beside a decoy transform that must be ignored
    return "/tf", "tf2_msgs/msg/TFMessage", M["tf2_msgs/msg/TFMessage"](transforms=[
        _tf(t, "world", "decoy", -np.asarray(p), q), _tf(t, "world", "tracker", p, q)])


def write_bag(path: Path, traj, kind: str, storage: StoragePlugin) -> Path:
    """A bag of the session's poses, one message per sample, stamped with its time."""
    with Writer(path, version=9, storage_plugin=storage) as w:
        conn = None
        for k in range(len(traj)):
            topic, msgtype, msg = _message(kind, float(traj.t[k]), traj.p[k], traj.q[k])
            if conn is None:
                conn = w.add_connection(topic, msgtype, typestore=TS)
            w.write(conn, round(float(traj.t[k]) * 1e9), TS.serialize_cdr(msg, msgtype))
    return path


@pytest.fixture(scope="module")
def csv_events(tiny, tmp_path_factory) -> list[dict]:
    root, stream = tiny
    out = tmp_path_factory.mktemp("ev") / "eval.jsonl"
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(root), "--stream", str(stream),
                                   "--emit", f"jsonl:{out}"])
    assert res.exit_code == 0, res.output
    events = [json.loads(s) for s in out.read_text().splitlines()]
    assert any(e["label"] != "stop" for e in events)
    return events


@pytest.mark.parametrize("storage", [StoragePlugin.SQLITE3, StoragePlugin.MCAP], ids=["sqlite3", "mcap"])
@pytest.mark.parametrize(("kind", "suffix"), [("pose", ""), ("tf", "#/tf:world>tracker"), ("odom", "")])
def test_bag_replay_gives_the_csv_events(tiny, csv_events, tmp_path, storage, kind, suffix,
                                         loopback_only):
    root, stream = tiny
    traj, _ = load_stream(stream)
    bag = write_bag(tmp_path / "bag", traj, kind, storage)
    src = list(RosbagSource.from_spec(f"{bag}{suffix}"))
    assert len(src) == len(traj)
    np.testing.assert_array_equal([s[0] for s in src], traj.t)
    np.testing.assert_array_equal(np.array([s[1] for s in src]), traj.p)
    np.testing.assert_array_equal(np.array([s[2] for s in src]), traj.q)
    out = tmp_path / "live.jsonl"
    res = CliRunner().invoke(cli, ["live", "--models", str(root), "--source", f"{bag}{suffix}",
                                   "--speed", "0", "--no-view", "--emit", f"jsonl:{out}"])
    assert res.exit_code == 0, res.output
    assert [json.loads(s) for s in out.read_text().splitlines()] == csv_events


def test_bag_errors_are_one_line(tiny, tmp_path):
    traj, _ = load_stream(tiny[1])
    bag = write_bag(tmp_path / "bag", traj, "tf", StoragePlugin.SQLITE3)
    with pytest.raises(FramefreeError, match="no topic"):
        RosbagSource.from_spec(f"{bag}#/nope")
    with pytest.raises(FramefreeError, match="PARENT>CHILD"):
        RosbagSource.from_spec(f"{bag}#/tf:world")
    with pytest.raises(FramefreeError, match="not a ROS 2 bag"):
        RosbagSource(tmp_path)
    res = CliRunner().invoke(cli, ["live", "--models", str(tiny[0]), "--source", f"{bag}#/nope",
                                   "--no-view"])
    assert res.exit_code == 2 and "no topic /nope" in res.output
