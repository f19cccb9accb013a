"""The Machete gesture recording format (Taranta et al., ACM TOCHI 28(1), 2021; the HTC Vive
recordings published with the Machete segmenter, MIT licence).

One binary file per performance, little-endian, as a .NET ``BinaryWriter`` writes it:

1. the gesture name: a 7-bit variable-length byte count, then UTF-8 bytes;
2. ``int32`` speed tag, ``int32`` number of frames ``n``, ``int32`` values per frame ``v``
   (7 per tracker: ``px py pz qx qy qz qw``; 14 for two controllers);
3. ``n × v`` ``float32`` values, frame by frame, tracker by tracker;
4. ``int32`` number of time stamps (``n``), then that many ``float32`` time stamps [s].

Coordinates are Unity's (metres, left-handed, y up, quaternions scalar last): the reader converts
them with the ``unity`` convention (:mod:`framefree.io.conventions`) unless told otherwise. A frame
whose values are all zero is a tracking dropout and is left out (the count is kept in
:attr:`MacheteRecording.dropouts`).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import MIN_SAMPLES, Trajectory
from ..errors import TrajectoryError
from .conventions import UP, Convention, poses_to_framefree

__all__ = ["MacheteRecording", "read_machete"]

_VALUES_PER_TRACKER = 7


@dataclass(frozen=True)
class MacheteRecording:
    """One performance as stored, before any conversion.

    Attributes
    ----------
    gesture : str
        The gesture name written in the file.
    speed : int
        The speed tag written in the file.
    t : ndarray, shape (n,)
        Time stamps [s] (absolute, as recorded).
    values : ndarray, shape (n, v)
        The frames, 7 values per tracker, as stored (float64).
    dropouts : int
        Frames left out because every value was zero.
    """

    gesture: str
    speed: int
    t: np.ndarray
    values: np.ndarray
    dropouts: int

    @property
    def n_trackers(self) -> int:
        return self.values.shape[1] // _VALUES_PER_TRACKER


class _Reader:
    """Sequential little-endian reads that name the file and the byte offset when data run out."""

    def __init__(self, path: Path, data: bytes) -> None:
        self.path, self.data, self.pos = path, data, 0

    def take(self, n: int, what: str) -> bytes:
        if n < 0 or self.pos + n > len(self.data):
            raise TrajectoryError(f"{self.path}: byte {self.pos}: file ends inside the {what} "
                                  f"(needs {n} more bytes, {len(self.data) - self.pos} left); not a "
                                  "complete Machete recording")
        out = self.data[self.pos:self.pos + n]
        self.pos += n
        return out

    def int32(self, what: str) -> int:
        return struct.unpack("<i", self.take(4, what))[0]

    def varint(self) -> int:
        value, shift = 0, 0
        for _ in range(5):
            byte = self.take(1, "gesture name length")[0]
            value |= (byte & 0x7F) << shift
            if byte < 0x80:
                return value
            shift += 7
        raise TrajectoryError(f"{self.path}: byte 0: bad gesture name length; not a Machete recording")

    def float32s(self, count: int, what: str) -> np.ndarray:
        return np.frombuffer(self.take(4 * count, what), dtype="<f4").astype(np.float64)


def _parse(path: Path, data: bytes) -> MacheteRecording:
    r = _Reader(path, data)
    try:
        name = r.take(r.varint(), "gesture name").decode("utf-8")
    except UnicodeDecodeError:
        raise TrajectoryError(f"{path}: byte 1: the gesture name is not UTF-8; not a Machete "
                              "recording") from None
    speed, n, v = r.int32("speed tag"), r.int32("frame count"), r.int32("values per frame")
    if n < 0 or v <= 0 or v % _VALUES_PER_TRACKER:
        raise TrajectoryError(f"{path}: byte {r.pos - 8}: {n} frames of {v} values; expected a "
                              f"positive multiple of {_VALUES_PER_TRACKER} values per frame")
    values = r.float32s(n * v, "frames").reshape(n, v)
    n_t = r.int32("time stamp count")
    if n_t != n:
        raise TrajectoryError(f"{path}: byte {r.pos - 4}: {n_t} time stamps for {n} frames")
    t = r.float32s(n_t, "time stamps")
    if r.pos != len(data):
        raise TrajectoryError(f"{path}: byte {r.pos}: {len(data) - r.pos} bytes after the last time "
                              "stamp; not a Machete recording")
    kept = ~np.all(values == 0.0, axis=1)
    bad = np.flatnonzero(~np.all(np.isfinite(values), axis=1) | ~np.isfinite(t))
    if bad.size:
        raise TrajectoryError(f"{path}: frame {bad[0] + 1}: non-finite value")
    return MacheteRecording(name, speed, t[kept], values[kept], int(np.count_nonzero(~kept)))


def read_machete(
    path: str | Path,
    convention: str | Convention = "unity",
    names: tuple[str, ...] | None = None,
) -> MultiTrajectory:
    """Read a Machete recording as a :class:`~framefree.core.multitrajectory.MultiTrajectory`.

    Parameters
    ----------
    path : path
        One recording file.
    convention : str or Convention
        The coordinate convention of the stored poses (the format's own is ``"unity"``; see
        :mod:`framefree.io.conventions`).
    names : tuple of str, optional
        Tracker names (default ``controller_0``, ``controller_1``, ...; in the published Vive set
        controller 0 is the right hand).

    Returns
    -------
    MultiTrajectory
        Time starting at 0 s, poses in framefree's right-handed z-up frame, ``up`` = +z.

    Raises
    ------
    TrajectoryError
        For a file that is not a complete Machete recording, naming the file, the byte or frame,
        and the problem.
    """
    path = Path(path)
    if path.is_dir():
        raise TrajectoryError(f"{path}: is a folder, not a Machete recording")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise TrajectoryError(f"{path}: cannot read ({exc.strerror or exc})") from None
    rec = _parse(path, data)
    if rec.t.size < MIN_SAMPLES:
        raise TrajectoryError(f"{path}: {rec.t.size} tracked frames; at least {MIN_SAMPLES} are needed")
    order = np.argsort(rec.t, kind="stable")
    t = rec.t[order] - rec.t[order[0]]
    values = rec.values[order]
    keep = np.concatenate([[True], np.diff(t) > 0.0])  # repeated time stamps: keep the first
    t, values = t[keep], values[keep]
    names = names or tuple(f"controller_{k}" for k in range(rec.n_trackers))
    trackers = []
    for k in range(rec.n_trackers):
        block = values[:, _VALUES_PER_TRACKER * k:_VALUES_PER_TRACKER * (k + 1)]
        p, q = poses_to_framefree(block[:, :3], block[:, 3:], convention)
        trackers.append(Trajectory(t, p, q, source=f"{path}:{names[k]}"))
    return MultiTrajectory(tuple(trackers), tuple(names), UP, str(path))
