"""Takes of several trackers: one long multi-tracker recording of a gesture performed again and
again, cut at the rests of the trackers' combined motion speed (what ``framefree record`` does with
a multi-tracker CSV file, and, as the poses arrive, with a live source of several trackers:
:class:`MultiTakeRecorder`).

Each tracker's frame-free motion speed (:func:`~framefree.library.takes.motion_speed`) is summed, so
a take lasts while either hand moves, and the single-tracker rules find the takes
(:func:`~framefree.library.takes.takes_from_speed`). A take is written as a multi-tracker CSV
``<library>/<gesture>/trial_<k>.csv``: a folder of ``<label>/<recording>`` files, which
``framefree live`` and ``framefree evaluate-stream`` take as ``--models``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import MIN_SAMPLES, Trajectory
from ..errors import FramefreeError
from ..io.conventions import UP
from ..io.multicsv import write_multi_csv
from .takes import (
    _NAME,
    SPEED_PERIOD,
    TakeSettings,
    TakeSpan,
    cut_take,
    motion_speed,
    takes_from_speed,
)

__all__ = ["MultiTakeRecorder", "find_multi_takes", "split_multi_takes", "write_multi_take"]


def find_multi_takes(sample: MultiTrajectory, settings: TakeSettings | None = None) -> list[TakeSpan]:
    """The takes of a multi-tracker recording, on the sum of its trackers' motion speeds."""
    s = settings or TakeSettings()
    speeds = [motion_speed(tr, s.L, s.smoothing) for tr in sample.trackers]
    return takes_from_speed(speeds[0][0], sum(v for _, v in speeds), s)


def split_multi_takes(sample: MultiTrajectory, settings: TakeSettings | None = None
                      ) -> list[tuple[TakeSpan, MultiTrajectory]]:
    """Each take's span and its samples (every tracker cut alike, time starting at 0)."""
    name = sample.source or "recording"
    out = []
    for k, span in enumerate(find_multi_takes(sample, settings)):
        where = f"{name} take {k + 1} ({span.start:.2f}-{span.stop:.2f} s)"
        trackers = tuple(cut_take(tr, span, where) for tr in sample.trackers)
        out.append((span, MultiTrajectory(trackers, sample.names, sample.up, where)))
    return out


def write_multi_take(take: MultiTrajectory, library: str | Path, gesture: str) -> Path:
    """Write a take as ``<library>/<gesture>/trial_<k>.csv`` (``k`` one more than the largest
    there; a gesture name as :func:`~framefree.library.takes.write_take` allows)."""
    if not _NAME.match(gesture) or gesture == "streams":
        raise FramefreeError(f"gesture name {gesture!r}: use letters, digits, _ - . (e.g. wave_twice)")
    folder = Path(library) / gesture
    found = (re.fullmatch(r"trial_(\d+)", f.stem) for f in folder.glob("trial_*.csv"))
    numbers = [int(m.group(1)) for m in found if m]
    return write_multi_csv(folder / f"trial_{max(numbers, default=0) + 1}.csv", take)


class MultiTakeRecorder:
    """Cuts takes of several trackers out of a live pose stream as soon as the rest after them is
    long enough: :func:`find_multi_takes` on everything recorded so far, so a live recording gives
    the takes :func:`split_multi_takes` finds in the same recording as a file.

    Every take is kept (the single-tracker recorder's way-back and settling rules look at one
    tracker's path and are not applied).

    Parameters
    ----------
    names : sequence of str
        Tracker names, in the order of the poses' rows.
    settings : TakeSettings, optional
    """

    def __init__(self, names: Sequence[str], settings: TakeSettings | None = None) -> None:
        self.names = tuple(names)
        self.settings = settings or TakeSettings()
        self._rows: list[np.ndarray] = []
        self._done_until = -math.inf
        self.spans: list[TakeSpan] = []
        #: rows with a NaN (a tracker that lost tracking), not recorded
        self.skipped = 0

    def push(self, t: float, p: np.ndarray, q: np.ndarray) -> None:
        """Buffer one pose of every tracker: time [s], positions (n, 3) [m], quaternions (n, 4)
        ``(w, x, y, z)``. A pose with a lost tracker (NaN) or a time not after the last one is
        skipped."""
        n = len(self.names)
        pq = np.column_stack([np.asarray(p, dtype=float).reshape(n, 3),
                              np.asarray(q, dtype=float).reshape(n, 4)])
        row = np.concatenate([[float(t)], pq.ravel()])
        if not np.isfinite(row).all() or (self._rows and row[0] <= self._rows[-1][0]):
            self.skipped += 1
            return
        self._rows.append(row)

    @property
    def recording(self) -> MultiTrajectory | None:
        """Everything recorded so far (``None`` before the first few samples)."""
        if len(self._rows) < MIN_SAMPLES:
            return None
        a = np.array(self._rows)
        trackers = tuple(Trajectory(a[:, 0], a[:, 1 + 7 * k:4 + 7 * k], a[:, 4 + 7 * k:8 + 7 * k],
                                    source=f"recording:{name}") for k, name in enumerate(self.names))
        return MultiTrajectory(trackers, self.names, UP, "recording")

    def _new(self, final: bool) -> list[tuple[TakeSpan, MultiTrajectory]]:
        sample = self.recording
        if sample is None or sample.t[-1] - sample.t[0] < MIN_SAMPLES * SPEED_PERIOD:
            return []
        now, out = float(sample.t[-1]), []
        for span in find_multi_takes(sample, self.settings):
            if span.onset <= self._done_until:
                continue
            if not final and now - span.end < self.settings.min_rest:
                break
            self._done_until = span.end
            where = f"take {len(self.spans) + 1} ({span.start:.2f}-{span.stop:.2f} s)"
            trackers = tuple(cut_take(tr, span, where) for tr in sample.trackers)
            self.spans.append(span)
            out.append((span, MultiTrajectory(trackers, self.names, sample.up, where)))
        return out

    def poll(self) -> list[tuple[TakeSpan, MultiTrajectory]]:
        """Takes completed since the last call: (span, take) pairs."""
        return self._new(final=False)

    def finish(self) -> list[tuple[TakeSpan, MultiTrajectory]]:
        """At the end of the recording: the remaining takes, including a last one without rest."""
        return self._new(final=True)
