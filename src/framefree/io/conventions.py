"""Coordinate conventions of tracking systems, and the one conversion into framefree's frame.

framefree works in a **right-handed frame with z up**, quaternions scalar first ``(w, x, y, z)``
(Hamilton). Tracking systems differ on all three counts, and a wrong guess is silent and
expensive: a left-handed frame read as a right-handed one mirrors every motion, which flips the
sign of every screw pitch — exactly what tells *open gripper* from *close gripper* — and a y-up
frame read as z-up loses the vertical that the ``gravity`` invariance keeps. So a convention is
always named, never guessed.

===========  ============  ======  ==================  =========================================
name         handedness    up      quaternion order    axes (as the system defines them)
===========  ============  ======  ==================  =========================================
framefree    right         +z      w x y z             framefree's own CSV
ros          right         +z      x y z w             REP 103: x forward, y left, z up
openvr       right         +y      w x y z             SteamVR: x right, y up, −z forward; the replica
unity        left          +y      x y z w             x right, y up, z forward (Machete, VR apps)
===========  ============  ======  ==================  =========================================

A pose ``(p, R)`` given in a source frame becomes ``(P p, P R Pᵀ)`` in framefree's frame, with
``P`` the 3×3 change of basis from the source axes to framefree's axes. For a left-handed source
``det P = −1`` (a mirror); ``P R Pᵀ`` is then still a proper rotation, and a motion keeps its
physical handedness: a right-handed screw in the room stays a right-handed screw. ``P R Pᵀ`` turns
by the same angle about ``det(P) · P a`` when ``R`` turns about ``a``, so a quaternion
``(w, v)`` becomes ``(w, det(P) · P v)`` exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import TrajectoryError

__all__ = ["CONVENTIONS", "UP", "Convention", "get_convention", "poses_to_framefree"]

#: The vertical of framefree's frame (after conversion from any convention).
UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class Convention:
    """A tracking system's coordinate convention.

    Attributes
    ----------
    name : str
    handedness : {"right", "left"}
    up : str
        The source axis that points up: ``"+y"`` or ``"+z"``.
    quat_order : {"wxyz", "xyzw"}
        Order of the quaternion components as the system writes them.
    basis : ndarray, shape (3, 3)
        ``P``: framefree coordinates = ``P @`` source coordinates.
    """

    name: str
    handedness: str
    up: str
    quat_order: str
    basis: np.ndarray

    def __post_init__(self) -> None:
        det = float(np.linalg.det(self.basis))
        if not np.allclose(self.basis @ self.basis.T, np.eye(3)) or abs(abs(det) - 1.0) > 1e-12:
            raise ValueError(f"convention {self.name}: basis is not orthonormal")
        if (det < 0) != (self.handedness == "left"):
            raise ValueError(f"convention {self.name}: a {self.handedness}-handed frame needs det P = "
                             f"{'-1' if self.handedness == 'left' else '+1'}")


CONVENTIONS: dict[str, Convention] = {
    "framefree": Convention("framefree", "right", "+z", "wxyz", np.eye(3)),
    "ros": Convention("ros", "right", "+z", "xyzw", np.eye(3)),
    # SteamVR: x right, y up, -z forward -> framefree: x right, y forward, z up (a quarter turn)
    "openvr": Convention("openvr", "right", "+y", "wxyz",
                         np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])),
    # Unity: x right, y up, z forward -> framefree: x right, y forward, z up (swap y and z: a mirror)
    "unity": Convention("unity", "left", "+y", "xyzw",
                        np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])),
}
CONVENTIONS["steamvr"] = CONVENTIONS["openvr"]


def get_convention(name: str | Convention) -> Convention:
    """The convention called ``name`` (one of :data:`CONVENTIONS`), or ``name`` itself."""
    if isinstance(name, Convention):
        return name
    try:
        return CONVENTIONS[str(name).lower()]
    except KeyError:
        raise TrajectoryError(f"unknown coordinate convention {name!r}; choose one of "
                              f"{', '.join(sorted(CONVENTIONS))}") from None


def poses_to_framefree(
    p: np.ndarray, quat: np.ndarray, convention: str | Convention
) -> tuple[np.ndarray, np.ndarray]:
    """Positions and quaternions of a source convention, in framefree's frame.

    Parameters
    ----------
    p : array_like, shape (N, 3)
        Positions [m] in the source frame.
    quat : array_like, shape (N, 4)
        Orientations in the source frame, components in the convention's ``quat_order``.
    convention : str or Convention

    Returns
    -------
    p : ndarray, shape (N, 3)
        Positions [m], right-handed, z up.
    q : ndarray, shape (N, 4)
        Unit quaternions ``(w, x, y, z)``.
    """
    conv = get_convention(convention)
    p = np.asarray(p, dtype=np.float64)
    quat = np.asarray(quat, dtype=np.float64)
    q = quat[:, [3, 0, 1, 2]] if conv.quat_order == "xyzw" else quat
    norms = np.linalg.norm(q, axis=1, keepdims=True)
    if np.any(norms == 0.0) or not np.all(np.isfinite(norms)):
        raise TrajectoryError("zero or non-finite quaternion in the source poses")
    q = q / norms
    P = conv.basis
    # P R Pᵀ turns about det(P) · P a by the same angle: the vector part maps the same way
    vector = np.linalg.det(P) * (q[:, 1:] @ P.T)
    return p @ P.T, np.column_stack([q[:, :1], vector])
