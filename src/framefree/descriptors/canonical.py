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
    in the hand (positions only, without the options below). Needs two or more trackers: the
    first axis points from the first tracker to the second at the start, the second is the principal
    direction of the trackers' displacements orthogonal to it (its sign: towards their mean
    displacement). One tracker alone has no such frame; use a local descriptor (BILTS+) there.

Options add columns from the trackers' orientations (``orientation_scale``, ``start_frame``) and
one hand seen from the other (``relative``); the classifier's defaults for several trackers are
``framefree.classifier.MULTI_TRACKER_PATHS``. ``start_frame`` and ``relative`` keep the world-frame
invariance and give up the invariance to how a tracker is held.

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

__all__ = ["INVARIANCES", "CanonicalPath", "as_sample", "canonical_frame", "start_orientation"]

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


def _turns_since_start(tr: Trajectory, R: np.ndarray) -> np.ndarray:
    """Rotation since the start in the canonical frame ``R``, ``Rᵀ R(t) R(0)ᵀ R`` flat, (N, 9)."""
    rot = tr.rotations()
    since = rot @ rot[0].T
    return (R.T @ since @ R).reshape(len(rot), 9)


def start_orientation(sample: MultiTrajectory) -> np.ndarray:
    """The rotation (3, 3) nearest to the sum of the trackers' starting rotations (chordal mean)."""
    total = sum(tr.rotations()[0] for tr in sample.trackers)
    u, _, vt = np.linalg.svd(total)
    return u @ np.diag([1.0, 1.0, float(np.linalg.det(u @ vt))]) @ vt


def _relative_positions(sample: MultiTrajectory) -> list[np.ndarray]:
    """Every other tracker in the first one's frame and the first in each other's, (N, 3) each [m]."""
    if sample.n_trackers < 2:
        where = f"{sample.source}: " if sample.source else ""
        raise DegenerateMotionError(f"{where}relative motion needs two or more trackers")
    first = sample.trackers[0]
    r0 = first.rotations()
    out = []
    for tr in sample.trackers[1:]:
        d = tr.p - first.p
        out.append(np.einsum("nji,nj->ni", r0, d))
        out.append(np.einsum("nji,nj->ni", tr.rotations(), -d))
    return out


class CanonicalPath:
    """Canonical paths of samples and the DTW distance between them.

    Parameters
    ----------
    invariance : {"full", "gravity"}
        See the module docstring.
    n_samples : int
        Points per path (uniform in time).
    orientation_scale : float, optional
        With a length ``ℓ`` [m], every tracker's rotation since its start, expressed in the
        canonical frame (``Cᵀ R_k(t) R_k(0)ᵀ C``, 9 entries), is added to the path times ``ℓ``; it
        is unchanged by how the tracker is turned in the hand. None (default): positions only.
    relative : bool
        Add where the other trackers are as seen from the first one and the first one as seen
        from each of them (``R_0(t)ᵀ (p_k(t) − p_0(t))`` and ``R_k(t)ᵀ (p_0(t) − p_k(t))`` [m]):
        the motion of one hand relative to the other, the same in any world frame. Needs two or
        more trackers.
    start_frame : bool
        Add every tracker's positions relative to its start in the trackers' mean orientation at
        the start (the rotation nearest to ``Σ_k R_k(0)``) [m]. Held controllers point roughly the
        same way for every person, so this frame carries where up and forward were without the
        world's vertical; it is the same in any world frame but turns with the grip.

    Notes
    -----
    Samples in one comparison must have the same number of trackers, in the same order.
    Columns, per point: 3 positions per tracker, then 9 orientation entries per tracker (with
    ``orientation_scale``), then 6 relative coordinates per tracker after the first (with
    ``relative``), then 3 per tracker in the start frame (with ``start_frame``).
    """

    def __init__(self, invariance: str = "gravity", n_samples: int = 64,
                 orientation_scale: float | None = None, relative: bool = False,
                 start_frame: bool = False) -> None:
        if invariance not in INVARIANCES:
            raise ValueError(f"unknown invariance {invariance!r}; choose one of {', '.join(INVARIANCES)}")
        if int(n_samples) < 2:
            raise ValueError(f"n_samples must be at least 2, got {n_samples}")
        if orientation_scale is not None and not float(orientation_scale) > 0.0:
            raise ValueError(f"orientation_scale must be a positive length [m], got {orientation_scale}")
        self.invariance = invariance
        self.n_samples = int(n_samples)
        self.orientation_scale = None if orientation_scale is None else float(orientation_scale)
        self.relative = bool(relative)
        self.start_frame = bool(start_frame)

    def __repr__(self) -> str:
        extra = ""
        if self.orientation_scale is not None:
            extra += f", orientation_scale={self.orientation_scale}"
        if self.relative:
            extra += ", relative=True"
        if self.start_frame:
            extra += ", start_frame=True"
        return f"CanonicalPath(invariance={self.invariance!r}, n_samples={self.n_samples}{extra})"

    def compute(self, sample: Trajectory | MultiTrajectory) -> np.ndarray:
        """The canonical path, shape (n_samples, n_columns) [m] (columns: see Notes)."""
        sample = as_sample(sample)
        R = canonical_frame(sample, self.invariance)
        t = sample.t
        grid = np.linspace(t[0], t[-1], self.n_samples)
        parts = [(tr.p - tr.p[0]) @ R for tr in sample.trackers]
        if self.orientation_scale is not None:
            parts += [_turns_since_start(tr, R) * self.orientation_scale for tr in sample.trackers]
        if self.relative:
            parts += _relative_positions(sample)
        if self.start_frame:
            S = start_orientation(sample)
            parts += [(tr.p - tr.p[0]) @ S for tr in sample.trackers]
        cols = np.concatenate(parts, axis=1)
        return np.column_stack([np.interp(grid, t, cols[:, k]) for k in range(cols.shape[1])])

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
