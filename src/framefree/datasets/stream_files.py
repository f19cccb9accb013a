"""Continuous labelled stream files: a pose CSV ``<name>.csv`` and its labels ``<name>_labels.csv``
(header ``label,start_t,end_t``; the label of a stop signal is ``stop``), as the replica writes
them (:func:`framefree.replica.streams.save_stream`) and as a user records them.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import Trajectory
from ..errors import DatasetError

__all__ = ["Segment", "labels_path", "load_stream", "write_labels"]


@dataclass(frozen=True)
class Segment:
    """A labelled stretch of a stream.

    Attributes
    ----------
    label : str
        Gesture name or ``"stop"``.
    start_t, end_t : float
        Movement onset and end [s], in the stream's clock.
    """

    label: str
    start_t: float
    end_t: float


def labels_path(path: str | Path) -> Path:
    """``<dir>/<name>_labels.csv`` beside the stream file ``<dir>/<name>.csv``."""
    path = Path(path)
    return path.with_name(f"{path.stem}_labels.csv")


def write_labels(path: str | Path, segments: Sequence[Segment]) -> Path:
    """Write a labels file ``label,start_t,end_t`` (times with full precision). Returns the path."""
    path = Path(path)
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["label", "start_t", "end_t"])
        for seg in segments:
            w.writerow([seg.label, repr(float(seg.start_t)), repr(float(seg.end_t))])
    return path


def load_stream(path: str | Path, quat_order: str = "wxyz"
                ) -> tuple[Trajectory | MultiTrajectory, list[Segment]]:
    """Read a stream CSV and its ``<name>_labels.csv``.

    A file whose header row names trackers (``t,right.x,...``, framefree's multi-tracker CSV,
    :mod:`framefree.io.multicsv`) is read as several trackers, a
    :class:`~framefree.core.multitrajectory.MultiTrajectory` (its header gives the quaternion
    order); any other as one tracker.

    Raises
    ------
    DatasetError
        If the labels file is missing or malformed (naming the file and row).
    """
    from ..io.multicsv import has_tracker_header, read_multi_csv

    path = Path(path)
    if has_tracker_header(path):
        traj: Trajectory | MultiTrajectory = read_multi_csv(path)
    else:
        traj = Trajectory.from_csv(path, quat_order=quat_order)
    lp = labels_path(path)
    if not lp.is_file():
        raise DatasetError(f"{lp}: labels file missing for stream {path}")
    segments = []
    with lp.open(newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows or [c.strip() for c in rows[0]] != ["label", "start_t", "end_t"]:
        raise DatasetError(f"{lp}, row 1: expected the header 'label,start_t,end_t'")
    for i, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != 3:
            raise DatasetError(f"{lp}, row {i}: expected 3 columns, found {len(row)}")
        try:
            a, b = float(row[1]), float(row[2])
        except ValueError:
            raise DatasetError(f"{lp}, row {i}: start_t and end_t must be numbers") from None
        if not (math.isfinite(a) and math.isfinite(b)) or b < a:
            raise DatasetError(f"{lp}, row {i}: need finite start_t <= end_t, got {a}, {b}")
        segments.append(Segment(row[0].strip(), a, b))
    return traj, segments
