"""Helpers for the descriptor tests: synthetic motions with known geometry, frame changes, data."""

from __future__ import annotations

import numpy as np

from framefree import Trajectory
from framefree.core import se3
from real_data import REAL_MOTIONS

REFERENCE_SET = REAL_MOTIONS / "reference_set"

#: (descriptor, progress) rows of Table I handled here
ROWS = [
    ("dhb", "arclength"),
    ("dhb", "angle"),
    ("dhb", "screw"),
    ("efs", "arclength"),
    ("efs", "angle"),
    ("efs", "screw"),
    ("isa", "angle"),
    ("isa", "screw"),
    ("rrv", "arclength"),
    ("rrv", "angle"),
    ("rrv", "screw"),
    ("dsrf", "arclength"),
    ("dsrf", "angle"),
    ("dsrf", "screw"),
]


def pose(rotvec, trans) -> np.ndarray:
    """Homogeneous pose (4, 4) from a rotation vector [rad] and a translation [m]."""
    T = np.eye(4)
    T[:3, :3] = se3.rotation_from_vector(np.asarray(rotvec, dtype=float))
    T[:3, 3] = trans
    return T


def generic_trajectory(duration: float = 4.0, rate: float = 50.0) -> Trajectory:
    """A smooth, non-singular motion: helical path, orientation turning about a moving axis."""
    t = np.arange(0.0, duration + 1e-9, 1.0 / rate)
    p = np.column_stack(
        [0.3 * np.cos(0.8 * t), 0.3 * np.sin(0.8 * t), 0.05 * t + 0.02 * np.sin(1.3 * t)]
    )
    rv = np.column_stack([0.6 * np.sin(0.7 * t), 0.4 * np.cos(0.5 * t) - 0.4, 0.3 * t])
    T = np.array([pose(r, x) for r, x in zip(rv, p, strict=True)])
    return Trajectory.from_poses(t, T, source="generic")


def screw_trajectory(total_angle: float, total_shift: float, n: int = 151) -> Trajectory:
    """Constant-rate rotation about z with translation along z (body origin on the axis)."""
    s = np.linspace(0.0, 1.0, n)
    T = np.array([pose([0, 0, total_angle * u], [0, 0, total_shift * u]) for u in s])
    return Trajectory.from_poses(2.0 * s, T, source="screw")


def real(name: str) -> Trajectory:
    """A recording of the reference set, e.g. ``real("ip_pouring_motion__tfworld")``."""
    return Trajectory.from_csv(REFERENCE_SET / f"{name}.csv")


def rel(a: np.ndarray, b: np.ndarray) -> float:
    """Relative Frobenius difference ``|a - b| / |b|``."""
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def circle_trajectory(radius: float = 0.2, arc: float = 2.0, rate: float = 50.0) -> Trajectory:
    """Constant orientation, body origin on a circle of ``radius`` in the xy plane, ``arc`` rad."""
    t = np.arange(0.0, arc + 1e-9, 1.0 / rate)
    T = np.array([pose([0.2, -0.1, 0.4], radius * np.array([np.cos(u), np.sin(u), 0])) for u in t])
    return Trajectory.from_poses(t, T, source="circle")


def pure_rotation_trajectory() -> Trajectory:
    """Rotation about a fixed axis through the body origin (arclength exactly zero)."""
    t = np.linspace(0.0, 2.0, 101)
    T = np.array([pose([0.1 * u, 0.0, u], [0.4, -0.2, 1.0]) for u in t])
    return Trajectory.from_poses(t, T, source="pure rotation")


def pure_translation_trajectory() -> Trajectory:
    """Straight-line translation with constant orientation (angle progress exactly zero)."""
    t = np.linspace(0.0, 2.0, 101)
    T = np.array([pose([0.3, 0.2, -0.1], [0.2 * u, 0.1 * u, 0.0]) for u in t])
    return Trajectory.from_poses(t, T, source="pure translation")


def standstill_trajectory() -> Trajectory:
    t = np.linspace(0.0, 1.0, 51)
    T = np.array([pose([0.3, 0.2, -0.1], [0.2, 0.1, 0.0]) for _ in t])
    return Trajectory.from_poses(t, T, source="standstill")


def world_changed(traj: Trajectory, world: np.ndarray) -> Trajectory:
    return traj.transformed(world=world)


def body_changed(traj: Trajectory, body: np.ndarray) -> Trajectory:
    return traj.transformed(body=body)


def constant_isa_trajectory(w1=1.2, w2=0.5, v1=0.1, v2=0.05, duration=3.0, dt=1e-3, every=20):
    """Motion with constant ISA invariants (ω₁, ω₂, 0, v₁, v₂, 0) per unit time.

    The ISA frame screws about its own y axis (rotation ω₂, translation v₂ per unit time); the
    object turns about the ISA frame's x axis at ω₁ while sliding along it at v₁. Integrated with
    midpoint exponential steps of ``dt`` and sampled every ``every`` steps.
    """
    from framefree.core import se3

    def adjoint(T):
        R, p = T[:3, :3], T[:3, 3]
        A = np.zeros((6, 6))
        A[:3, :3] = R
        A[3:, 3:] = R
        A[3:, :3] = se3.hat(p) @ R
        return A

    T = pose([0, 0, 0], [0.0, 0.2, 0.1])
    ts, Ts = [0.0], [T.copy()]
    body = np.array([w1, 0, 0, v1, 0, 0])
    for k in range(round(duration / dt)):
        sm = (k + 0.5) * dt
        F = se3.pose_from_twist(np.array([0, w2 * sm, 0, 0, v2 * sm, 0]))
        T = se3.pose_from_twist(adjoint(F) @ body * dt) @ T
        ts.append((k + 1) * dt)
        Ts.append(T.copy())
    return Trajectory.from_poses(np.array(ts)[::every], np.array(Ts)[::every], source="const ISA")


def finite_or_degenerate(fn):
    """Call ``fn``; a DegenerateMotionError is fine (returns None), otherwise all must be finite."""
    from framefree.errors import DegenerateMotionError

    try:
        out = fn()
    except DegenerateMotionError:
        return None
    assert np.isfinite(out).all()
    return out


def time_rescaling_change(name: str, progress: str, factor: float = 2.0) -> float:
    """Relative change of a descriptor when the generic motion is executed ``factor`` × slower."""
    from framefree import get_descriptor

    traj = generic_trajectory()
    d = get_descriptor(name, progress=progress, L=0.5)
    return rel(d.compute(traj.time_scaled(factor)), d.compute(traj))
