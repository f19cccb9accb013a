"""framefree's CSV for several trackers recorded together.

One header row, then one row per sample: the time, then seven columns per tracker::

    t,right.x,right.y,right.z,right.qw,right.qx,right.qy,right.qz,left.x,left.y,...,left.qz
    0.000,0.153,0.079,1.150,0.71,0.02,-0.01,0.70,...

Time in seconds, strictly increasing; positions in metres; quaternions in the column order the
header names (``qw qx qy qz`` or ``qx qy qz qw``, the same for every tracker). The header's tracker
names (the part before the dot) name the trackers. Poses are in framefree's frame (right-handed,
z up) unless the reader is given another convention (:mod:`framefree.io.conventions`).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.posecsv import header_kind
from ..core.trajectory import MIN_SAMPLES, Trajectory
from ..errors import TrajectoryError
from .conventions import UP, Convention, get_convention, poses_to_framefree

__all__ = ["has_tracker_header", "read_multi_csv", "write_multi_csv"]

_POS = ("x", "y", "z")
_QUAT = {"wxyz": ("qw", "qx", "qy", "qz"), "xyzw": ("qx", "qy", "qz", "qw")}


def has_tracker_header(path: str | Path) -> bool:
    """Whether ``path`` is a file whose first row names trackers (``t,NAME.x,...``): this format,
    not a single-tracker CSV (whose header, if any, is ``t,x,y,z,qw,qx,qy,qz``). A malformed
    tracker header still counts, so that its reader names the faulty columns."""
    path = Path(path)
    if not path.is_file():
        return False
    with path.open("rb") as fh:
        head = fh.read(4096)
    if not head.startswith((b"t,", b"t\r", b"t\n")):
        return False
    first = head.decode("utf-8", errors="replace").splitlines()[0]
    return header_kind(first) == "multi" or "." in first


def _parse_header(path: Path, header: list[str]) -> tuple[list[str], str]:
    """Tracker names and quaternion order from the header row."""
    cells = [c.strip() for c in header]
    if not cells or cells[0] != "t" or (len(cells) - 1) % 7 or len(cells) < 8:
        raise TrajectoryError(f"{path}, row 1: expected the header 't,<name>.x,<name>.y,<name>.z,"
                              f"<name>.qw,<name>.qx,<name>.qy,<name>.qz,...' (7 columns per tracker)")
    names, order = [], None
    for k in range(1, len(cells), 7):
        group = cells[k:k + 7]
        name = group[0].rpartition(".")[0]
        fields = tuple(c.rpartition(".")[2] for c in group)
        prefixes = {c.rpartition(".")[0] for c in group}
        this = next((o for o, qf in _QUAT.items() if fields == (*_POS, *qf)), None)
        if not name or len(prefixes) != 1 or this is None:
            raise TrajectoryError(f"{path}, row 1, columns {k + 1}-{k + 7}: expected "
                                  f"'{name or 'NAME'}.x,.y,.z' then '.qw,.qx,.qy,.qz' or "
                                  f"'.qx,.qy,.qz,.qw', found {','.join(group)}")
        if order is not None and this != order:
            raise TrajectoryError(f"{path}, row 1: every tracker must use the same quaternion order")
        order = this
        names.append(name)
    if len(set(names)) != len(names):
        raise TrajectoryError(f"{path}, row 1: tracker names must be unique, found {names}")
    return names, order or "wxyz"


def _parse_rows(path: Path, rows: list[list[str]], width: int) -> np.ndarray:
    data = np.empty((len(rows), width))
    for i, row in enumerate(rows):
        if len(row) != width:
            raise TrajectoryError(f"{path}, row {i + 2}: {len(row)} columns, expected {width}")
        try:
            data[i] = [float(c) for c in row]
        except ValueError:
            raise TrajectoryError(f"{path}, row {i + 2}: a value is not a number") from None
    bad = np.flatnonzero(~np.all(np.isfinite(data), axis=1))
    if bad.size:
        raise TrajectoryError(f"{path}, row {bad[0] + 2}: non-finite value")
    step = np.diff(data[:, 0])
    if np.any(step <= 0):
        k = int(np.flatnonzero(step <= 0)[0])
        raise TrajectoryError(f"{path}, row {k + 3}: time does not increase ({data[k + 1, 0]} after "
                              f"{data[k, 0]})")
    return data


def read_multi_csv(path: str | Path, convention: str | Convention = "framefree") -> MultiTrajectory:
    """Read a multi-tracker CSV (see the module docstring).

    Parameters
    ----------
    path : path
    convention : str or Convention
        Handedness and vertical of the stored poses (default: framefree's own, right-handed z up).
        The quaternion order comes from the header, not from the convention.

    Returns
    -------
    MultiTrajectory

    Raises
    ------
    TrajectoryError
        Naming the file, the row and the problem.
    """
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            rows = [r for r in csv.reader(fh) if r]
    except (OSError, UnicodeDecodeError) as exc:
        raise TrajectoryError(f"{path}: cannot read as text ({exc})") from None
    if not rows:
        raise TrajectoryError(f"{path}: empty file")
    names, order = _parse_header(path, rows[0])
    data = _parse_rows(path, rows[1:], 1 + 7 * len(names))
    if data.shape[0] < MIN_SAMPLES:
        raise TrajectoryError(f"{path}: {data.shape[0]} samples; at least {MIN_SAMPLES} are needed")
    conv = get_convention(convention)
    as_read = Convention(conv.name, conv.handedness, conv.up, order, conv.basis)
    trackers = []
    for k, name in enumerate(names):
        block = data[:, 1 + 7 * k:8 + 7 * k]
        p, q = poses_to_framefree(block[:, :3], block[:, 3:], as_read)
        trackers.append(Trajectory(data[:, 0], p, q, source=f"{path}:{name}"))
    return MultiTrajectory(tuple(trackers), tuple(names), UP, str(path))


def write_multi_csv(path: str | Path, sample: MultiTrajectory) -> Path:
    """Write ``sample`` as a multi-tracker CSV (framefree's frame, ``qw qx qy qz``, full precision).

    Returns
    -------
    Path
    """
    path = Path(path)
    header = ["t"] + [f"{n}.{f}" for n in sample.names for f in (*_POS, *_QUAT["wxyz"])]
    data = np.column_stack([sample.t] + [np.column_stack([tr.p, tr.q]) for tr in sample.trackers])
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        fh.write(",".join(header) + "\n")
        np.savetxt(fh, data, delimiter=",", fmt="%.17g")
    return path
