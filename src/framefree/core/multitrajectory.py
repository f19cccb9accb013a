"""Several trackers recorded together: one sample of a two-handed (or hand-and-head) gesture."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import TrajectoryError
from .trajectory import Trajectory

__all__ = ["MultiTrajectory"]


@dataclass(frozen=True, eq=False)
class MultiTrajectory:
    """Named trackers on one time base, with the world's vertical.

    Parameters
    ----------
    trackers : sequence of Trajectory
        One trajectory per tracker, all with the same time stamps (N,), in one world frame.
    names : sequence of str, optional
        Tracker names (default ``tracker_0``, ``tracker_1``, ...), unique.
    up : array_like, shape (3,)
        The vertical of the world frame, a unit vector (framefree's convention: +z). Only the
        ``gravity`` invariance uses it.
    source : str, optional
        Where the data came from (a file path or a label); used in error messages.

    Notes
    -----
    Instances are immutable; :meth:`transformed` applies one world-frame change to every tracker,
    as moving the tracking system's base stations would.
    """

    trackers: tuple[Trajectory, ...]
    names: tuple[str, ...] = ()
    up: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    source: str | None = None

    def __post_init__(self) -> None:
        trackers = tuple(self.trackers)
        where = f"{self.source}: " if self.source else ""
        if not trackers or not all(isinstance(tr, Trajectory) for tr in trackers):
            raise TrajectoryError(f"{where}a multi-tracker sample needs one or more Trajectory objects")
        t0 = trackers[0].t
        for k, tr in enumerate(trackers[1:], start=1):
            if tr.t.shape != t0.shape or not np.array_equal(tr.t, t0):
                raise TrajectoryError(f"{where}tracker {k} has other time stamps than tracker 0 "
                                      "(trackers recorded together share one time base)")
        names = tuple(self.names) or tuple(f"tracker_{k}" for k in range(len(trackers)))
        if len(names) != len(trackers) or len(set(names)) != len(names):
            raise TrajectoryError(f"{where}need {len(trackers)} unique tracker names, got {names}")
        up = np.asarray(self.up, dtype=np.float64).reshape(3)
        norm = float(np.linalg.norm(up))
        if not np.isfinite(norm) or norm == 0.0:
            raise TrajectoryError(f"{where}the up vector must be a non-zero finite 3-vector")
        up = up / norm
        up.flags.writeable = False
        object.__setattr__(self, "trackers", trackers)
        object.__setattr__(self, "names", names)
        object.__setattr__(self, "up", up)

    def __len__(self) -> int:
        return len(self.trackers[0])

    def __repr__(self) -> str:
        src = f", source={self.source!r}" if self.source else ""
        return f"MultiTrajectory({len(self)} samples, trackers={list(self.names)}{src})"

    @property
    def t(self) -> np.ndarray:
        """Time stamps [s], shape (N,)."""
        return self.trackers[0].t

    @property
    def n_trackers(self) -> int:
        return len(self.trackers)

    def __getitem__(self, name: str | int) -> Trajectory:
        if isinstance(name, int):
            return self.trackers[name]
        try:
            return self.trackers[self.names.index(name)]
        except ValueError:
            raise KeyError(f"no tracker {name!r}; trackers: {', '.join(self.names)}") from None

    def transformed(self, world: np.ndarray) -> MultiTrajectory:
        """Every tracker seen from another world frame ``world`` (4, 4): poses ``world @ T(t)``;
        the vertical turns with it."""
        world = np.asarray(world, dtype=np.float64)
        trackers = tuple(tr.transformed(world=world) for tr in self.trackers)
        return MultiTrajectory(trackers, self.names, world[:3, :3] @ self.up, self.source)
