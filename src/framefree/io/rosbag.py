"""ROS 2 bags without ROS (``rosbags``): poses from PoseStamped, TransformStamped/tf or Odometry.

``--source BAG`` (a bag folder with ``metadata.yaml``, or a ``.db3`` / ``.mcap`` file) with an
optional ``#TOPIC`` (default: the only pose topic in the bag); for tf give the frames,
``BAG#/tf:PARENT>CHILD``. Both storages (sqlite3 and MCAP) are read.

Convention: ROS's (REP 103) — right-handed, z up, metres, quaternions scalar last in the message
(``x, y, z, w``); poses come out scalar first ``(w, x, y, z)`` like every framefree source. The
time of a pose is its header stamp [s] (``sec + nanosec·1e-9``), i.e. the
recording system's clock.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ..errors import FramefreeError

__all__ = ["POSE_TYPES", "RosbagSource", "is_bag"]

_MISSING = "ROS 2 bags need rosbags: pip install 'framefree[ros]'"

POSE_TYPES = ("geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/TransformStamped",
              "tf2_msgs/msg/TFMessage", "nav_msgs/msg/Odometry")


def is_bag(path: str | Path) -> bool:
    """Whether ``path`` looks like a ROS 2 bag (folder with metadata.yaml, .db3 or .mcap file)."""
    p = Path(path)
    return (p.is_dir() and (p / "metadata.yaml").is_file()) or (
        p.is_file() and p.suffix in (".db3", ".mcap"))


def _stamp(header) -> float:
    """Header stamp [s]: the nearest double to ``sec + nanosec·1e-9`` (one correctly rounded
    division of the whole nanoseconds)."""
    return (int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)) / 1e9


def _pq(position, orientation) -> tuple[np.ndarray, np.ndarray]:
    return (np.array([position.x, position.y, position.z], dtype=float),
            np.array([orientation.w, orientation.x, orientation.y, orientation.z], dtype=float))


class RosbagSource:
    """Replay the poses of one topic of a ROS 2 bag.

    Parameters
    ----------
    path : str or Path
        Bag folder or storage file.
    topic : str, optional
        Topic to read (default: the only topic of a pose type).
    frames : (str, str), optional
        ``(parent, child)`` frame ids of the transform to follow (TransformStamped / tf);
        required when the topic carries several.
    speed : float
        1.0 replays at recorded speed (following the stamps), 2.0 twice as fast, 0 as fast as
        possible.
    """

    def __init__(self, path: str | Path, topic: str | None = None,
                 frames: tuple[str, str] | None = None, speed: float = 0.0) -> None:
        try:
            from rosbags.highlevel import AnyReader
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self.path = Path(path)
        if not is_bag(self.path):
            raise FramefreeError(f"{path}: not a ROS 2 bag (a folder with metadata.yaml, .db3 or .mcap)")
        self._reader_cls = AnyReader
        self.frames = frames
        self.speed = float(speed)
        paths = [self.path.parent if self.path.is_file() and
                 (self.path.parent / "metadata.yaml").is_file() else self.path]
        self._paths = paths
        try:
            with AnyReader(paths) as reader:
                topics = {c.topic: c.msgtype for c in reader.connections}
        except Exception as exc:  # rosbags raises its own error types for broken bags
            raise FramefreeError(f"{path}: cannot read the bag ({exc})") from None
        poses = [t for t, ty in topics.items() if ty in POSE_TYPES]
        if topic is None:
            if len(poses) != 1:
                raise FramefreeError(f"{path}: {len(poses)} pose topics ({', '.join(poses) or 'none'}); "
                                     "choose one with BAG#TOPIC")
            topic = poses[0]
        if topic not in topics:
            raise FramefreeError(f"{path}: no topic {topic} (topics: {', '.join(sorted(topics))})")
        if topics[topic] not in POSE_TYPES:
            raise FramefreeError(f"{path}#{topic}: type {topics[topic]} is not one of "
                                 f"{', '.join(POSE_TYPES)}")
        self.topic, self.msgtype = topic, topics[topic]

    @classmethod
    def from_spec(cls, spec: str, speed: float = 0.0) -> RosbagSource:
        """Source from ``BAG``, ``BAG#TOPIC`` or ``BAG#TOPIC:PARENT>CHILD``."""
        path, _, rest = spec.partition("#")
        topic, frames = rest or None, None
        if topic and ":" in topic:
            topic, _, fr = topic.partition(":")
            parent, sep, child = fr.partition(">")
            if not sep or not parent or not child:
                raise FramefreeError(f"{spec}: frames are written TOPIC:PARENT>CHILD")
            frames = (parent, child)
        return cls(path, topic or None, frames, speed)

    def _transforms(self, msg) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        items = msg.transforms if self.msgtype == "tf2_msgs/msg/TFMessage" else [msg]
        for tf in items:
            if self.frames is None or (tf.header.frame_id.lstrip("/") == self.frames[0].lstrip("/")
                                       and tf.child_frame_id.lstrip("/") == self.frames[1].lstrip("/")):
                tr = tf.transform
                yield (_stamp(tf.header), *_pq(tr.translation, tr.rotation))

    def _poses(self, msg) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        if self.msgtype == "geometry_msgs/msg/PoseStamped":
            yield (_stamp(msg.header), *_pq(msg.pose.position, msg.pose.orientation))
        elif self.msgtype == "nav_msgs/msg/Odometry":
            yield (_stamp(msg.header), *_pq(msg.pose.pose.position, msg.pose.pose.orientation))
        else:
            yield from self._transforms(msg)

    def __iter__(self) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        start, t_first = time.perf_counter(), None
        with self._reader_cls(self._paths) as reader:
            conns = [c for c in reader.connections if c.topic == self.topic]
            for conn, _, raw in reader.messages(connections=conns):
                for t, p, q in self._poses(reader.deserialize(raw, conn.msgtype)):
                    if t_first is None:
                        t_first = t
                    if self.speed > 0:
                        wait = start + (t - t_first) / self.speed - time.perf_counter()
                        if wait > 0:
                            time.sleep(wait)
                    yield t, p, q
