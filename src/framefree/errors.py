"""Exceptions raised by framefree. Every one is a ``ValueError`` that says where and what."""

from __future__ import annotations

from pathlib import Path

__all__ = [
    "DatasetError",
    "DegenerateMotionError",
    "FramefreeError",
    "FramefreeWarning",
    "TrajectoryError",
]


class FramefreeError(ValueError):
    """Base class of framefree's input errors."""


class TrajectoryError(FramefreeError):
    """A trajectory (file or arrays) is malformed.

    Parameters
    ----------
    problem : str
        What is wrong, in words.
    source : str or Path, optional
        The file (or a label for in-memory data) the trajectory came from.
    row : int, optional
        1-based row number in the file (or sample index + 1 for arrays).
    """

    def __init__(self, problem: str, source: str | Path | None = None, row: int | None = None):
        self.problem = problem
        self.source = None if source is None else str(source)
        self.row = row
        where = []
        if self.source is not None:
            where.append(self.source)
        if row is not None:
            where.append(f"row {row}")
        prefix = ", ".join(where)
        super().__init__(f"{prefix}: {problem}" if prefix else problem)


class DegenerateMotionError(TrajectoryError):
    """The motion has no geometric progress (e.g. the tracker never moved)."""


class DatasetError(FramefreeError):
    """A dataset folder does not have the expected layout."""


class FramefreeWarning(UserWarning):
    """Base class of framefree's warnings: the input is usable but something looks wrong.

    The command line shows each as one line; ``problem`` (when set) groups repeats of one problem.
    """

    problem: str | None = None
