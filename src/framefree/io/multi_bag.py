"""Several trackers from one ROS 2 bag: a pose topic or a tf transform per tracker, joined on one
time base (read with ``rosbags``, no ROS needed; :class:`~framefree.io.rosbag.RosbagSource` reads
each tracker).

Spec: ``BAG#ITEM,ITEM,...``, each item a topic (``/right/pose``), a topic with the transform to
follow (``/tf:world>right``), or, after a tf item, just the frames (``world>left``: the same
topic). ``BAG`` alone, with models of several trackers, takes every pose topic of the bag (sorted
by name). Tracker names: the child frame of a tf item, else the topic's last part that is not
``pose``/``odom`` (``/vive/right/pose`` → ``right``), else the whole topic.

Joining: the first tracker's stamps are the time base (within the span every tracker covers);
each other tracker's pose at those times is its own where the stamps are equal (one driver
publishing every tracker at once) and ScLERP between its two nearest messages otherwise. A time
where another tracker has no message within ``max(0.1 s, 3 ×`` its median period``)`` before and
after (it lost tracking) is left out; the recognizer's gate bridges the gap.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..core import se3
from ..core.multitrajectory import MultiTrajectory
from ..core.posecsv import UNITS
from ..core.trajectory import MIN_SAMPLES, Trajectory
from ..errors import FramefreeError
from .conventions import UP
from .rosbag import POSE_TYPES, RosbagSource

__all__ = ["bag_items", "join_tracks", "multi_bag_sample"]

Item = tuple[str, tuple[str, str] | None]
Track = tuple[np.ndarray, np.ndarray, np.ndarray]

_GENERIC = {"pose", "poses", "odom", "odometry", "pose_stamped", "transform"}


def bag_items(spec: str) -> list[Item]:
    """``(topic, (parent, child) or None)`` of each tracker a multi-tracker bag spec names (an
    empty list for ``BAG`` alone)."""
    _, _, rest = spec.partition("#")
    items: list[Item] = []
    for part in (p.strip() for p in rest.split(",") if rest):
        topic, frames = part, None
        if ">" in part:
            topic, _, fr = part.rpartition(":") if ":" in part else ("", "", part)
            if not topic:
                if not items:
                    raise FramefreeError(f"{spec}: {part}: give the topic first (/tf:{part})")
                topic = items[-1][0]
            parent, _, child = fr.partition(">")
            if not parent or not child:
                raise FramefreeError(f"{spec}: {part}: frames are written PARENT>CHILD")
            frames = (parent, child)
        if not topic:
            raise FramefreeError(f"{spec}: an empty tracker item")
        items.append((topic, frames))
    return items


def _name(item: Item) -> str:
    topic, frames = item
    if frames is not None:
        return frames[1].strip("/").replace("/", "_")
    parts = [p for p in topic.strip("/").split("/") if p and p.lower() not in _GENERIC]
    return parts[-1] if parts else topic


def _all_pose_topics(path: str) -> list[Item]:
    from rosbags.highlevel import AnyReader

    bag = Path(path)
    folder = bag.parent if bag.is_file() and (bag.parent / "metadata.yaml").is_file() else bag
    with AnyReader([folder]) as reader:
        topics = sorted({c.topic for c in reader.connections if c.msgtype in POSE_TYPES})
    return [(t, None) for t in topics]


def _read(path: str, item: Item, spec: str) -> Track:
    """Times (N,) [s], positions (N, 3), quaternions (N, 4) of one tracker, sorted by stamp
    (a repeated stamp keeps its first message)."""
    src = RosbagSource(path, item[0], item[1], speed=0.0)
    rows = [(t, p, q) for t, p, q in src]
    where = f"{spec} ({item[0]}{'' if item[1] is None else ':' + '>'.join(item[1])})"
    if len(rows) < MIN_SAMPLES:
        raise FramefreeError(f"{where}: {len(rows)} poses; at least {MIN_SAMPLES} are needed")
    t = np.array([r[0] for r in rows])
    order = np.argsort(t, kind="stable")
    t = t[order]
    keep = np.concatenate([[True], np.diff(t) > 0])
    p = np.array([r[1] for r in rows])[order][keep]
    q = np.array([r[2] for r in rows])[order][keep]
    return t[keep], p, q


def _at(track: Track, base: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions (M, 3), quaternions (M, 4) of a track at the times ``base`` (M,), and which
    times it covers (a message within its gap limit on both sides)."""
    t, p, q = track
    idx = np.clip(np.searchsorted(t, base), 1, t.size - 1)
    max_gap = max(0.1, 3.0 * float(np.median(np.diff(t))))
    covered = (t[idx] - t[idx - 1] <= max_gap) & (base >= t[0]) & (base <= t[-1])
    exact = np.isin(base, t)
    T = np.repeat(np.eye(4)[None], t.size, axis=0)
    T[:, :3, :3] = se3.matrix_from_quaternion(q)
    T[:, :3, 3] = p
    inside = np.clip(base, t[0], t[-1])
    Tq = se3.interpolate_poses(t - t[0], T, inside - t[0])
    qq = se3.quaternion_from_matrix(Tq[:, :3, :3], continuous=False)
    pos = Tq[:, :3, 3].copy()
    j = np.searchsorted(t, base[exact])
    pos[exact], qq[exact] = p[j], q[j]
    return pos, qq, covered


def join_tracks(tracks: Sequence[Track], names: Sequence[str], source: str) -> MultiTrajectory:
    """One :class:`~framefree.core.multitrajectory.MultiTrajectory` of tracks recorded apart
    (see the module docstring for the rule).

    Parameters
    ----------
    tracks : sequence of (t (N_k,), p (N_k, 3), q (N_k, 4))
        Each tracker's stamps [s] (strictly increasing), positions [m] and quaternions (w, x, y, z).
    names : sequence of str
    source : str
        For messages.

    Raises
    ------
    FramefreeError
        When the trackers share fewer than the samples a recording needs.
    """
    t0 = tracks[0][0]
    lo, hi = max(tr[0][0] for tr in tracks), min(tr[0][-1] for tr in tracks)
    base = t0[(t0 >= lo) & (t0 <= hi)]
    if base.size < MIN_SAMPLES:
        raise FramefreeError(f"{source}: the trackers share {base.size} time stamps' span; they "
                             "were not recorded together")
    columns = [(tracks[0][1][(t0 >= lo) & (t0 <= hi)], tracks[0][2][(t0 >= lo) & (t0 <= hi)])]
    keep = np.ones(base.size, dtype=bool)
    for tr in tracks[1:]:
        pos, quat, covered = _at(tr, base)
        columns.append((pos, quat))
        keep &= covered
    if keep.sum() < MIN_SAMPLES:
        raise FramefreeError(f"{source}: the trackers have messages together at {int(keep.sum())} "
                             "times only")
    trackers = tuple(Trajectory(base[keep], p[keep], q[keep], source=f"{source}:{n}")
                     for (p, q), n in zip(columns, names, strict=True))
    return MultiTrajectory(trackers, tuple(names), UP, source)


def multi_bag_sample(spec: str, units: str = "m") -> MultiTrajectory:
    """The trackers a bag spec names (``BAG#ITEM,...``, or every pose topic of ``BAG``), joined
    on one time base, positions in metres (``units``: the bag's unit)."""
    path = spec.partition("#")[0]
    items = bag_items(spec) or _all_pose_topics(path)
    if len(items) < 2:
        raise FramefreeError(f"{spec}: {len(items)} pose topic(s); name a topic or tf frame per "
                             "tracker: BAG#/right,/left or BAG#/tf:world>right,world>left")
    names = [_name(it) for it in items]
    if len(set(names)) != len(names):
        names = [f"{it[0]}:{'>'.join(it[1])}" if it[1] else it[0] for it in items]
    if len(set(names)) != len(names):
        raise FramefreeError(f"{spec}: a tracker is named twice")
    tracks = [_read(path, it, spec) for it in items]
    scale = UNITS[units]
    tracks = [(t, p * scale, q) for t, p, q in tracks]
    return join_tracks(tracks, names, spec)
