"""Robot backends behind the one planner: MuJoCo simulation, dry run, a real Franka (franky)."""

from .base import RobotBackend, RobotSession
from .dry_run import DryRunBackend
from .franka import FrankaBackend, franka_velocity
from .mujoco import MujocoBackend

__all__ = ["DryRunBackend", "FrankaBackend", "MujocoBackend", "RobotBackend", "RobotSession",
           "franka_velocity"]
