"""A Franka arm (FR3 or Panda) through franky (``pip install 'framefree[franka]'``).

The same backend drives a real arm over FCI and the libfranka-protocol simulator of
:mod:`framefree.robot.franka_sim`; it only knows a host address.

Command mapping (:func:`franka_velocity`, :func:`franka_twist`): the planner's TCP velocity becomes
a franky ``CartesianVelocityMotion`` of a ``Twist`` in the base frame: linear = the commanded
velocity [m/s], plus a small pull onto the path those velocities integrate to (franky's
motion generator and the arm's tracking lose a few per cent of a travel otherwise), clamped to
:attr:`FrankaLimits.max_speed` and cut where it would leave the workspace box; angular = a
proportional pull of the measured TCP orientation onto the planner's
(``orientation_gain`` [1/s], clamped to ``max_angular_speed``). A motion is valid for ``hold``
seconds and re-sent every period while the planner moves, so a framefree that falls silent stops
the arm. The finger reference goes to the gripper once per change of direction: ``move`` to open,
``grasp`` to close (a grasp holds an object with ``grasp_force`` and succeeds at any width).
franky's own 1 kHz loop, with the arm's limits scaled by ``dynamics_factor``, does the rest.

Before anything is sent, every period (:meth:`FrankaBackend.apply`): the command must be finite,
every joint must be farther than ``joint_margin`` from its limit, the TCP inside the workspace
box, the arm's state fresh (a state older than ``state_timeout`` seconds means a lost
connection). A violation stops the arm and raises :class:`~framefree.errors.FramefreeError` with
one line; so does any error franky reports (a refused motion, a reflex, a network error), with
one exception: when franky's motion planner (Ruckig) could not follow the arm's state, an
asynchronous motion ends with "Motion planner failed" and franky reports it at the next motion.
The arm has then braked, and the period's motion is sent once more from where the arm stands
(counted in :attr:`FrankaBackend.replans`); a second failure in a row stops the session.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...errors import FramefreeError
from ..planner import Command

__all__ = ["FR3_Q_MAX", "FR3_Q_MIN", "FrankaBackend", "FrankaLimits", "franka_twist",
           "franka_velocity"]

_MISSING = ("the Franka backend needs franky: pip install 'framefree[franka]' (and a Franka arm "
            "with FCI, or the simulator: framefree demo --robot franka-sim)")

#: Joint limits [rad] valid for both arms: the tighter of the FR3's and the Panda's published
#: limits, joint by joint.
FR3_Q_MIN = np.array([-2.7437, -1.7628, -2.8973, -3.0421, -2.8065, 0.5445, -2.8973])
FR3_Q_MAX = np.array([2.7437, 1.7628, 2.8973, -0.1518, 2.8065, 3.7525, 2.8973])


@dataclass(frozen=True)
class FrankaLimits:
    """What framefree enforces before a command reaches the arm (SI units, base frame).

    Attributes
    ----------
    max_speed : float
        Largest TCP speed sent [m/s]; a faster command is scaled down along its direction.
    max_angular_speed : float
        Largest TCP angular speed sent [rad/s].
    workspace_min, workspace_max : tuple of float
        Box the TCP stays in [m]: a velocity component that leads out of it is not sent, and a
        TCP found outside it by more than ``workspace_slack`` stops the session.
    workspace_slack : float
        Tolerance on the box for the measured TCP [m].
    joint_margin : float
        Distance to a joint limit (:data:`FR3_Q_MIN`, :data:`FR3_Q_MAX`) at which the session
        stops [rad].
    dynamics_factor : float
        franky's relative dynamics factor (fraction of the arm's velocity, acceleration and jerk
        limits that its motion generator may use).
    state_timeout : float
        A robot state that has not advanced for this long means a lost connection [s].
    """

    max_speed: float = 0.25
    max_angular_speed: float = 0.5
    workspace_min: tuple[float, float, float] = (0.2, -0.5, 0.0)
    workspace_max: tuple[float, float, float] = (0.8, 0.5, 0.7)
    workspace_slack: float = 0.02
    joint_margin: float = 0.05
    dynamics_factor: float = 0.1
    state_timeout: float = 0.5

    def __post_init__(self) -> None:
        for name in ("max_speed", "max_angular_speed", "dynamics_factor", "state_timeout"):
            if not getattr(self, name) > 0:
                raise ValueError(f"FrankaLimits.{name} must be positive")
        if not 0 < self.dynamics_factor <= 1:
            raise ValueError("FrankaLimits.dynamics_factor must be in (0, 1]")
        if np.any(np.asarray(self.workspace_min) >= np.asarray(self.workspace_max)):
            raise ValueError("FrankaLimits.workspace_min must be below workspace_max")


def franka_velocity(command: Command, max_speed: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """The translational twist sent for a planner command (no orientation feedback).

    Parameters
    ----------
    command : Command
    max_speed : float
        Largest linear speed sent [m/s]; a faster command is scaled down along its direction.

    Returns
    -------
    linear, angular : ndarray, shape (3,)
        Base-frame velocity [m/s] and angular velocity [rad/s] (zero).
    """
    v = np.asarray(command.velocity, dtype=float).copy()
    if not np.all(np.isfinite(v)):
        raise FramefreeError(f"planner command with a non-finite velocity {v.tolist()}: not sent")
    speed = float(np.linalg.norm(v))
    if speed > max_speed:
        v *= max_speed / speed
    return v, np.zeros(3)


def _rotation_vector(R: np.ndarray) -> np.ndarray:
    """Axis times angle [rad] of a rotation matrix, shape (3,)."""
    c = float(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0))
    angle = np.arccos(c)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if angle < 1e-9:
        return 0.5 * w
    if np.pi - angle < 1e-6:  # half a turn: the axis from the symmetric part
        axis = np.sqrt(np.clip((np.diag(R) + 1.0) / 2.0, 0.0, None))
        k = int(np.argmax(axis))
        axis = (R[:, k] + np.eye(3)[k]) / (2.0 * axis[k])
        return angle * axis / np.linalg.norm(axis)
    return angle * w / (2.0 * np.sin(angle))


def franka_twist(command: Command, ee_pose: np.ndarray, limits: FrankaLimits,
                 dt: float = 0.01, orientation_gain: float = 2.0,
                 correction: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The twist sent to the arm for a planner command, with the limits applied.

    Parameters
    ----------
    command : Command
    ee_pose : ndarray, shape (4, 4)
        Measured TCP pose [m].
    limits : FrankaLimits
    dt : float
        Control period [s]: a component that would leave the workspace within it is cut.
    orientation_gain : float
        Angular velocity per radian of orientation error [1/s].
    correction : ndarray, shape (3,), optional
        Added to the commanded velocity before the limits [m/s] (the backend's pull onto the
        commanded path).

    Returns
    -------
    linear, angular : ndarray, shape (3,)
        Base-frame velocity [m/s] and angular velocity [rad/s].
    """
    v = np.asarray(command.velocity, dtype=float)
    if correction is not None:
        v = v + np.asarray(correction, dtype=float)
    v, _ = franka_velocity(replace(command, twist=np.concatenate([np.zeros(3), v])),
                           limits.max_speed)
    p = np.asarray(ee_pose, dtype=float)[:3, 3]
    ahead = p + v * dt
    lo, hi = np.asarray(limits.workspace_min), np.asarray(limits.workspace_max)
    v[(ahead < lo) & (v < 0)] = 0.0
    v[(ahead > hi) & (v > 0)] = 0.0
    R_err = np.asarray(command.orientation, dtype=float) @ np.asarray(ee_pose)[:3, :3].T
    w = orientation_gain * _rotation_vector(R_err)
    rate = float(np.linalg.norm(w))
    if rate > limits.max_angular_speed:
        w *= limits.max_angular_speed / rate
    return v, w


class FrankaBackend:
    """Drive a Franka arm with franky, one planner period at a time on the arm's clock.

    Parameters
    ----------
    host : str
        The arm's FCI address (e.g. ``172.16.0.2``), or the address a
        :class:`~framefree.robot.franka_sim.ProtocolSimulator` reports.
    dt : float
        Period of the planner [s] (franky interpolates at 1 kHz).
    limits : FrankaLimits, optional
        What is enforced before anything is sent.
    hold : float
        How long one velocity command stays valid [s].
    grasp_force : float
        Force with which a closing gripper holds an object [N].
    open_width : float
        Finger opening an opening gripper moves to [m] (the planner's ``gripper_open_width``).
    realtime : bool, optional
        Whether libfranka insists on a real-time kernel. Default: yes for a real arm, no for a
        loopback address (``127.*``: the simulator on this machine).

    Attributes
    ----------
    trace : list of (float, ndarray (3,), ndarray (3,), float)
        Every period: backend time [s], measured TCP position [m], linear velocity sent [m/s],
        measured finger opening [m].
    replans : int
        How many motions were sent again after franky's motion planner failed.
    """

    def __init__(self, host: str, dt: float = 0.01, limits: FrankaLimits | None = None,
                 hold: float = 0.1, grasp_force: float = 20.0, open_width: float = 0.07,
                 realtime: bool | None = None) -> None:
        try:
            import franky
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self._fr = franky
        self.host = str(host)
        self.limits = FrankaLimits() if limits is None else limits
        if realtime is None:
            realtime = not self.host.startswith("127.")
        config = franky.RealtimeConfig.Enforce if realtime else franky.RealtimeConfig.Ignore
        try:
            self.robot = franky.Robot(self.host, realtime_config=config)
            self.gripper = franky.Gripper(self.host)
            self.robot.relative_dynamics_factor = self.limits.dynamics_factor
            self._width = float(self.gripper.width)
        except Exception as exc:  # franky raises its own network and control exceptions
            raise FramefreeError(f"Franka at {self.host}: cannot connect ({_one_line(exc)})"
                                 ) from None
        self.dt, self.hold, self.grasp_force = float(dt), float(hold), float(grasp_force)
        self.open_width = float(open_width)
        self.path_gain, self.max_correction = 2.0, 0.02
        self._p_ref: np.ndarray | None = None
        self._state: Any = None
        self._state_time = -1.0
        self._state_seen = time.perf_counter()
        self._sent_v: np.ndarray | None = None
        self._sent_at = -np.inf
        self._gripper_dir = 0
        self._closed = False
        self.replans = 0
        self.trace: list[tuple[float, np.ndarray, np.ndarray, float]] = []
        self._read_state()
        self._time0 = self._state_time
        self._next = 0.0

    # ----------------------------------------------------------------------------- state
    @property
    def time(self) -> float:
        """The arm's clock since the backend started [s] (real time on an arm; a simulator that
        runs slower than real time slows the session with it)."""
        return self._state_time - self._time0

    @property
    def gripper_width(self) -> float:
        """Finger opening [m] (measured at start, then the latest reference sent)."""
        return self._width

    def joint_positions(self) -> np.ndarray:
        """Measured joint angles [rad], shape (7,)."""
        return np.asarray(self._state.q, dtype=float)

    def measured_gripper_width(self) -> float:
        """Finger opening read from the gripper now [m]."""
        return float(self._call("read the gripper", lambda: self.gripper.width))

    def ee_pose(self) -> np.ndarray:
        """Measured TCP pose from the arm's state, shape (4, 4) [m]."""
        self._read_state()
        return np.asarray(self._state.O_T_EE.matrix, dtype=float)

    def _read_state(self) -> None:
        self._state = self._call("read the state", lambda: self.robot.state)
        now, t = time.perf_counter(), float(self._state.time.to_sec())
        if t != self._state_time:
            self._state_time, self._state_seen = t, now
        elif now - self._state_seen > self.limits.state_timeout:
            self._fail(f"no new state for {now - self._state_seen:.1f} s (connection lost?)")

    # ----------------------------------------------------------------------------- commands
    def check_limits(self, ee_pose: np.ndarray) -> None:
        """Stop the arm (one-line :class:`FramefreeError`) when a joint is within
        ``joint_margin`` of its limit or the TCP is outside the workspace box."""
        lim = self.limits
        q = self.joint_positions()
        near = np.flatnonzero((q < FR3_Q_MIN + lim.joint_margin) | (q > FR3_Q_MAX - lim.joint_margin))
        if near.size:
            k = int(near[0])
            self._fail(f"joint {k + 1} at {q[k]:.3f} rad, within {lim.joint_margin} rad of its "
                       f"limit [{FR3_Q_MIN[k]}, {FR3_Q_MAX[k]}]")
        p = np.asarray(ee_pose)[:3, 3]
        slack = lim.workspace_slack
        if np.any(p < np.asarray(lim.workspace_min) - slack) or np.any(
                p > np.asarray(lim.workspace_max) + slack):
            self._fail(f"TCP at {np.round(p, 3).tolist()} m, outside the workspace "
                       f"{list(lim.workspace_min)}..{list(lim.workspace_max)}")

    def apply(self, command: Command) -> None:
        """Check the limits, send what the period needs, then wait for the arm's next period."""
        fr = self._fr
        T = np.asarray(self._state.O_T_EE.matrix, dtype=float)
        self.check_limits(T)
        lin, ang = franka_twist(command, T, self.limits, self.dt,
                                correction=self._path_correction(command, T[:3, 3]))
        now = self.time
        moving = bool(np.any(lin) or np.any(np.abs(ang) > 1e-3))
        changed = self._sent_v is None or np.max(np.abs(lin - self._sent_v)) > 1e-4
        if moving and (changed or now - self._sent_at > 0.5 * self.hold):
            motion = fr.CartesianVelocityMotion(fr.Twist(lin.tolist(), ang.tolist()),
                                                duration=fr.Duration(int(1000 * self.hold)))
            self._move(motion)
            self._sent_v, self._sent_at = lin, now
        elif not moving and self._sent_v is not None and np.any(self._sent_v):
            self._sent_v = lin  # the last motion runs out within `hold`: the arm comes to rest
        self.trace.append((now, T[:3, 3].copy(), lin, self.measured_gripper_width()))
        self._gripper(command)
        self._next += self.dt
        while self.time < self._next - 1e-6:  # the next period on the arm's clock
            time.sleep(0.001)
            self._read_state()

    def _move(self, motion: Any) -> None:
        """Send one asynchronous motion; after a motion-planner failure, send it once more."""
        try:
            self.robot.move(motion, asynchronous=True)
            return
        except Exception as exc:  # franky reports the previous motion's failure here
            if "motion planner failed" not in str(exc).lower():
                self._fail(f"could not move: {_one_line(exc)}")
            first = _one_line(exc)
        self.replans += 1
        try:
            self.robot.move(motion, asynchronous=True)
        except Exception as exc:
            self._fail(f"could not move: {first}, and again: {_one_line(exc)}")

    def _path_correction(self, command: Command, p: np.ndarray) -> np.ndarray:
        """Velocity [m/s] that pulls the TCP onto the path the planner's velocities integrate to
        (``path_gain`` times the lag, at most ``max_correction``), so that a motion covers its
        whole travel; zero, and the path restarted at the TCP, while the planner is at rest."""
        v = np.asarray(command.velocity, dtype=float)
        if not np.any(v):
            self._p_ref = None
            return np.zeros(3)
        if self._p_ref is None:
            self._p_ref = p.copy()
        correction = self.path_gain * (self._p_ref - p)
        size = float(np.linalg.norm(correction))
        if size > self.max_correction:
            correction *= self.max_correction / size
        self._p_ref = self._p_ref + v * self.dt
        return correction

    def _gripper(self, command: Command) -> None:
        """One gripper command per change of the reference's direction."""
        direction = int(np.sign(command.gripper_velocity))
        if direction == 0 or direction == self._gripper_dir:
            return
        self._gripper_dir = direction
        speed = max(abs(float(command.gripper_velocity)), 0.01)
        g = self.gripper
        if direction > 0:
            self._call("open the gripper", lambda: g.move_async(self.open_width, speed))
            self._width = self.open_width
        else:
            self._call("close the gripper", lambda: g.grasp_async(
                0.0, speed, self.grasp_force, epsilon_inner=0.005, epsilon_outer=0.1))
            self._width = 0.0

    # ----------------------------------------------------------------------------- errors, end
    def _call(self, what: str, fn: Any) -> Any:
        try:
            return fn()
        except FramefreeError:
            raise
        except Exception as exc:  # franky's network, control and command exceptions
            self._fail(f"could not {what}: {_one_line(exc)}")

    def _fail(self, why: str) -> None:
        self.close()
        raise FramefreeError(f"Franka at {self.host}: {why}; arm stopped")

    def close(self) -> None:
        """Stop the arm; safe to call twice and after a failure. The gripper keeps what it holds
        (as the planner's stop does)."""
        if self._closed:
            return
        self._closed = True
        _bounded(self.robot.stop, STOP_TIMEOUT)


#: Longest wait [s] for franky's stop: on a connection that is gone, libfranka's stop can block
#: for ever (seen in the lost-connection test under load), and nothing more can be stopped then.
STOP_TIMEOUT = 2.0


def _bounded(fn: Any, timeout: float) -> None:
    """Call ``fn`` on a daemon thread and wait at most ``timeout`` seconds for it; its exceptions
    (a connection already gone) are ignored."""

    def run() -> None:
        try:
            fn()
        except Exception:  # the connection may be gone: then nothing more can be stopped
            pass

    worker = threading.Thread(target=run, name="franka-stop", daemon=True)
    worker.start()
    worker.join(timeout)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__
