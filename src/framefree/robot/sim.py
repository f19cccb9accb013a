"""MuJoCo simulation of the Panda under the joint impedance controller (needs the ``robot`` extra).

:class:`PandaSim` owns a MuJoCo model of :func:`~framefree.robot.panda_model.scene_xml` and a
:class:`~framefree.robot.control.Controller`; :meth:`PandaSim.step` applies one planner
:class:`~framefree.robot.planner.Command` for one control period (= one physics step).
"""

from __future__ import annotations

import os

import numpy as np

from ..errors import FramefreeError
from .control import HOME_Q, Controller, ControlParams
from .kinematics import PandaKinematics
from .panda_model import FINGER_RANGE, SceneSpec, scene_xml
from .planner import Command

# MuJoCo picks its OpenGL backend when it is first imported; without a display, EGL is the
# offscreen backend that works on this kind of machine (OSMesa is the software alternative).
if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
    os.environ["MUJOCO_GL"] = "egl"

__all__ = ["PandaSim", "SimulatorMissing", "import_mujoco"]


class SimulatorMissing(FramefreeError):
    """MuJoCo is not installed (``pip install 'framefree[robot]'``)."""


def import_mujoco():
    """Import :mod:`mujoco` or raise :class:`SimulatorMissing` with the install hint."""
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise SimulatorMissing(
            "the robot simulation needs MuJoCo: pip install 'framefree[robot]'"
        ) from exc
    return mujoco


class PandaSim:
    """A simulated Panda with hand, table and blocks, driven by planner commands.

    Parameters
    ----------
    scene : SceneSpec, optional
        Blocks and physics options.
    control : ControlParams, optional
        Controller gains and limits.
    q0 : ndarray, shape (7,), optional
        Initial joint angles [rad] (default :data:`~framefree.robot.control.HOME_Q`).
    gripper_width : float, optional
        Initial finger opening [m].

    Attributes
    ----------
    model, data : mujoco.MjModel, mujoco.MjData
        The MuJoCo model and state.
    controller : Controller
        Velocity mapping and joint impedance controller.
    dt : float
        Control period = physics time step [s].
    """

    def __init__(
        self,
        scene: SceneSpec | None = None,
        control: ControlParams | None = None,
        q0: np.ndarray | None = None,
        gripper_width: float = 0.07,
    ):
        mj = import_mujoco()
        self._mj = mj
        self.scene = SceneSpec() if scene is None else scene
        self.model = mj.MjModel.from_xml_string(scene_xml(self.scene))
        self.data = mj.MjData(self.model)
        self.kin = PandaKinematics()
        self.controller = Controller(control, self.kin)
        self.dt = float(self.model.opt.timestep)
        self._tcp_site = self.model.site("tcp").id
        self.block_names = [b.name for b in self.scene.blocks]
        self._block_qpos = [
            int(self.model.jnt_qposadr[self.model.body(n).jntadr[0]]) for n in self.block_names
        ]
        self.reset(HOME_Q if q0 is None else q0, gripper_width)

    def reset(self, q0: np.ndarray, gripper_width: float = 0.07) -> None:
        """Put the arm at ``q0`` at rest, the blocks at their initial poses, time to 0.

        Parameters
        ----------
        q0 : ndarray, shape (7,)
            Joint angles [rad].
        gripper_width : float, optional
            Finger opening [m].
        """
        mj = self._mj
        mj.mj_resetData(self.model, self.data)
        half = min(max(gripper_width / 2, 0.0), FINGER_RANGE)
        self.data.qpos[:7] = q0
        self.data.qpos[7:9] = half
        self.data.ctrl[7:9] = half
        mj.mj_forward(self.model, self.data)
        self.controller.reset(q0)

    # ------------------------------------------------------------------ state
    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self.data.time)

    @property
    def q(self) -> np.ndarray:
        """Measured joint angles, shape (7,) [rad]."""
        return self.data.qpos[:7].copy()

    @property
    def dq(self) -> np.ndarray:
        """Measured joint velocities, shape (7,) [rad/s]."""
        return self.data.qvel[:7].copy()

    @property
    def gripper_width(self) -> float:
        """Measured finger opening (sum of both fingers) [m]."""
        return float(self.data.qpos[7] + self.data.qpos[8])

    def ee_pose(self) -> np.ndarray:
        """Measured TCP pose from the robot model at the measured joints, shape (4, 4)."""
        return self.kin.tcp_pose(self.data.qpos[:7])

    def block_poses(self) -> np.ndarray:
        """Block poses, shape (n_blocks, 7): position [m] and quaternion (w, x, y, z)."""
        return np.array([self.data.qpos[a : a + 7] for a in self._block_qpos])

    # ------------------------------------------------------------------ stepping
    def step(self, command: Command) -> None:
        """Apply one planner command for one control period (one physics step).

        Parameters
        ----------
        command : Command
            Twist, orientation and gripper reference.
        """
        d = self.data
        tau = self.controller.step(
            command.twist, d.qpos[:7], d.qvel[:7], self.dt, command.orientation
        )
        d.ctrl[:7] = tau
        d.ctrl[7:9] = min(max(command.gripper_width / 2, 0.0), FINGER_RANGE)
        self._mj.mj_step(self.model, d)
