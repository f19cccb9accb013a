"""Building blocks of synthetic human motion: minimum-jerk timing, SE(3) paths, and motions that are
sequences of timed pieces.

A *path* maps a normalized progress ``s ∈ [0, 1]`` to poses; a *piece* traverses a path in a given
time with a bell-shaped (minimum-jerk) speed profile, or holds a pose; a :class:`Motion` chains
pieces and can be evaluated at any time stamps. Poses are 4×4 homogeneous matrices.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..core import se3

__all__ = [
    "Motion",
    "Path",
    "Piece",
    "deviated",
    "hesitant_stroke",
    "hold",
    "make_pose",
    "minimum_jerk",
    "overlapped",
    "reversed_path",
    "rot",
    "sclerp_path",
    "screw_path",
    "stroke",
    "translation_path",
]

#: A path: progress values ``s`` (n,) in [0, 1] → poses (n, 4, 4).
Path = Callable[[np.ndarray], np.ndarray]


def minimum_jerk(tau: np.ndarray) -> np.ndarray:
    """Minimum-jerk position profile ``10τ³ − 15τ⁴ + 6τ⁵`` (Flash & Hogan 1985).

    Parameters
    ----------
    tau : ndarray, shape (n,)
        Normalized time, clipped to [0, 1].

    Returns
    -------
    ndarray, shape (n,)
        Normalized progress in [0, 1]; zero velocity and acceleration at both ends, bell-shaped speed
        with peak ``1.875`` (in units of progress per unit of normalized time) at ``τ = 0.5``.
    """
    tau = np.clip(np.asarray(tau, dtype=np.float64), 0.0, 1.0)
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2)


def rot(axis: Sequence[float] | np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix (3, 3) of ``angle`` [rad] about ``axis`` (3,) (normalized here)."""
    axis = np.asarray(axis, dtype=np.float64)
    return se3.rotation_from_vector(axis / np.linalg.norm(axis) * angle)


def make_pose(R: np.ndarray, p: Sequence[float] | np.ndarray) -> np.ndarray:
    """Homogeneous pose (4, 4) from a rotation (3, 3) and a position (3,) [m]."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def _poses(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    T = np.zeros((*p.shape[:-1], 4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


def screw_path(
    start: np.ndarray,
    axis: Sequence[float] | np.ndarray,
    point: Sequence[float] | np.ndarray,
    angle: float,
    advance: float = 0.0,
) -> Path:
    """Constant screw motion in the world: rotation ``angle`` [rad] about the line through ``point``
    (3,) [m] with direction ``axis`` (3,), while translating ``advance`` [m] along it.

    The pose at progress ``s`` is ``S(s) · start`` with ``S(s)`` the screw displacement of angle
    ``s·angle`` and translation ``s·advance``; the pitch is ``advance / angle`` [m/rad].
    """
    u = np.asarray(axis, dtype=np.float64)
    u = u / np.linalg.norm(u)
    c = np.asarray(point, dtype=np.float64)
    start = np.asarray(start, dtype=np.float64)

    def path(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=np.float64)
        R = se3.rotation_from_vector(s[:, None] * angle * u)
        p = np.einsum("nij,j->ni", R, start[:3, 3] - c) + c + s[:, None] * advance * u
        return _poses(R @ start[:3, :3], p)

    return path


def translation_path(start: np.ndarray, position: Callable[[np.ndarray], np.ndarray]) -> Path:
    """Pure translation: constant orientation of ``start``, position ``start_p + position(s)``.

    ``position`` maps (n,) progress values to (n, 3) offsets [m] and must be zero at ``s = 0``.
    """
    start = np.asarray(start, dtype=np.float64)

    def path(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=np.float64)
        p = start[:3, 3] + position(s)
        return _poses(np.broadcast_to(start[:3, :3], (s.shape[0], 3, 3)), p)

    return path


def sclerp_path(start: np.ndarray, end: np.ndarray) -> Path:
    """Screw linear interpolation (constant body twist) from ``start`` to ``end`` (4, 4):
    ``start · exp(s · log(start⁻¹ end))``."""
    start = np.asarray(start, dtype=np.float64)
    xi = se3.twist_from_pose(se3.transform_inverse(start) @ np.asarray(end, dtype=np.float64))

    def path(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=np.float64)
        return start @ se3.pose_from_twist(s[:, None] * xi)

    return path


def reversed_path(path: Path) -> Path:
    """The same path traversed backwards."""
    return lambda s: path(1.0 - np.asarray(s, dtype=np.float64))


def deviated(
    path: Path,
    bulge_p: np.ndarray,
    bulge_r: np.ndarray,
    end_p: np.ndarray | None = None,
    end_r: np.ndarray | None = None,
) -> Path:
    """A path with a smooth human deviation: ``sin(πs)·bulge + s·end`` added to the position and
    (as a rotation vector, left-multiplied about the moving point) to the orientation.

    Parameters
    ----------
    path : Path
    bulge_p, bulge_r : ndarray, shape (3,)
        Mid-path position [m] and orientation [rad] deviation (zero at both ends).
    end_p, end_r : ndarray, shape (3,), optional
        Endpoint error [m], [rad] (zero at the start, full at the end).
    """
    end_p = np.zeros(3) if end_p is None else np.asarray(end_p, dtype=np.float64)
    end_r = np.zeros(3) if end_r is None else np.asarray(end_r, dtype=np.float64)
    bulge_p = np.asarray(bulge_p, dtype=np.float64)
    bulge_r = np.asarray(bulge_r, dtype=np.float64)

    def new(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=np.float64)
        T = path(s).copy()
        b = np.sin(np.pi * s)[:, None]
        T[:, :3, 3] += b * bulge_p + s[:, None] * end_p
        dR = se3.rotation_from_vector(b * bulge_r + s[:, None] * end_r)
        T[:, :3, :3] = dR @ T[:, :3, :3]
        return T

    return new


@dataclass(frozen=True)
class Piece:
    """One timed segment of a motion.

    Attributes
    ----------
    duration : float
        Length of the piece [s].
    fn : callable
        Local times (n,) in ``[0, duration]`` → poses (n, 4, 4).
    """

    duration: float
    fn: Callable[[np.ndarray], np.ndarray]

    @property
    def start(self) -> np.ndarray:
        """First pose (4, 4)."""
        return self.fn(np.zeros(1))[0]

    @property
    def end(self) -> np.ndarray:
        """Last pose (4, 4)."""
        return self.fn(np.array([self.duration]))[0]


def hold(pose: np.ndarray, duration: float) -> Piece:
    """Hold ``pose`` (4, 4) still for ``duration`` [s]."""
    pose = np.array(pose, dtype=np.float64)
    return Piece(float(duration), lambda t: np.broadcast_to(pose, (np.shape(t)[0], 4, 4)).copy())


def stroke(path: Path, duration: float, skew: float = 1.0) -> Piece:
    """Traverse ``path`` in ``duration`` [s] with a minimum-jerk profile.

    ``skew`` warps normalized time as ``τ ** skew`` before the profile: 1 gives the symmetric bell,
    values above 1 move the speed peak later, below 1 earlier (human reaches are mildly asymmetric).
    """
    if not duration > 0:
        raise ValueError(f"stroke duration must be positive, got {duration}")
    return Piece(float(duration), lambda t: path(minimum_jerk((np.asarray(t) / duration) ** skew)))


def hesitant_stroke(path: Path, duration: float, skew: float, at: float, pause: float,
                    residual: float = 0.1, ramp: float = 0.12) -> Piece:
    """A :func:`stroke` that nearly stops on the way: the person hesitates in mid-stroke.

    The stroke's normalized time runs at ``residual`` times its normal rate for ``pause`` seconds
    starting when it reaches ``at``, with raised-cosine ramps of ``ramp`` seconds into and out
    of the slow phase, so the hand slows to about ``residual`` of the speed it had there, creeps
    on, and resumes. Without the slow phase (``pause = 0``) it is the plain stroke.

    Parameters
    ----------
    path : Path
    duration : float
        Duration [s] of the stroke without the hesitation.
    skew : float
        Time-warp exponent, as in :func:`stroke`.
    at : float
        Normalized time in (0, 1) of the stroke where the hesitation begins.
    pause : float
        Duration [s] of the slow phase.
    residual : float
        Rate of progress during the slow phase relative to the normal rate (0: a full stop).
    ramp : float
        Duration [s] of each ramp between the normal and the slow rate.

    Returns
    -------
    Piece
        Lasting longer than ``duration`` by about ``(1 - residual) (pause + ramp)`` seconds.
    """
    if not duration > 0 or pause < 0 or not 0 < at < 1 or not 0 <= residual <= 1:
        raise ValueError(f"invalid hesitation: duration {duration}, at {at}, pause {pause}, "
                         f"residual {residual}")
    t0 = at * duration
    t = np.linspace(0.0, duration + pause + 2 * ramp, 4001)
    u = t - t0  # time since the slow-down began
    window = np.where((u > 0) & (u < 2 * ramp + pause), 1.0, 0.0)
    rise = (u > 0) & (u < ramp)
    window[rise] = 0.5 - 0.5 * np.cos(np.pi * u[rise] / ramp)
    fall = (u >= ramp + pause) & (u < 2 * ramp + pause)
    window[fall] = 0.5 + 0.5 * np.cos(np.pi * (u[fall] - ramp - pause) / ramp)
    rate = (1.0 - (1.0 - residual) * window) / duration
    tau = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
    end = float(np.interp(1.0, tau, t))

    def fn(local: np.ndarray) -> np.ndarray:
        tt = np.clip(np.interp(np.asarray(local, dtype=np.float64), t, tau), 0.0, 1.0)
        return path(minimum_jerk(tt ** skew))

    return Piece(end, fn)


def overlapped(pieces: Sequence[Piece], overlap: float) -> Piece:
    """Consecutive strokes superposed, as fluent movement joins them: each stroke begins
    ``overlap`` × the previous stroke's duration before that one ends, and the displacements of
    the strokes add up (the superposition of movement units: Morasso & Mussa-Ivaldi, Biol Cybern
    45:131, 1982, for handwriting; Flash & Henis, J Cogn Neurosci 3:220, 1991, for minimum-jerk
    units).

    Where two strokes meet at a corner, the hand no longer stops: the corner is rounded and the
    speed dips only partway (with minimum-jerk strokes at right angles, to about 0.2 of the peak at
    an overlap of 0.2 and 0.6 at 0.4). Every stroke still moves the hand by its own displacement,
    so the path ends where the chained strokes end.

    Parameters
    ----------
    pieces : sequence of Piece
        Chained strokes (each starts where the previous one ends).
    overlap : float
        In [0, 1): 0 chains them as they are (the hand stops at every corner).

    Returns
    -------
    Piece
        Lasting ``Σ durations − overlap × Σ durations but the last``.
    """
    if not 0.0 <= overlap < 1.0:
        raise ValueError(f"overlap must be in [0, 1), got {overlap}")
    if not pieces:
        raise ValueError("overlapped() needs at least one piece")
    starts = np.concatenate([[0.0], np.cumsum([(1.0 - overlap) * p.duration for p in pieces[:-1]])])
    total = float(starts[-1] + pieces[-1].duration)
    first = pieces[0].start
    origins = [p.start for p in pieces]

    def fn(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=np.float64)
        T = np.broadcast_to(first, (t.shape[0], 4, 4)).copy()
        for start, piece, origin in zip(starts, pieces, origins, strict=True):
            P = piece.fn(np.clip(t - start, 0.0, piece.duration))
            T[:, :3, 3] += P[:, :3, 3] - origin[:3, 3]
            T[:, :3, :3] = P[:, :3, :3] @ origin[:3, :3].T @ T[:, :3, :3]
        return T

    return Piece(total, fn)


class Motion:
    """A chain of pieces evaluated on one clock (t = 0 at the start of the first piece).

    Parameters
    ----------
    pieces : sequence of Piece
    """

    def __init__(self, pieces: Sequence[Piece] = ()) -> None:
        self.pieces: list[Piece] = list(pieces)

    def append(self, piece: Piece) -> Motion:
        """Add a piece at the end; returns ``self``."""
        self.pieces.append(piece)
        return self

    @property
    def duration(self) -> float:
        """Total duration [s]."""
        return float(sum(p.duration for p in self.pieces))

    @property
    def end(self) -> np.ndarray:
        """Final pose (4, 4)."""
        return self.pieces[-1].end

    def at(self, t: np.ndarray) -> np.ndarray:
        """Poses (n, 4, 4) at times ``t`` (n,) [s] (clipped to the motion's time span)."""
        t = np.clip(np.asarray(t, dtype=np.float64), 0.0, self.duration)
        bounds = np.concatenate([[0.0], np.cumsum([p.duration for p in self.pieces])])
        idx = np.clip(np.searchsorted(bounds, t, side="right") - 1, 0, len(self.pieces) - 1)
        out = np.empty((t.shape[0], 4, 4))
        for k in np.unique(idx):
            sel = idx == k
            local = np.clip(t[sel] - bounds[k], 0.0, self.pieces[k].duration)
            out[sel] = self.pieces[k].fn(local)
        return out
