"""The paper's pick-and-place and stacking task (its Section V, Table II) as a reproducible scenario.

See docs/robot.md, *The stacking scenario*.

Scene (robot base frame, table top z = 0, blocks are 4 cm cubes of 50 g):

* ``block_a`` (red) on top of ``block_b`` (green): a two-block tower at (0.50, +0.15) m, centres
  at z = 0.06 and 0.02 m;
* ``block_c`` (blue) at (0.50, −0.20, 0.02) m, not touched (a distractor);
* the arm starts in Franka's *ready* configuration (TCP at (0.307, 0, 0.487) m).

Planner (:data:`STACKING_PLANNER`): home TCP at (0.50, 0, 0.20) m pointing down; go_left/right
move 0.15 m along ±y, go_up 0.10 m, go_down 0.14 m, all at 0.06 m/s with 0.25 m/s²; the
workspace floor is z = 0.02 m (the TCP never goes below the centre of a block on the table) and
go_down ends on contact (measured TCP 8 mm behind the commanded one). A motion command equal to
the last accepted one within 8 s (``repeat_window``) is a repeat: the paper's user re-performed
go_right and go_down when the robot seemed not to react, and a recognizer that caught the first
attempt must not move the robot twice.

Why these distances make the paper's gesture timeline stack a block: the timeline (detected
events only) moves the TCP between y = 0 and y = +0.15 and performs four pick/place descents.
With fixed travels the heights a descent reaches form an arithmetic sequence (each up/down pair
changes the height by up − down = −0.04 m = −one block), while the task needs the heights top of
the tower, table, table, on top of a block. The floor and the contact stop make it work:

====== ================= ===================================== =============================
 time   event             TCP afterwards (y, z) [m]             effect
====== ================= ===================================== =============================
 0:31   go_home           (0, 0.20)                             from the ready pose
 0:44   go_left           (0.15, 0.20)                          above the tower
 0:52   go_down           (0.15, 0.06)                          fingers around block A
 1:14   close_gripper                                           A grasped
 1:20   go_up             (0.15, 0.16)
 1:34   go_right          (0, 0.16)                             (1:32 missed in the paper; if
                                                                both are detected the second
                                                                is a repeat and is ignored)
 1:38   go_down           (0, 0.02)                             A set on the table (floor)
 1:47   open_gripper                                            A released
 1:53   go_up             (0, 0.12)
 1:58   go_left           (0.15, 0.12)                          above block B
 2:06   stop              —                                     paper: a too-fast go_down read
                                                                as stop; the arm is at rest
 2:11   go_down           (0.15, 0.02)                          floor: fingers around B
 2:19   close_gripper                                           B grasped
 2:26   go_up             (0.15, 0.12)
 2:33   go_right          (0, 0.12)                             (2:31 missed in the paper)
 2:42   go_down           (0, ≈0.06)                            contact: B lands on A
 2:48   open_gripper                                            B released: **B stacked on A**
 2:58   go_up             (0, ≈0.16)
 3:05   go_home           (0, 0.20)
====== ================= ===================================== =============================

Every motion lasts at most 2.8 s, shorter than every gap between consecutive events of the
timeline (the shortest is 4 s), and a repeated go_right within 2.7 s of the first is ignored.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..online.events import STOP, Event
from .kinematics import Q_READY
from .panda_model import Block, SceneSpec
from .planner import PlannerParams

__all__ = [
    "PAPER_TIMELINE",
    "STACKING_PLANNER",
    "STACKING_SCENE",
    "STACKING_START",
    "StackResult",
    "evaluate_stacking",
    "paper_events",
]

#: The 21 gestures of the paper's demonstration (its Table II): (time [s], performed gesture,
#: detected as).
#: "detected as" is the gesture itself, ``None`` (missed) or ``"stop"``.
PAPER_TIMELINE: tuple[tuple[float, str, str | None], ...] = (
    (31.0, "go_home", "go_home"),
    (44.0, "go_left", "go_left"),
    (52.0, "go_down", "go_down"),
    (74.0, "close_gripper", "close_gripper"),
    (80.0, "go_up", "go_up"),
    (92.0, "go_right", None),
    (94.0, "go_right", "go_right"),
    (98.0, "go_down", "go_down"),
    (107.0, "open_gripper", "open_gripper"),
    (113.0, "go_up", "go_up"),
    (118.0, "go_left", "go_left"),
    (126.0, "go_down", STOP),
    (131.0, "go_down", "go_down"),
    (139.0, "close_gripper", "close_gripper"),
    (146.0, "go_up", "go_up"),
    (151.0, "go_right", None),
    (153.0, "go_right", "go_right"),
    (162.0, "go_down", "go_down"),
    (168.0, "open_gripper", "open_gripper"),
    (178.0, "go_up", "go_up"),
    (185.0, "go_home", "go_home"),
)

#: Blocks of the stacking task.
STACKING_SCENE = SceneSpec(
    blocks=(
        Block("block_a", (0.5, 0.15, 0.06), rgba=(0.85, 0.2, 0.2, 1.0)),
        Block("block_b", (0.5, 0.15, 0.02), rgba=(0.2, 0.6, 0.25, 1.0)),
        Block("block_c", (0.5, -0.2, 0.02), rgba=(0.2, 0.35, 0.85, 1.0)),
    )
)
#: Planner parameters of the stacking task.
STACKING_PLANNER = PlannerParams(workspace_min=(0.25, -0.45, 0.02), repeat_window=8.0)
#: Initial joint angles [rad] (Franka's ready pose).
STACKING_START = Q_READY.copy()


def paper_events(
    start: float = 1.0, detected: bool = True, missed_as_performed: bool = False
) -> list[Event]:
    """The paper's timeline as events, shifted so that the first happens at ``start``.

    Parameters
    ----------
    start : float, optional
        Simulated time of the first gesture (0:31 in the paper) [s].
    detected : bool, optional
        True: the events the paper's recognizer emitted (18 gestures and 1 stop); False: the
        gestures the person performed (21, no stop).
    missed_as_performed : bool, optional
        With ``detected``, also emit the two missed go_right gestures (a better recognizer).

    Returns
    -------
    list of Event
        Time-ordered events (dissimilarity 0, model -1).
    """
    t0 = PAPER_TIMELINE[0][0]
    out = []
    for t, performed, seen in PAPER_TIMELINE:
        label = seen if detected else performed
        if detected and seen is None and missed_as_performed:
            label = performed
        if label is None:
            continue
        out.append(Event(label, t - t0 + start, 0.0 if label != STOP else -1.0, -1))
    return out


@dataclass(frozen=True)
class StackResult:
    """Outcome of the stacking task.

    Attributes
    ----------
    success : bool
        ``top`` rests on ``bottom`` (centres within ``xy_tolerance`` horizontally, height
        difference one block ± ``z_tolerance``), both upright and at rest.
    top_position, bottom_position : ndarray, shape (3,)
        Final block centres [m].
    horizontal_offset : float
        Horizontal distance between the two centres [m].
    height_difference : float
        ``top z − bottom z`` [m].
    tilt : float
        Largest tilt of the two blocks from upright [rad].
    moved : dict of str to float
        Displacement of every block from its start [m].
    """

    success: bool
    top_position: np.ndarray
    bottom_position: np.ndarray
    horizontal_offset: float
    height_difference: float
    tilt: float
    moved: dict[str, float]


def _tilt(quat: np.ndarray) -> float:
    w, x, y, z = quat
    # angle between the block's z axis and the world z axis (cubes: any face up is upright)
    R = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return float(np.arccos(np.clip(np.max(np.abs(R[2])), -1.0, 1.0)))


def evaluate_stacking(
    log,
    top: str = "block_b",
    bottom: str = "block_a",
    block_height: float = 0.04,
    xy_tolerance: float = 0.01,
    z_tolerance: float = 0.005,
    tilt_tolerance: float = 0.1,
) -> StackResult:
    """Did ``top`` end up stacked on ``bottom``?

    Parameters
    ----------
    log : SessionLog
        A simulated session.
    top, bottom : str
        Block names.
    block_height : float, optional
        Height of the bottom block [m].
    xy_tolerance, z_tolerance : float, optional
        Tolerances on the horizontal offset and on the height difference [m].
    tilt_tolerance : float, optional
        Largest accepted tilt from upright [rad].

    Returns
    -------
    StackResult
    """
    final = log.blocks[-1]
    first = log.blocks[0]
    i_top = log.block_names.index(top)
    i_bot = log.block_names.index(bottom)
    p_top = final[i_top, :3]
    p_bot = final[i_bot, :3]
    offset = float(np.linalg.norm(p_top[:2] - p_bot[:2]))
    dz = float(p_top[2] - p_bot[2])
    tilt = max(_tilt(final[i_top, 3:]), _tilt(final[i_bot, 3:]))
    moved = {
        n: float(np.linalg.norm(final[i, :3] - first[i, :3])) for i, n in enumerate(log.block_names)
    }
    success = (
        offset < xy_tolerance
        and abs(dz - block_height) < z_tolerance
        and tilt < tilt_tolerance
        and p_bot[2] < block_height / 2 + z_tolerance
    )
    return StackResult(success, p_top.copy(), p_bot.copy(), offset, dz, tilt, moved)
