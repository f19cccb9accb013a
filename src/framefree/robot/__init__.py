"""The gesture-commanded robot: planner FSM, Panda kinematics and control, MuJoCo simulation.

Pure-numpy parts (importable without MuJoCo): :mod:`.planner`, :mod:`.kinematics`,
:mod:`.control`, :mod:`.panda_model` (MJCF text). The simulation (:mod:`.sim`, :mod:`.session`,
:mod:`.render`, :mod:`.scenario` evaluation) needs the ``robot`` extra (``mujoco``).
See ``docs/robot.md``.
"""

from .control import HOME_Q, Controller, ControlParams
from .kinematics import PandaKinematics
from .planner import Command, Decision, Planner, PlannerParams

__all__ = [
    "HOME_Q",
    "Command",
    "ControlParams",
    "Controller",
    "Decision",
    "PandaKinematics",
    "Planner",
    "PlannerParams",
]
