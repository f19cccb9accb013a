"""Live ROS 2 topics through rclpy: poses in (``--source ros2:///TOPIC``) and gestures out
(``--emit ros2:///TOPIC``).

* Poses: ``geometry_msgs/PoseStamped`` (what motion-capture drivers such as vrpn_client_ros,
  mocap4r2 or the OptiTrack and Vicon bridges publish), or ``nav_msgs/Odometry`` with
  ``ros2:///TOPIC#odometry``. A pose's time is its ``header.stamp`` (the publisher's clock).
  ROS's frame convention (REP 103: right-handed, z up, quaternions stored x, y, z, w) is
  framefree's frame; the quaternion is reordered to scalar first.
* Gestures: ``std_msgs/String`` messages carrying the event record as JSON
  (:func:`framefree.io.outputs.event_record`: label, time on the source's clock, distance,
  threshold, model).

rclpy comes with a ROS 2 installation, not from PyPI. Without it, these specs fail in one line that
says what to do (record a bag with ``ros2 bag record`` and replay it with ``--source BAG``,
:mod:`framefree.io.rosbag`, needs no ROS). ROS 2 discovery is the DDS middleware's: set
``ROS_LOCALHOST_ONLY=1`` (or ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``) to keep it on this machine.
"""

from __future__ import annotations

import json
import time
from collections import deque
from collections.abc import Iterator
from typing import Any

import numpy as np

from ..errors import FramefreeError

__all__ = ["ROS2_MISSING", "Ros2Emitter", "Ros2PoseSource", "import_rclpy", "parse_topic"]

#: what a user without rclpy reads
ROS2_MISSING = ("live ROS 2 topics need rclpy, which comes with ROS 2, not from PyPI: install ROS 2 "
                "and `source /opt/ros/<distro>/setup.bash` before framefree; or record a bag "
                "(`ros2 bag record TOPIC`) and replay it with --source BAG (no ROS needed)")


def import_rclpy() -> Any:
    """rclpy, initialized once; :class:`FramefreeError` with :data:`ROS2_MISSING` without it."""
    try:
        import rclpy
    except ImportError:
        raise FramefreeError(ROS2_MISSING) from None
    if not rclpy.ok():
        rclpy.init()
    return rclpy


def parse_topic(spec: str) -> tuple[str, str]:
    """``ros2:///TOPIC[#odometry]`` → (topic, message kind ``"pose"`` or ``"odometry"``)."""
    if not spec.startswith("ros2://"):
        raise FramefreeError(f"{spec}: expected ros2:///TOPIC")
    topic, _, kind = spec[len("ros2://"):].partition("#")
    if not topic.startswith("/") or len(topic) < 2:
        raise FramefreeError(f"{spec}: expected ros2:///TOPIC (an absolute topic name, e.g. "
                             "ros2:///tracker/pose)")
    if kind not in ("", "pose", "odometry"):
        raise FramefreeError(f"{spec}: #{kind}: the message kind is #pose (PoseStamped, the "
                             "default) or #odometry")
    return topic, kind or "pose"


def _stamp(header: Any) -> float:
    return float(header.stamp.sec) + 1e-9 * float(header.stamp.nanosec)


class Ros2PoseSource:
    """Poses of a live ROS 2 topic, as ``(t, p, q)`` with ``q`` scalar first.

    Parameters
    ----------
    spec : str
        ``ros2:///TOPIC`` or ``ros2:///TOPIC#odometry``.
    timeout : float, optional
        End the stream after this many seconds without a message (``None``: never).
    queue : int
        At most this many received poses are kept while the consumer is busy (memory stays
        bounded; the oldest are dropped and counted in :attr:`dropped`).
    """

    def __init__(self, spec: str, timeout: float | None = 5.0, queue: int = 1000) -> None:
        self.topic, kind = parse_topic(spec)
        self.rclpy = import_rclpy()
        from rclpy.node import Node

        if kind == "odometry":
            from nav_msgs.msg import Odometry as message
        else:
            from geometry_msgs.msg import PoseStamped as message
        self.timeout = timeout
        self.dropped = 0
        self._poses: deque[tuple[float, np.ndarray, np.ndarray]] = deque(maxlen=queue)
        self.node = Node("framefree_pose_source")
        self.node.create_subscription(message, self.topic, self._on_message, 10)

    def _on_message(self, msg: Any) -> None:
        pose = msg.pose.pose if hasattr(msg.pose, "pose") else msg.pose
        p, o = pose.position, pose.orientation
        if len(self._poses) == self._poses.maxlen:
            self.dropped += 1
        self._poses.append((_stamp(msg.header), np.array([p.x, p.y, p.z]),
                            np.array([o.w, o.x, o.y, o.z])))

    def __iter__(self) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        last = time.monotonic()
        try:
            while self.rclpy.ok():
                while self._poses:
                    last = time.monotonic()
                    yield self._poses.popleft()
                if self.timeout is not None and time.monotonic() - last > self.timeout:
                    return
                self.rclpy.spin_once(self.node, timeout_sec=0.05)
        finally:
            self.close()

    def close(self) -> None:
        """Leave the ROS graph."""
        if self.node is not None:
            self.node.destroy_node()
            self.node = None


class Ros2Emitter:
    """Gesture events as ``std_msgs/String`` JSON messages on a ROS 2 topic (``--emit ros2:///TOPIC``)."""

    def __init__(self, spec: str) -> None:
        self.topic, _ = parse_topic(spec)
        rclpy = import_rclpy()
        from rclpy.node import Node
        from std_msgs.msg import String

        self._string = String
        self._rclpy = rclpy
        self.node = Node("framefree_gestures")
        self._publisher = self.node.create_publisher(String, self.topic, 10)

    def emit(self, record: dict[str, Any]) -> None:
        """Publish one event record."""
        msg = self._string()
        msg.data = json.dumps(record)
        self._publisher.publish(msg)

    def close(self) -> None:
        """Leave the ROS graph."""
        if self.node is not None:
            self.node.destroy_node()
            self.node = None
