"""Takes of several trackers: one long multi-tracker recording of a gesture performed again and
again, cut at the rests of the trackers' combined motion speed (what ``framefree record`` does with
a multi-tracker CSV file).

Each tracker's frame-free motion speed (:func:`~framefree.library.takes.motion_speed`) is summed, so
a take lasts while either hand moves, and the single-tracker rules find the takes
(:func:`~framefree.library.takes.takes_from_speed`). A take is written as a multi-tracker CSV
``<library>/<gesture>/trial_<k>.csv``: a folder of ``<label>/<recording>`` files, which
``framefree live`` and ``framefree evaluate-stream`` take as ``--models``.
"""

from __future__ import annotations

import re
from pathlib import Path

from ..core.multitrajectory import MultiTrajectory
from ..errors import FramefreeError
from ..io.multicsv import write_multi_csv
from .takes import _NAME, TakeSettings, TakeSpan, cut_take, motion_speed, takes_from_speed

__all__ = ["find_multi_takes", "split_multi_takes", "write_multi_take"]


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
