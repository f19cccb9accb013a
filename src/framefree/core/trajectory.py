"""The :class:`Trajectory` value type: time-stamped 6-DoF poses, validated, with frame and time
transformations that return new values."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import TrajectoryError
from . import se3, se3_kernels
from .posecsv import QUAT_ORDERS, read_pose_csv, warn_if_implausible

__all__ = ["MIN_SAMPLES", "Trajectory", "read_pose_csv"]

#: The fewest samples a trajectory may have.
MIN_SAMPLES = 5

_QUAT_ORDERS = QUAT_ORDERS


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=np.float64)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A rigid-body trajectory: N time-stamped poses of a body (tracker) frame in a world frame.

    Parameters
    ----------
    t : array_like, shape (N,)
        Time stamps [s], strictly increasing.
    p : array_like, shape (N, 3)
        Positions of the body origin in the world [m].
    q : array_like, shape (N, 4)
        Orientations as quaternions ``(w, x, y, z)``; renormalized and made sign-continuous.
    source : str, optional
        Where the data came from (a file path or a label); used in error messages.

    Notes
    -----
    Construction validates: shapes, finite values, at least :data:`MIN_SAMPLES` samples,
    strictly increasing time, non-zero quaternions. Instances are immutable: all transformations
    return new trajectories.
    """

    t: np.ndarray
    p: np.ndarray
    q: np.ndarray
    source: str | None = field(default=None)

    def __post_init__(self) -> None:
        src = self.source
        t = np.asarray(self.t, dtype=np.float64)
        p = np.asarray(self.p, dtype=np.float64)
        q = np.asarray(self.q, dtype=np.float64)
        if t.ndim != 1:
            raise TrajectoryError(f"t must have shape (N,), got {t.shape}", src)
        n = t.shape[0]
        if p.shape != (n, 3):
            raise TrajectoryError(f"p must have shape ({n}, 3), got {p.shape}", src)
        if q.shape != (n, 4):
            raise TrajectoryError(f"q must have shape ({n}, 4), got {q.shape}", src)
        if n < MIN_SAMPLES:
            raise TrajectoryError(
                f"only {n} samples; a trajectory needs at least {MIN_SAMPLES}", src
            )
        for name, arr in (("time", t), ("position", p), ("quaternion", q)):
            bad = ~np.isfinite(arr.reshape(n, -1)).all(axis=1)
            if bad.any():
                raise TrajectoryError(
                    f"{name} is not finite (NaN or inf)", src, int(np.argmax(bad)) + 1
                )
        dt = np.diff(t)
        if (dt <= 0).any():
            k = int(np.argmax(dt <= 0)) + 2
            what = "repeats the previous time stamp" if dt[k - 2] == 0 else "goes backwards in time"
            raise TrajectoryError(f"time {t[k - 1]:.6g} s {what} ({t[k - 2]:.6g} s before)", src, k)
        norms = np.linalg.norm(q, axis=1)
        if (norms < 1e-9).any():
            raise TrajectoryError("quaternion has zero norm", src, int(np.argmax(norms < 1e-9)) + 1)
        q = se3.quaternion_continuity(q / norms[:, None])
        object.__setattr__(self, "t", _readonly(t))
        object.__setattr__(self, "p", _readonly(p))
        object.__setattr__(self, "q", _readonly(q))

    # ---------------------------------------------------------------------------------------- I/O
    @classmethod
    def from_csv(
        cls,
        path: str | Path,
        quat_order: str = "wxyz",
        *,
        skip_header: bool = False,
        units: str = "m",
        check: bool = True,
    ) -> Trajectory:
        """Load an 8-column CSV ``t, x, y, z, qw, qx, qy, qz`` (no header).

        Exact duplicate rows (a sensor repeating a sample) are dropped; any other non-increasing
        time stamp is an error.

        Parameters
        ----------
        path : str or Path
        quat_order : {"wxyz", "xyzw"}
            ``"xyzw"`` for files that store the quaternion scalar last.
        skip_header : bool
            Ignore a header row (the first non-empty line).
        units : {"m", "cm", "mm"}
            Unit of the file's positions (converted to metres).
        check : bool
            Warn (:class:`~framefree.core.posecsv.PlausibilityWarning`) when the positions or speeds
            are implausible for a hand (wrong ``units``) or the quaternions look scalar-last.

        Raises
        ------
        TrajectoryError
            With the file, the row and the problem (see :func:`~framefree.core.posecsv.read_pose_csv`).
        """
        data = read_pose_csv(path, quat_order, skip_header=skip_header, units=units)
        traj = cls.from_array(data, source=str(path))
        if check:
            warn_if_implausible(data, path, quat_order)
        return traj

    @classmethod
    def from_array(cls, data: np.ndarray, source: str | None = None) -> Trajectory:
        """Build from an (N, 8) array ``t, x, y, z, qw, qx, qy, qz``; exact duplicate rows dropped."""
        data = np.asarray(data, dtype=np.float64)
        if data.ndim != 2 or data.shape[1] != 8:
            raise TrajectoryError(f"expected an (N, 8) array, got shape {data.shape}", source)
        if data.shape[0] > 1:
            dup = np.all(data[1:] == data[:-1], axis=1)
            if dup.any():
                data = data[np.concatenate([[True], ~dup])]
        return cls(data[:, 0], data[:, 1:4], data[:, 4:8], source=source)

    @classmethod
    def from_poses(cls, t: np.ndarray, T: np.ndarray, source: str | None = None) -> Trajectory:
        """Build from time stamps (N,) and poses (N, 4, 4)."""
        p, q = se3.pq_from_poses(T)
        return cls(t, p, q, source=source)

    def to_array(self) -> np.ndarray:
        """(N, 8) array ``t, x, y, z, qw, qx, qy, qz``."""
        return np.column_stack([self.t, self.p, self.q])

    def to_csv(self, path: str | Path, quat_order: str = "wxyz") -> None:
        """Write an 8-column CSV (no header) at full precision."""
        if quat_order not in _QUAT_ORDERS:
            raise ValueError(f"quat_order must be one of {_QUAT_ORDERS}, got {quat_order!r}")
        data = self.to_array()
        if quat_order == "xyzw":
            data = data[:, [0, 1, 2, 3, 5, 6, 7, 4]]
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savetxt(path, data, delimiter=",", fmt="%.17g")

    # ----------------------------------------------------------------------------------- accessors
    def __len__(self) -> int:
        return int(self.t.shape[0])

    def __repr__(self) -> str:
        src = f", source={self.source!r}" if self.source else ""
        return f"Trajectory(N={len(self)}, duration={self.duration:.3f} s{src})"

    @property
    def duration(self) -> float:
        """Time from the first to the last sample [s]."""
        return float(self.t[-1] - self.t[0])

    def poses(self) -> np.ndarray:
        """Homogeneous poses, shape (N, 4, 4)."""
        return se3.poses_from_pq(self.p, self.q)

    def rotations(self) -> np.ndarray:
        """Rotation matrices, shape (N, 3, 3)."""
        return se3.matrix_from_quaternion(self.q)

    # ----------------------------------------------------------------------------- transformations
    def _with_poses(self, t: np.ndarray, T: np.ndarray) -> Trajectory:
        p, q = se3.pq_from_poses(T)
        q = q * se3.quaternion_sign(q[0], self.q[0])
        return Trajectory(t, p, q, source=self.source)

    def transformed(
        self, world: np.ndarray | None = None, body: np.ndarray | None = None
    ) -> Trajectory:
        """Change of reference frames: ``T'(t) = world · T(t) · body``.

        Parameters
        ----------
        world : ndarray, shape (4, 4), optional
            Pose of the old world frame in the new one (left multiplication).
        body : ndarray, shape (4, 4), optional
            Pose of the new body frame in the old one (right multiplication).
        """
        T = self.poses()
        if world is not None:
            T = np.asarray(world, dtype=np.float64) @ T
        if body is not None:
            T = T @ np.asarray(body, dtype=np.float64)
        return self._with_poses(self.t.copy(), T)

    def time_scaled(self, factor: float) -> Trajectory:
        """Same poses with time stamps stretched by ``factor`` about the first sample (2 = twice as slow)."""
        if not factor > 0:
            raise ValueError(f"time scale factor must be positive, got {factor}")
        t = self.t[0] + factor * (self.t - self.t[0])
        return Trajectory(t, self.p, self.q, source=self.source)

    def path_scaled(self, factor: float) -> Trajectory:
        """Positions scaled by ``factor`` about the first one, orientations kept: the same gesture
        made larger or smaller, as by a person with a longer or shorter reach (the wrist turns as
        far)."""
        if not factor > 0:
            raise ValueError(f"path scale factor must be positive, got {factor}")
        return Trajectory(self.t, self.p[0] + factor * (self.p - self.p[0]), self.q, source=self.source)

    def resampled(self, dt: float = 0.02) -> Trajectory:
        """Resample on a uniform time grid by ScLERP (constant-twist interpolation,
        docs/algorithms/progress.md).

        The grid has ``round(1 + floor(duration / dt))`` points from the first to the last time
        stamp inclusive, as the reference does; its step is therefore close to, but in general not
        exactly, ``dt``.
        """
        tq, T = self.uniform_poses(dt)
        return self._with_poses(self.t[0] + tq, T)

    def uniform_poses(self, dt: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
        """Times relative to the first sample (M,) [s] and ScLERP poses (M, 4, 4) on the grid of
        :meth:`resampled`, without building a new trajectory."""
        if not dt > 0:
            raise ValueError(f"dt must be positive, got {dt}")
        n = math.floor(1.0 + math.floor(self.duration / dt) + 0.5)
        if n < MIN_SAMPLES:
            raise TrajectoryError(
                f"resampling a {self.duration:.3g} s trajectory at {dt} s leaves {n} samples",
                self.source,
            )
        # interpolate in time relative to the first sample, so that large absolute clocks
        # (e.g. Unix time) cost no precision in the interpolation fractions
        t_rel = self.t - self.t[0]
        tq = np.linspace(0.0, t_rel[-1], n)
        tq[-1] = t_rel[-1]
        return tq, se3_kernels.interpolate_poses_kernel(t_rel, self.poses(), tq)

    def head(self, fraction: float) -> Trajectory:
        """The first ``ceil(fraction · N)`` samples (e.g. 0.5 for an unfinished gesture)."""
        if not 0 < fraction <= 1:
            raise ValueError(f"fraction must be in (0, 1], got {fraction}")
        n = math.ceil(fraction * len(self))
        return Trajectory(self.t[:n], self.p[:n], self.q[:n], source=self.source)

    def slice_time(self, start: float, end: float) -> Trajectory:
        """Samples with ``start <= t <= end``."""
        keep = (self.t >= start) & (self.t <= end)
        return Trajectory(self.t[keep], self.p[keep], self.q[keep], source=self.source)
