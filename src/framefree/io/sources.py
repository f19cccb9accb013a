"""Pose sources for live sessions: CSV replay, ZeroMQ on loopback, and an optional OpenVR tracker.

Every source is an iterator of ``(t, p, q)``: time [s], position (3,) [m], quaternion (4,)
``(w, x, y, z)``.

ZeroMQ (its message format and loopback rule): :mod:`framefree.io.zeromq`.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.posecsv import UNITS, warn_if_implausible
from ..core.trajectory import Trajectory
from ..errors import FramefreeError
from .openvr_source import OpenVRSource
from .zeromq import (
    MESSAGE_FORMAT,
    Pose,
    ZmqPublisher,
    ZmqSource,
    check_loopback,
    decode_pose,
    encode_pose,
)

__all__ = [
    "MESSAGE_FORMAT",
    "CsvReplay",
    "OpenVRSource",
    "UnitsAndOrder",
    "ZmqPublisher",
    "ZmqSource",
    "carries_several",
    "check_loopback",
    "decode_pose",
    "encode_pose",
    "open_source",
]

class CsvReplay:
    """Replay a recording (8-column CSV or a :class:`Trajectory`).

    Parameters
    ----------
    source : str, Path or Trajectory
    speed : float
        1.0 replays in real time (following the file's time stamps), 2.0 twice as fast, 0 (or
        less) as fast as possible.
    rate : float, optional
        If given, pace the samples at this many per second instead of following the time stamps.
    """

    def __init__(self, source: str | Path | Trajectory | MultiTrajectory, speed: float = 1.0,
                 rate: float | None = None):
        self.traj = (source if isinstance(source, Trajectory | MultiTrajectory)
                     else Trajectory.from_csv(source))
        self.speed = float(speed)
        self.rate = rate

    @property
    def n_trackers(self) -> int:
        """Trackers per pose: 1, or a MultiTrajectory's (then p is (n, 3) and q (n, 4))."""
        return getattr(self.traj, "n_trackers", 1)

    def __iter__(self) -> Iterator[Pose]:
        tr = self.traj
        if isinstance(tr, MultiTrajectory):
            tr = _Stacked(tr)
        start = time.perf_counter()
        for k in range(len(tr)):
            if self.rate:
                due = k / self.rate
            elif self.speed > 0:
                due = (tr.t[k] - tr.t[0]) / self.speed
            else:
                due = 0.0
            wait = start + due - time.perf_counter()
            if wait > 0:
                time.sleep(wait)
            yield float(tr.t[k]), tr.p[k].copy(), tr.q[k].copy()


class _Stacked:
    """A MultiTrajectory's poses as arrays (N, n_trackers, 3) and (N, n_trackers, 4)."""

    def __init__(self, sample: MultiTrajectory) -> None:
        self.t = sample.t
        self.p = np.stack([tr.p for tr in sample.trackers], axis=1)
        self.q = np.stack([tr.q for tr in sample.trackers], axis=1)

    def __len__(self) -> int:
        return int(self.t.shape[0])


class UnitsAndOrder:
    """Convert a pose source's positions to metres and quaternions to scalar first, and warn once
    when its first samples look implausible for a hand (see :mod:`framefree.core.posecsv`).

    Parameters
    ----------
    source : iterable of (t, p, q)
    name : str
        Shown in warnings (the endpoint).
    quat_order : {"wxyz", "xyzw"}
        Order of the source's quaternions.
    units : {"m", "cm", "mm"}
        Unit of the source's positions.
    check_after : int
        Samples collected before the plausibility check.
    """

    def __init__(self, source: Iterable[Pose], name: str, quat_order: str = "wxyz",
                 units: str = "m", check_after: int = 250) -> None:
        self.source = source
        self.name = name
        self.scale = UNITS[units]
        self.order = [3, 0, 1, 2] if quat_order == "xyzw" else [0, 1, 2, 3]
        self.quat_order = quat_order
        self.check_after = check_after

    @property
    def timed_out(self) -> bool:
        """Whether the wrapped source ended for lack of data (see :attr:`ZmqSource.timed_out`)."""
        return bool(getattr(self.source, "timed_out", False))

    @property
    def n_trackers(self) -> int:
        """Trackers per pose of the wrapped source (1 unless it carries several)."""
        return int(getattr(self.source, "n_trackers", 1))

    def __iter__(self) -> Iterator[Pose]:
        first: list[np.ndarray] = []
        for t, p, q in self.source:
            p = p * self.scale
            q = q[..., self.order]  # (4,), or (n_trackers, 4)
            if len(first) < self.check_after:  # several trackers: the first one is looked at
                first.append(np.concatenate([[t], p.reshape(-1, 3)[0], q.reshape(-1, 4)[0]]))
                if len(first) == self.check_after:
                    warn_if_implausible(np.asarray(first), self.name, self.quat_order)
            yield t, p, q


def carries_several(spec: str) -> bool:
    """Whether a live or bag source spec names several trackers by itself (whatever the models):
    a ROS 2 bag with several topics (``BAG#/right,/left``) or several tf frames
    (``BAG#/tf:world>right,world>left``), or ZeroMQ with ``?trackers=N``, N > 1. An LSL stream's
    trackers are known once it is found (:class:`~framefree.io.lsl.LslSource`), a ZeroMQ
    stream's from its first message (:meth:`ZmqSource.peek`)."""
    rest = spec.partition("#")[2]
    return "," in rest and not spec.startswith(("lsl://", "zmq://", "tcp://", "ipc://", "ros2://"))


def open_source(
    spec: str, speed: float = 1.0, timeout: float | None = 5.0, quat_order: str = "wxyz",
    units: str = "m", several: bool = False,
):
    """Source from a command-line spec: ``zmq://127.0.0.1:PORT``, ``tcp://...``,
    ``openvr[#DEVICE,...]`` (:mod:`framefree.io.openvr_source`),
    ``lsl://NAME[#TRACKER]`` (:mod:`framefree.io.lsl`), a live ROS 2 topic ``ros2:///TOPIC``
    (:mod:`framefree.io.ros2`, where rclpy can be imported), a ROS 2 bag
    ``BAG[#TOPIC[:PARENT>CHILD]]`` (:mod:`framefree.io.rosbag`) or a CSV.

    The spec is checked here, before anything slow: a non-loopback endpoint, a missing file or a
    missing OpenVR raise :class:`FramefreeError`. ``quat_order`` and ``units`` describe the source's
    numbers (a CSV file's columns, or the pose messages).

    With ``several`` (models of several trackers), ``lsl://NAME`` yields every tracker of the
    stream at once (positions (n, 3), quaternions (n, 4)), ZeroMQ every tracker of each message,
    a bag every topic or tf frame named (``BAG#/right,/left``; without a topic, all its pose
    topics: :mod:`framefree.io.multi_bag`); a multi-tracker CSV file (:mod:`framefree.io.multicsv`)
    always does, and ``openvr`` every controller and generic tracker SteamVR reports (or the
    devices named). Live ROS 2 topics carry one tracker, and say so.
    """
    zmq = spec.startswith(("zmq://", "tcp://", "ipc://"))
    openvr = spec == "openvr" or spec.startswith("openvr#")
    if several and not spec.startswith("lsl://") and not zmq and not openvr and (
            spec.startswith("ros2://")
            or not (Path(spec).exists() or Path(spec.partition("#")[0]).exists())):
        raise FramefreeError(f"{spec}: this source carries one tracker, and the models have "
                             "several; use a multi-tracker CSV file, an LSL stream or ZeroMQ "
                             "messages of all the trackers, openvr, or a bag with a topic or tf "
                             "frame per tracker (docs/io.md)")
    if zmq:
        return UnitsAndOrder(ZmqSource(spec, timeout=timeout, several=several), spec, quat_order,
                             units)
    if openvr:
        return UnitsAndOrder(OpenVRSource.from_spec(spec, several), spec, quat_order, units)
    if spec.startswith("lsl://"):
        return _lsl(spec, several, quat_order, timeout, units)
    if spec.startswith("ros2://"):
        from .ros2 import Ros2PoseSource

        return UnitsAndOrder(Ros2PoseSource(spec, timeout=timeout), spec, "wxyz", units)
    return _file_or_bag(spec, speed, quat_order, units, several)


def _lsl(spec: str, several: bool, quat_order: str, timeout: float | None, units: str) -> Any:
    """``lsl://NAME[#TRACKER]``: one tracker, or every tracker with ``several``."""
    from .lsl import LslSource

    name, _, tracker = spec[len("lsl://"):].partition("#")
    if tracker and not tracker.isdigit():
        raise FramefreeError(f"{spec}: expected lsl://NAME or lsl://NAME#TRACKER_INDEX")
    if several and tracker:
        raise FramefreeError(f"{spec}: the models have several trackers; give lsl://{name} "
                             "(every tracker of the stream, in its channel order)")
    which = None if several else int(tracker or 0)
    lsl = LslSource(name, tracker=which, quat_order=quat_order, timeout=timeout)
    return UnitsAndOrder(lsl, spec, "wxyz", units)


def _file_or_bag(spec: str, speed: float, quat_order: str, units: str, several: bool) -> Any:
    """A ROS 2 bag (one topic, or several trackers: :mod:`framefree.io.multi_bag`) or a CSV file
    (one tracker, or a multi-tracker CSV)."""
    from .rosbag import RosbagSource, is_bag

    if is_bag(spec.partition("#")[0]):
        if several or carries_several(spec):
            from .multi_bag import multi_bag_sample

            return CsvReplay(multi_bag_sample(spec, units), speed=speed)
        return UnitsAndOrder(RosbagSource.from_spec(spec, speed=speed), spec, "wxyz", units)
    path = Path(spec)
    if not path.is_file():
        raise FramefreeError(f"{spec}: not a file, and not zmq://127.0.0.1:PORT, lsl://NAME, "
                             "a ROS 2 bag or 'openvr'")
    from .multicsv import has_tracker_header, read_multi_csv

    if has_tracker_header(path):
        if units != "m":
            raise FramefreeError(f"{spec}: a multi-tracker CSV file is in metres; --units "
                                 f"{units} does not apply")
        return CsvReplay(read_multi_csv(path), speed=speed)
    return CsvReplay(Trajectory.from_csv(path, quat_order=quat_order, units=units), speed=speed)
