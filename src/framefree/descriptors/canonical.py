"""Canonical hand paths: the trackers' paths in a frame that the motion itself defines.

A local descriptor such as BILTS+ is invariant to every change of world and body frame, and so
cannot tell an upward stroke from a sideways one, nor how two hands move relative to each other.
A canonical path keeps that information: the positions of every tracker, relative to where each
started, are expressed in a frame built from the sample itself, and compared with DTW
(docs/real-people.md).

``invariance="gravity"``
    invariant to translations and to rotations about the world's vertical ``up``. The frame's
    third axis is ``up``; its first is the *heading*: the horizontal direction from the first
    tracker to the second at the start (two-handed gestures: across the body), or, for one
    tracker, the principal horizontal direction of its displacement (its sign: towards where the
    hand is on average). Vertical and horizontal, up and down, stay apart.
``invariance="full"``
    invariant to any translation and rotation of the world frame, and to how a tracker is turned
    in the hand (only tracker positions are used). Needs two or more trackers: the first axis
    points from the first tracker to the second at the start, the second is the principal
    direction of the trackers' displacements orthogonal to it (its sign: towards their mean
    displacement). One tracker alone has no such frame; use a local descriptor (BILTS+) there.

Paths are resampled to ``n_samples`` points uniformly in time, so a slower performance gives the
same sequence; DTW absorbs the rest of the timing.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core.dtw import POINTWISE_EUCLIDEAN, pack_sequences, path_distance_matrix_kernel
from ..core.multitrajectory import MultiTrajectory
from ..core.pruning import DistanceSpec
from ..core.trajectory import Trajectory
from ..errors import DegenerateMotionError

__all__ = ["INVARIANCES", "CanonicalPath", "as_sample", "canonical_frame"]

#: invariance levels, from the most to the least invariant
INVARIANCES = ("full", "gravity")
#: shortest heading or motion direction [m] that defines an axis
_MIN_LENGTH = 1e-3


def as_sample(x: Trajectory | MultiTrajectory) -> MultiTrajectory:
    """A single trajectory as a one-tracker sample (``up`` = +z); a sample unchanged."""
    if isinstance(x, MultiTrajectory):
        return x
    if isinstance(x, Trajectory):
        return MultiTrajectory((x,), ("tracker_0",), source=x.source)
    raise TypeError(f"expected a Trajectory or MultiTrajectory, got {type(x).__name__}")


def _norm(v: np.ndarray) -> float:
    return float(np.linalg.norm(v))


def _principal(d: np.ndarray, towards: np.ndarray) -> np.ndarray:
    """Principal direction of displacements ``d`` (n, k), signed towards ``towards``."""
    vt = np.linalg.svd(d - d.mean(axis=0), full_matrices=False)[2]
    axis = vt[0]
    if float(axis @ towards) < 0.0:
        axis = -axis
    return axis


def _displacements(sample: MultiTrajectory) -> np.ndarray:
    """Every tracker's positions relative to its start, stacked (n_trackers · N, 3)."""
    return np.concatenate([tr.p - tr.p[0] for tr in sample.trackers])


def canonical_frame(sample: MultiTrajectory, invariance: str) -> np.ndarray:
    """Rotation (3, 3) whose columns are the canonical axes, in world coordinates.

    Raises
    ------
    DegenerateMotionError
        When the motion defines no frame (e.g. ``full`` with one tracker, or trackers that do not
        move).
    ValueError
        For an unknown ``invariance``.
    """
    d = _displacements(sample)
    where = f"{sample.source}: " if sample.source else ""
    if invariance == "gravity":
        up = sample.up
        across = sample.trackers[1].p[0] - sample.trackers[0].p[0] if sample.n_trackers > 1 else None
        if across is not None:
            across = across - up * float(up @ across)
        if across is None or _norm(across) < _MIN_LENGTH:
            flat = d - np.outer(d @ up, up)
            if _norm(flat.max(axis=0) - flat.min(axis=0)) < _MIN_LENGTH:
                across = np.cross(up, [1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.cross(up, [0.0, 1.0, 0.0])
            else:
                across = _principal(flat, flat.mean(axis=0))
                across = across - up * float(up @ across)
        e1 = across / _norm(across)
        return np.column_stack([e1, np.cross(up, e1), up])
    if invariance == "full":
        if sample.n_trackers < 2:
            raise DegenerateMotionError(f"{where}invariance 'full' of a canonical path needs two or "
                                        "more trackers; use a local descriptor for one")
        across = sample.trackers[1].p[0] - sample.trackers[0].p[0]
        if _norm(across) < _MIN_LENGTH:
            raise DegenerateMotionError(f"{where}the first two trackers start at one place")
        e1 = across / _norm(across)
        flat = d - np.outer(d @ e1, e1)
        if _norm(flat.max(axis=0) - flat.min(axis=0)) < _MIN_LENGTH:
            raise DegenerateMotionError(f"{where}the trackers do not move across their line")
        e2 = _principal(flat, flat.mean(axis=0))
        e2 = e2 - e1 * float(e1 @ e2)
        e2 /= _norm(e2)
        return np.column_stack([e1, e2, np.cross(e1, e2)])
    raise ValueError(f"unknown invariance {invariance!r}; choose one of {', '.join(INVARIANCES)}")


class CanonicalPath:
    """Canonical paths of samples and the DTW distance between them.

    Parameters
    ----------
    invariance : {"full", "gravity"}
        See the module docstring.
    n_samples : int
        Points per path (uniform in time).

    Notes
    -----
    Samples in one comparison must have the same number of trackers, in the same order.
    """

    def __init__(self, invariance: str = "gravity", n_samples: int = 64) -> None:
        if invariance not in INVARIANCES:
            raise ValueError(f"unknown invariance {invariance!r}; choose one of {', '.join(INVARIANCES)}")
        if int(n_samples) < 2:
            raise ValueError(f"n_samples must be at least 2, got {n_samples}")
        self.invariance = invariance
        self.n_samples = int(n_samples)

    def __repr__(self) -> str:
        return f"CanonicalPath(invariance={self.invariance!r}, n_samples={self.n_samples})"

    def compute(self, sample: Trajectory | MultiTrajectory) -> np.ndarray:
        """The canonical path, shape (n_samples, 3 · n_trackers) [m]."""
        sample = as_sample(sample)
        R = canonical_frame(sample, self.invariance)
        t = sample.t
        grid = np.linspace(t[0], t[-1], self.n_samples)
        cols = []
        for tr in sample.trackers:
            local = (tr.p - tr.p[0]) @ R
            cols += [np.interp(grid, t, local[:, k]) for k in range(3)]
        return np.column_stack(cols)

    def distance_spec(self) -> DistanceSpec:
        """DTW with Euclidean local cost over all columns, closed end."""
        return DistanceSpec(0, 0, POINTWISE_EUCLIDEAN, False)

    def distance_matrix(self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]) -> np.ndarray:
        """DTW distances (n_queries, n_models): Euclidean local cost, averaged along the path."""
        widths = {q.shape[1] for q in queries} | {m.shape[1] for m in models}
        if len(widths) != 1:
            raise ValueError("queries and models have different numbers of trackers")
        qdata, qoff = pack_sequences(list(queries))
        mdata, moff = pack_sequences(list(models))
        width = qdata.shape[1]
        return path_distance_matrix_kernel(qdata, qoff, mdata, moff, 0, width, POINTWISE_EUCLIDEAN, False)
