"""A real Franka arm (Panda or FR3) through franky (``pip install 'framefree[franka]'``).

Command mapping (tested without an arm, :func:`franka_velocity`): the planner's TCP velocity
becomes a franky ``CartesianVelocityMotion`` of a ``Twist`` (linear = the commanded velocity in
the base frame [m/s], clamped to ``max_speed``; angular = 0, the arm holds its orientation
itself), sent asynchronously whenever it changes and valid for ``hold`` seconds, so a silent
framefree stops the arm; the finger reference goes to the gripper (``Gripper.move_async``) when it
changes by more than 1 mm. franky's own 1 kHz loop, with the arm's limits scaled by
``dynamics_factor``, does the rest.
"""

from __future__ import annotations

import time

import numpy as np

from ...errors import FramefreeError
from ..planner import Command

__all__ = ["FrankaBackend", "franka_velocity"]

_MISSING = "the Franka backend needs franky: pip install 'framefree[franka]' (and a Franka arm with FCI)"


def franka_velocity(command: Command, max_speed: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """The twist sent to the arm for a planner command.

    Parameters
    ----------
    command : Command
    max_speed : float
        Largest linear speed sent [m/s]; a faster command is scaled down along its direction.

    Returns
    -------
    linear, angular : ndarray, shape (3,)
        Base-frame velocity [m/s] and angular velocity [rad/s] (always zero).
    """
    v = np.asarray(command.velocity, dtype=float).copy()
    if not np.all(np.isfinite(v)):
        raise FramefreeError(f"planner command with a non-finite velocity {v.tolist()}: not sent")
    speed = float(np.linalg.norm(v))
    if speed > max_speed:
        v *= max_speed / speed
    return v, np.zeros(3)


class FrankaBackend:
    """Drive a Franka arm with franky.

    Parameters
    ----------
    host : str
        The arm's FCI address (e.g. ``172.16.0.2``; ``127.0.0.1`` for a local simulation server).
    dt : float
        Period of the planner [s] (franky interpolates at 1 kHz).
    max_speed : float
        Clamp on the commanded linear speed [m/s].
    dynamics_factor : float
        franky's relative dynamics factor (fraction of the arm's velocity, acceleration and jerk
        limits).
    hold : float
        How long one velocity command stays valid [s].
    """

    def __init__(self, host: str, dt: float = 0.01, max_speed: float = 0.25,
                 dynamics_factor: float = 0.1, hold: float = 0.1) -> None:
        try:
            import franky
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self._fr = franky
        try:
            self.robot = franky.Robot(host)
            self.gripper = franky.Gripper(host)
        except Exception as exc:  # franky raises its own network/control exceptions
            raise FramefreeError(f"Franka at {host}: cannot connect ({exc})") from None
        self.robot.relative_dynamics_factor = dynamics_factor
        self.dt, self.max_speed, self.hold = float(dt), float(max_speed), float(hold)
        self._t0 = time.perf_counter()
        self._next = self._t0
        self._sent_v: np.ndarray | None = None
        self._sent_width = float(self.gripper.width)

    @property
    def time(self) -> float:
        """Wall-clock time since the backend started [s]."""
        return time.perf_counter() - self._t0

    @property
    def gripper_width(self) -> float:
        """Measured finger opening [m]."""
        return float(self.gripper.width)

    def ee_pose(self) -> np.ndarray:
        """Measured TCP pose from the arm's state, shape (4, 4)."""
        pose = self.robot.current_cartesian_state.pose.end_effector_pose
        return np.asarray(pose.matrix, dtype=float)

    def apply(self, command: Command) -> None:
        """Send what changed, then wait for the next period (real time)."""
        fr = self._fr
        lin, ang = franka_velocity(command, self.max_speed)
        if self._sent_v is None or np.max(np.abs(lin - self._sent_v)) > 1e-4 or not np.any(lin):
            motion = fr.CartesianVelocityMotion(
                fr.Twist(lin.tolist(), ang.tolist()), duration=fr.Duration(int(1000 * self.hold)))
            self.robot.move(motion, asynchronous=True)
            self._sent_v = lin
        if abs(command.gripper_width - self._sent_width) > 1e-3:
            self.gripper.move_async(float(command.gripper_width), 0.05)
            self._sent_width = float(command.gripper_width)
        self._next += self.dt
        time.sleep(max(0.0, self._next - time.perf_counter()))

    def close(self) -> None:
        """Stop the arm."""
        self.robot.stop()
