"""Franka Emika Panda kinematics and gravity from the published parameters (pure numpy).

Kinematics: Franka's modified Denavit–Hartenberg table (Craig's convention), as printed in the
Franka Control Interface documentation ("Robot and interface specifications"): the transform from
frame ``i-1`` to frame ``i`` is ``Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``; the flange sits
0.107 m along joint 7's axis; the Franka Hand is mounted at −45° about the flange axis and its tool
centre point (TCP, between the finger tips) lies 0.1034 m further along it.

Inertial parameters: the physically consistent identified values of C. Gaz, M. Cognetti, A. Oliva,
P. Robuffo Giordano, A. De Luca, "Dynamic identification of the Franka Emika Panda robot with
retrieval of feasible parameters using penalty-based optimization", IEEE RA-L 4(4), 2019 (masses,
centres of mass and inertia tensors expressed in the DH link frames), and the Franka Hand data
sheet mass (0.73 kg, fingers 0.015 kg each).

Conventions: SI units, base frame = robot base (z up), twists rotation first ``(ω; v)``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "DH_TABLE",
    "FINGER_BASE",
    "FINGER_COM_HEIGHT",
    "FINGER_MASS",
    "FLANGE_LENGTH",
    "GRAVITY",
    "HAND_CENTER_OF_MASS",
    "HAND_MASS",
    "HAND_YAW",
    "LINK_CENTERS_OF_MASS",
    "LINK_INERTIAS",
    "LINK_MASSES",
    "QD_MAX",
    "Q_MAX",
    "Q_MIN",
    "Q_READY",
    "TAU_MAX",
    "TCP_OFFSET",
    "PandaKinematics",
    "rotation_error",
]

#: Modified DH parameters, one row per joint: ``(a_{i-1} [m], d_i [m], alpha_{i-1} [rad])``.
DH_TABLE = np.array(
    [
        [0.0, 0.333, 0.0],
        [0.0, 0.0, -math.pi / 2],
        [0.0, 0.316, math.pi / 2],
        [0.0825, 0.0, math.pi / 2],
        [-0.0825, 0.384, -math.pi / 2],
        [0.0, 0.0, math.pi / 2],
        [0.088, 0.0, math.pi / 2],
    ]
)
#: Flange offset along joint 7's axis [m].
FLANGE_LENGTH = 0.107
#: Rotation of the Franka Hand about the flange z axis [rad].
HAND_YAW = -math.pi / 4
#: Distance from the flange to the tool centre point, along the hand z axis [m].
TCP_OFFSET = 0.1034
#: Height of the finger bodies (slide-joint origins) above the flange, in the hand frame [m].
FINGER_BASE = 0.0584

#: Joint limits [rad] (Franka datasheet).
Q_MIN = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
Q_MAX = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])
#: Joint speed limits [rad/s].
QD_MAX = np.array([2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100])
#: Joint torque limits [N m].
TAU_MAX = np.array([87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0])
#: Franka's "ready" configuration [rad].
Q_READY = np.array([0.0, -math.pi / 4, 0.0, -3 * math.pi / 4, 0.0, math.pi / 2, math.pi / 4])

#: Link masses [kg] (Gaz et al. 2019), links 1..7.
LINK_MASSES = np.array([4.970684, 0.646926, 3.228604, 3.587895, 1.225946, 1.666555, 0.735522])
#: Link centres of mass in the link's DH frame [m], shape (7, 3).
LINK_CENTERS_OF_MASS = np.array(
    [
        [3.875e-03, 2.081e-03, -4.762e-02],
        [-3.141e-03, -2.872e-02, 3.495e-03],
        [2.7518e-02, 3.9252e-02, -6.6502e-02],
        [-5.317e-02, 1.04419e-01, 2.7454e-02],
        [-1.1953e-02, 4.1065e-02, -3.8437e-02],
        [6.0149e-02, -1.4117e-02, -1.0517e-02],
        [1.0517e-02, -4.252e-03, 6.1597e-02],
    ]
)
#: Link inertia tensors about the centre of mass, in the DH frame, as
#: ``(Ixx, Iyy, Izz, Ixy, Ixz, Iyz)`` [kg m²], shape (7, 6).
LINK_INERTIAS = np.array(
    [
        [7.0337e-01, 7.0661e-01, 9.1170e-03, -1.3900e-04, 6.7720e-03, 1.9169e-02],
        [7.9620e-03, 2.8110e-02, 2.5995e-02, -3.9250e-03, 1.0254e-02, 7.0400e-04],
        [3.7242e-02, 3.6155e-02, 1.0830e-02, -4.7610e-03, -1.1396e-02, -1.2805e-02],
        [2.5853e-02, 1.9552e-02, 2.8323e-02, 7.7960e-03, -1.3320e-03, 8.6410e-03],
        [3.5549e-02, 2.9474e-02, 8.6270e-03, -2.1170e-03, -4.0370e-03, 2.2900e-04],
        [1.9640e-03, 4.3540e-03, 5.4330e-03, 1.0900e-04, -1.1580e-03, 3.4100e-04],
        [1.2516e-02, 1.0027e-02, 4.8150e-03, -4.2800e-04, -1.1960e-03, -7.4100e-04],
    ]
)
#: Franka Hand mass [kg] and centre of mass in the hand frame [m].
HAND_MASS = 0.73
HAND_CENTER_OF_MASS = np.array([-0.01, 0.0, 0.03])
#: Mass of one finger [kg] and height of its centre of mass above the finger base [m].
FINGER_MASS = 0.015
FINGER_COM_HEIGHT = 0.025
#: Gravity vector in the base frame [m/s²].
GRAVITY = np.array([0.0, 0.0, -9.81])


@njit(cache=True)
def _frames_kernel(q, dh, flange_to_hand, out):
    """Frames 1..7 and the hand frame for joint angles ``q`` (writes ``out`` (8, 4, 4))."""
    T = np.eye(4)
    A = np.zeros((4, 4))
    A[3, 3] = 1.0
    for i in range(7):
        a = dh[i, 0]
        d = dh[i, 1]
        ca = math.cos(dh[i, 2])
        sa = math.sin(dh[i, 2])
        ct = math.cos(q[i])
        st = math.sin(q[i])
        A[0, 0] = ct
        A[0, 1] = -st
        A[0, 2] = 0.0
        A[0, 3] = a
        A[1, 0] = st * ca
        A[1, 1] = ct * ca
        A[1, 2] = -sa
        A[1, 3] = -d * sa
        A[2, 0] = st * sa
        A[2, 1] = ct * sa
        A[2, 2] = ca
        A[2, 3] = d * ca
        T = T @ A
        out[i] = T
    out[7] = T @ flange_to_hand


@njit(cache=True)
def _jacobian_kernel(frames, p, J):
    for j in range(7):
        z0 = frames[j, 0, 2]
        z1 = frames[j, 1, 2]
        z2 = frames[j, 2, 2]
        r0 = p[0] - frames[j, 0, 3]
        r1 = p[1] - frames[j, 1, 3]
        r2 = p[2] - frames[j, 2, 3]
        J[0, j] = z0
        J[1, j] = z1
        J[2, j] = z2
        J[3, j] = z1 * r2 - z2 * r1
        J[4, j] = z2 * r0 - z0 * r2
        J[5, j] = z0 * r1 - z1 * r0


@njit(cache=True)
def _gravity_kernel(frames, com_local, mass, g, out):
    """Gravity compensation torques; bodies 0..6 ride on links 1..7, the rest on the hand frame."""
    nb = mass.shape[0]
    fx = 0.0
    fy = 0.0
    fz = 0.0
    mx = 0.0
    my = 0.0
    mz = 0.0
    b = nb - 1
    for j in range(6, -1, -1):
        # add every body carried by link j+1 (for j = 6 also the hand-frame bodies)
        while b >= 0 and (b > 6 or b == j):
            f = 7 if b > 6 else b
            c = np.empty(3)
            for r in range(3):
                c[r] = (
                    frames[f, r, 0] * com_local[b, 0]
                    + frames[f, r, 1] * com_local[b, 1]
                    + frames[f, r, 2] * com_local[b, 2]
                    + frames[f, r, 3]
                )
            Fx = mass[b] * g[0]
            Fy = mass[b] * g[1]
            Fz = mass[b] * g[2]
            fx += Fx
            fy += Fy
            fz += Fz
            mx += c[1] * Fz - c[2] * Fy
            my += c[2] * Fx - c[0] * Fz
            mz += c[0] * Fy - c[1] * Fx
            b -= 1
        ox = frames[j, 0, 3]
        oy = frames[j, 1, 3]
        oz = frames[j, 2, 3]
        tx = mx - (oy * fz - oz * fy)
        ty = my - (oz * fx - ox * fz)
        tz = mz - (ox * fy - oy * fx)
        out[j] = -(frames[j, 0, 2] * tx + frames[j, 1, 2] * ty + frames[j, 2, 2] * tz)


def _rotz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_error(R_desired: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Rotation vector that turns ``R`` into ``R_desired``, expressed in the base frame.

    Parameters
    ----------
    R_desired, R : ndarray, shape (3, 3)
        Rotation matrices.

    Returns
    -------
    ndarray, shape (3,)
        ``log(R_desired Rᵀ)`` as a rotation vector [rad] (angle in [0, π]).
    """
    E = R_desired @ R.T
    cos = min(1.0, max(-1.0, 0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0)))
    angle = math.acos(cos)
    w = np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]])
    s = math.sin(angle)
    if s < 1e-9:
        if cos > 0:
            return 0.5 * w
        # angle near π: axis from the symmetric part
        B = 0.5 * (E + np.eye(3))
        axis = B[np.argmax(np.diag(B))]
        return math.pi * axis / np.linalg.norm(axis)
    return angle / (2.0 * s) * w


class PandaKinematics:
    """Forward kinematics, geometric Jacobian and gravity torques of a Panda with its hand.

    Parameters
    ----------
    payload : float, optional
        Extra mass [kg] held at the TCP (added to the gravity model).
    """

    def __init__(self, payload: float = 0.0):
        self.payload = float(payload)
        self._flange = np.eye(4)
        self._flange[2, 3] = FLANGE_LENGTH
        self._hand = np.eye(4)
        self._hand[:3, :3] = _rotz(HAND_YAW)
        self._tcp = np.eye(4)
        self._tcp[2, 3] = TCP_OFFSET
        self._flange_to_hand = self._flange @ self._hand
        # gravity bodies: links 1..7 (own frames), hand + fingers and payload (hand frame)
        m_h = HAND_MASS + 2 * FINGER_MASS
        finger_com = np.array([0.0, 0.0, FINGER_BASE + FINGER_COM_HEIGHT])
        self._hand_com = (HAND_MASS * HAND_CENTER_OF_MASS + 2 * FINGER_MASS * finger_com) / m_h
        self._com_local = np.zeros((9, 3))
        self._com_local[:7] = LINK_CENTERS_OF_MASS
        self._com_local[7] = self._hand_com
        self._com_local[8] = [0.0, 0.0, TCP_OFFSET]
        self._mass = np.concatenate([LINK_MASSES, [m_h, self.payload]])

    # ------------------------------------------------------------------ kinematics
    def link_frames(self, q: np.ndarray) -> np.ndarray:
        """Poses of the joint frames 1..7 and of the hand frame in the base frame.

        Parameters
        ----------
        q : ndarray, shape (7,)
            Joint angles [rad].

        Returns
        -------
        ndarray, shape (8, 4, 4)
            Frames 1..7 (joint ``i`` rotates about the z axis of frame ``i``) and the hand frame.
        """
        out = np.empty((8, 4, 4))
        _frames_kernel(np.asarray(q, dtype=float), DH_TABLE, self._flange_to_hand, out)
        return out

    def tcp_pose(self, q: np.ndarray, frames: np.ndarray | None = None) -> np.ndarray:
        """Pose of the tool centre point in the base frame.

        Parameters
        ----------
        q : ndarray, shape (7,)
            Joint angles [rad].
        frames : ndarray, shape (8, 4, 4), optional
            Output of :meth:`link_frames` for ``q`` (to avoid recomputing it).

        Returns
        -------
        ndarray, shape (4, 4)
            Homogeneous TCP pose [m].
        """
        if frames is None:
            frames = self.link_frames(q)
        return frames[7] @ self._tcp

    def jacobian(self, q: np.ndarray, frames: np.ndarray | None = None) -> np.ndarray:
        """Geometric Jacobian of the TCP, rotation rows first, in the base frame.

        Parameters
        ----------
        q : ndarray, shape (7,)
            Joint angles [rad].
        frames : ndarray, shape (8, 4, 4), optional
            Output of :meth:`link_frames` for ``q``.

        Returns
        -------
        ndarray, shape (6, 7)
            ``(ω; v) = J q̇`` with ω [rad/s] and the TCP's linear velocity v [m/s].
        """
        if frames is None:
            frames = self.link_frames(q)
        p = frames[7, :3, :3] @ self._tcp[:3, 3] + frames[7, :3, 3]
        J = np.empty((6, 7))
        _jacobian_kernel(frames, p, J)
        return J

    # ------------------------------------------------------------------ gravity
    def gravity_torque(self, q: np.ndarray, frames: np.ndarray | None = None) -> np.ndarray:
        """Joint torques that compensate gravity (what MuJoCo calls the bias force at rest).

        Parameters
        ----------
        q : ndarray, shape (7,)
            Joint angles [rad].
        frames : ndarray, shape (8, 4, 4), optional
            Output of :meth:`link_frames` for ``q``.

        Returns
        -------
        ndarray, shape (7,)
            Torques [N m] to apply so that the arm holds its configuration.
        """
        if frames is None:
            frames = self.link_frames(q)
        self._com_local[7] = self._hand_com
        self._mass[8] = self.payload
        out = np.empty(7)
        _gravity_kernel(frames, self._com_local, self._mass, GRAVITY, out)
        return out

    # ------------------------------------------------------------------ inverse kinematics
    def inverse_kinematics(
        self,
        target: np.ndarray,
        q0: np.ndarray,
        iterations: int = 500,
        tolerance: float = 1e-10,
        rest: np.ndarray | None = None,
    ) -> np.ndarray:
        """Numerical inverse kinematics (damped Newton with null-space pull to ``rest``).

        Parameters
        ----------
        target : ndarray, shape (4, 4)
            Desired TCP pose.
        q0 : ndarray, shape (7,)
            Initial guess [rad].
        iterations : int, optional
            Maximum number of iterations.
        tolerance : float, optional
            Stop when the squared pose error (rad², m²) falls below this value.
        rest : ndarray, shape (7,), optional
            Posture the redundancy is pulled towards (default ``q0``).

        Returns
        -------
        ndarray, shape (7,)
            Joint angles [rad], clipped to the joint limits.
        """
        q = np.array(q0, dtype=float)
        rest = q.copy() if rest is None else np.asarray(rest, dtype=float)
        for _ in range(iterations):
            frames = self.link_frames(q)
            T = self.tcp_pose(q, frames)
            e = np.concatenate([rotation_error(target[:3, :3], T[:3, :3]), target[:3, 3] - T[:3, 3]])
            if e @ e < tolerance:
                break
            J = self.jacobian(q, frames)
            Jp = J.T @ np.linalg.solve(J @ J.T + 1e-6 * np.eye(6), np.eye(6))
            dq = Jp @ e + (np.eye(7) - Jp @ J) @ (0.1 * (rest - q))
            q = np.clip(q + dq, Q_MIN, Q_MAX)
        return q
