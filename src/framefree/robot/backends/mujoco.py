"""The MuJoCo Panda (:class:`framefree.robot.sim.PandaSim`) as a backend."""

from __future__ import annotations

import numpy as np

from ..planner import Command

__all__ = ["MujocoBackend"]


class MujocoBackend:
    """Simulated Panda: one physics step per control period.

    Parameters are those of :class:`framefree.robot.sim.PandaSim` (scene, control, q0).
    """

    def __init__(self, scene=None, control=None, q0: np.ndarray | None = None) -> None:
        from ..sim import PandaSim

        self.sim = PandaSim(scene, control, q0)
        self.dt = float(self.sim.dt)

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self.sim.time)

    @property
    def gripper_width(self) -> float:
        """Measured finger opening [m]."""
        return float(self.sim.gripper_width)

    def ee_pose(self) -> np.ndarray:
        """Measured TCP pose, shape (4, 4)."""
        return self.sim.ee_pose()

    def apply(self, command: Command) -> None:
        """One physics step under ``command``."""
        self.sim.step(command)

    def close(self) -> None:
        """Nothing to release."""
