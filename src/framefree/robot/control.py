"""Velocity-level inverse kinematics and joint impedance control of the Panda.

See docs/robot.md, *From the paper to the simulation* and *Control*.

Each control period ``dt``:

1. **Reference twist**: the planner's twist plus an orientation loop,
   ``ω_ref = ω_cmd + k_R · log(R_des R(φ_k)ᵀ)`` (keeps the gripper pointing down although
   directional commands carry no rotation).
2. **Damped least squares** at the joint reference ``φ_k`` (the integrated joint angles, which the
   measured ones track to within the impedance error):
   ``φ̇ = Σ σ_i/(σ_i² + λ²) v_i u_iᵀ x_ref`` with the adaptive damping
   ``λ² = λ_max² (1 − (σ_min/ε)²)`` when ``σ_min < ε`` (zero otherwise) — exact pseudo-inverse
   away from singularities, bounded joint speeds at them.
3. **Redundancy**: a null-space velocity ``k_null (φ_rest − φ)`` plus a repulsion from joint
   limits inside a buffer zone, projected onto the null space of the Jacobian.
4. **Joint limits** (clamping): a joint whose next reference would leave
   ``[q_min + margin, q_max − margin]`` is locked at the bound and the task is re-solved with the
   remaining joints (up to 7 passes); then all joint speeds are scaled by one common factor so
   that ``|φ̇_i| ≤ qd_scale · qd_max_i`` (the direction of motion is kept).
5. **Integration**: ``φ_{k+1} = φ_k + dt φ̇_k``.
6. **Joint impedance with gravity compensation**:
   ``τ = K (φ_{k+1} − q) + D (φ̇_k − q̇) + g(q)``, clipped to the torque limits, with ``g`` from
   the published inertial parameters (:class:`~framefree.robot.kinematics.PandaKinematics`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .kinematics import (
    DH_TABLE,
    Q_MAX,
    Q_MIN,
    QD_MAX,
    TAU_MAX,
    PandaKinematics,
    _frames_kernel,
    _jacobian_kernel,
    rotation_error,
)

__all__ = ["HOME_Q", "ControlParams", "Controller", "dls_velocity"]

#: Home configuration [rad]: TCP at (0.5, 0, 0.2) m, pointing down (IK of the default home pose).
HOME_Q = np.array([0.0, 0.0459, 0.0, -2.3763, 0.0, 2.4222, 0.7854])


@dataclass(frozen=True)
class ControlParams:
    """Gains and limits of the velocity mapping and of the joint impedance controller.

    Attributes
    ----------
    stiffness : tuple of float
        Joint stiffness K [N m/rad] (libfranka's joint impedance example values).
    damping : tuple of float
        Joint damping D [N m s/rad].
    orientation_gain : float
        Gain k_R of the orientation loop [1/s].
    damping_max : float
        λ_max of the damped least squares [m/s per rad/s, dimensionless here].
    singular_threshold : float
        ε: damping starts when the smallest singular value drops below it.
    nullspace_gain : float
        k_null [1/s], pull towards ``rest`` in the null space.
    limit_buffer : float
        Width of the zone near a joint limit where the null-space repulsion acts [rad].
    limit_gain : float
        Strength of that repulsion [rad/s at the limit].
    limit_margin : float
        The joint reference is kept this far inside the joint limits [rad].
    qd_scale : float
        Fraction of the joint speed limits the reference may use.
    rest : tuple of float
        Rest posture for the null-space pull [rad] (default :data:`HOME_Q`).
    """

    stiffness: tuple[float, ...] = (600.0, 600.0, 600.0, 600.0, 250.0, 150.0, 50.0)
    damping: tuple[float, ...] = (50.0, 50.0, 50.0, 50.0, 30.0, 25.0, 15.0)
    orientation_gain: float = 2.0
    damping_max: float = 0.05
    singular_threshold: float = 0.05
    nullspace_gain: float = 0.5
    limit_buffer: float = 0.3
    limit_gain: float = 0.5
    limit_margin: float = 0.02
    qd_scale: float = 0.5
    rest: tuple[float, ...] = tuple(HOME_Q)


@njit(cache=True)
def _dls_kernel(J, twist, damping_max, threshold, secondary, use_secondary):
    n = J.shape[1]
    U, s, Vt = np.linalg.svd(J, full_matrices=True)
    r = s.shape[0]
    s_min = s[r - 1] if r > 0 else 0.0
    lam2 = 0.0
    if s_min < threshold:
        lam2 = (1.0 - (s_min / threshold) ** 2) * damping_max**2
    dq = np.zeros(n)
    rank = 0
    for i in range(r):
        if s[i] > 1e-9:
            rank += 1
        if lam2 > 0.0:
            g = s[i] / (s[i] * s[i] + lam2)
        elif s[i] > 1e-12:
            g = 1.0 / s[i]
        else:
            g = 0.0
        c = 0.0
        for k in range(U.shape[0]):
            c += U[k, i] * twist[k]
        c *= g
        for j in range(n):
            dq[j] += Vt[i, j] * c
    if use_secondary:
        for i in range(rank, n):
            c = 0.0
            for j in range(n):
                c += Vt[i, j] * secondary[j]
            for j in range(n):
                dq[j] += Vt[i, j] * c
    return dq


def dls_velocity(
    J: np.ndarray,
    twist: np.ndarray,
    damping_max: float,
    threshold: float,
    secondary: np.ndarray | None = None,
) -> np.ndarray:
    """Joint velocities from a twist by damped least squares, plus a null-space velocity.

    Parameters
    ----------
    J : ndarray, shape (6, n)
        Jacobian (rotation rows first).
    twist : ndarray, shape (6,)
        Desired twist ``(ω; v)``.
    damping_max : float
        λ_max of the adaptive damping.
    threshold : float
        ε: singular value below which damping sets in.
    secondary : ndarray, shape (n,), optional
        Joint velocity projected onto the null space of ``J``.

    Returns
    -------
    ndarray, shape (n,)
        Joint velocities.
    """
    J = np.ascontiguousarray(J, dtype=float)
    sec = np.zeros(J.shape[1]) if secondary is None else np.asarray(secondary, dtype=float)
    return _dls_kernel(
        J, np.asarray(twist, dtype=float), damping_max, threshold, sec, secondary is not None
    )


@njit(cache=True)
def _update_kernel(q, twist, J, lo, hi, qd_max, secondary, damping_max, threshold, dt):
    """Clamping loop: DLS on the free joints, lock joints that would leave their range."""
    free = np.ones(7, dtype=np.bool_)
    dq = np.zeros(7)
    for _ in range(7):
        nf = 0
        for j in range(7):
            if free[j]:
                nf += 1
        Jf = np.empty((6, nf))
        sf = np.empty(nf)
        x = twist.copy()
        c = 0
        for j in range(7):
            if free[j]:
                Jf[:, c] = J[:, j]
                sf[c] = secondary[j]
                c += 1
            else:
                for k in range(6):
                    x[k] -= J[k, j] * dq[j]
        dqf = _dls_kernel(Jf, x, damping_max, threshold, sf, True)
        c = 0
        for j in range(7):
            if free[j]:
                dq[j] = dqf[c]
                c += 1
        any_over = False
        for j in range(7):
            if not free[j]:
                continue
            nxt = q[j] + dq[j] * dt
            if nxt > hi[j]:
                dq[j] = min((hi[j] - q[j]) / dt, 0.0) if q[j] > hi[j] else (hi[j] - q[j]) / dt
                free[j] = False
                any_over = True
            elif nxt < lo[j]:
                dq[j] = max((lo[j] - q[j]) / dt, 0.0) if q[j] < lo[j] else (lo[j] - q[j]) / dt
                free[j] = False
                any_over = True
        if not any_over:
            break
        nf = 0
        for j in range(7):
            if free[j]:
                nf += 1
        if nf == 0:
            break
    ratio = 0.0
    for j in range(7):
        ratio = max(ratio, abs(dq[j]) / qd_max[j])
    if ratio > 1.0:
        for j in range(7):
            dq[j] /= ratio
    return dq, ~free


class Controller:
    """Twist → joint reference → joint torques, for the 7 arm joints of the Panda.

    Parameters
    ----------
    params : ControlParams, optional
        Gains and limits.
    kinematics : PandaKinematics, optional
        Robot model (kinematics and gravity).

    Attributes
    ----------
    q_ref : ndarray, shape (7,)
        Joint reference φ [rad].
    dq_ref : ndarray, shape (7,)
        Joint reference velocity φ̇ [rad/s] of the last period.
    locked : ndarray of bool, shape (7,)
        Joints clamped at a limit in the last period.
    """

    def __init__(self, params: ControlParams | None = None, kinematics: PandaKinematics | None = None):
        self.params = ControlParams() if params is None else params
        self.kin = PandaKinematics() if kinematics is None else kinematics
        p = self.params
        self._K = np.array(p.stiffness)
        self._D = np.array(p.damping)
        self._rest = np.array(p.rest)
        self._lo = Q_MIN + p.limit_margin
        self._hi = Q_MAX - p.limit_margin
        self._qd_max = p.qd_scale * QD_MAX
        self.q_ref = np.array(self._rest)
        self.dq_ref = np.zeros(7)
        self.locked = np.zeros(7, dtype=bool)

    def reset(self, q: np.ndarray) -> None:
        """Start the reference at the measured configuration.

        Parameters
        ----------
        q : ndarray, shape (7,)
            Joint angles [rad].
        """
        self.q_ref = np.clip(np.array(q, dtype=float), self._lo, self._hi)
        self.dq_ref = np.zeros(7)

    # ------------------------------------------------------------------ reference
    def reference_twist(self, twist: np.ndarray, orientation: np.ndarray | None) -> np.ndarray:
        """Planner twist plus the orientation loop at the current reference, shape (6,)."""
        x = np.array(twist, dtype=float)
        if orientation is not None:
            R = self.kin.tcp_pose(self.q_ref)[:3, :3]
            x[:3] += self.params.orientation_gain * rotation_error(orientation, R)
        return x

    def _secondary(self, q: np.ndarray) -> np.ndarray:
        p = self.params
        v = p.nullspace_gain * (self._rest - q)
        d_lo = q - Q_MIN
        d_hi = Q_MAX - q
        v += np.where(d_lo < p.limit_buffer, p.limit_gain * (1 - d_lo / p.limit_buffer), 0.0)
        v -= np.where(d_hi < p.limit_buffer, p.limit_gain * (1 - d_hi / p.limit_buffer), 0.0)
        return v

    def update_reference(
        self, twist: np.ndarray, dt: float, orientation: np.ndarray | None = None
    ) -> np.ndarray:
        """Map a twist to joint velocities, clamp them to the limits and integrate the reference.

        Parameters
        ----------
        twist : ndarray, shape (6,)
            Commanded TCP twist ``(ω; v)`` [rad/s, m/s].
        dt : float
            Control period [s].
        orientation : ndarray, shape (3, 3), optional
            Desired TCP orientation (orientation loop off when None).

        Returns
        -------
        ndarray, shape (7,)
            The new joint reference φ_{k+1} [rad].
        """
        p = self.params
        q = self.q_ref
        frames = np.empty((8, 4, 4))
        _frames_kernel(q, DH_TABLE, self.kin._flange_to_hand, frames)
        T = frames[7] @ self.kin._tcp
        x = np.array(twist, dtype=float)
        if orientation is not None:
            x[:3] += p.orientation_gain * rotation_error(orientation, T[:3, :3])
        J = np.empty((6, 7))
        _jacobian_kernel(frames, T[:3, 3].copy(), J)
        dq, locked = _update_kernel(
            q, x, J, self._lo, self._hi, self._qd_max, self._secondary(q),
            p.damping_max, p.singular_threshold, float(dt),
        )
        self.locked = locked
        self.dq_ref = dq
        self.q_ref = q + dq * dt
        return self.q_ref

    # ------------------------------------------------------------------ torques
    def torque(self, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """Joint impedance torques with gravity compensation at the measured state.

        Parameters
        ----------
        q, dq : ndarray, shape (7,)
            Measured joint angles [rad] and velocities [rad/s].

        Returns
        -------
        ndarray, shape (7,)
            ``τ = K(φ − q) + D(φ̇ − q̇) + g(q)`` [N m], clipped to the torque limits.
        """
        tau = self._K * (self.q_ref - q) + self._D * (self.dq_ref - dq) + self.kin.gravity_torque(q)
        return np.clip(tau, -TAU_MAX, TAU_MAX)

    def step(
        self,
        twist: np.ndarray,
        q: np.ndarray,
        dq: np.ndarray,
        dt: float,
        orientation: np.ndarray | None = None,
    ) -> np.ndarray:
        """One control period: update the reference from the twist, return the torques.

        Parameters
        ----------
        twist : ndarray, shape (6,)
            Commanded TCP twist [rad/s, m/s].
        q, dq : ndarray, shape (7,)
            Measured joint angles [rad] and velocities [rad/s].
        dt : float
            Control period [s].
        orientation : ndarray, shape (3, 3), optional
            Desired TCP orientation.

        Returns
        -------
        ndarray, shape (7,)
            Joint torques [N m].
        """
        self.update_reference(twist, dt, orientation)
        return self.torque(q, dq)
