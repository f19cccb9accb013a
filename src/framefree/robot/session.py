"""Planner + controller + simulation in one object: what the live recognizer (or a script) drives.

:class:`RobotSim` is the robot half of ``framefree live --robot sim`` and of the demo: feed it
recognition events with :meth:`RobotSim.handle` (or a whole timed list with
:func:`run_events`), advance simulated time with :meth:`RobotSim.advance_to`, read the log.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from ..online.events import Event
from .control import ControlParams
from .panda_model import SceneSpec
from .planner import Command, Decision, Planner, PlannerParams
from .sim import PandaSim

__all__ = ["RobotSim", "SessionLog", "run_events"]


@dataclass(frozen=True)
class SessionLog:
    """Sampled record of a simulated session (``n`` samples at ``log_rate``).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Simulated time [s].
    q, q_ref : ndarray, shape (n, 7)
        Measured joint angles and joint reference [rad].
    dq, dq_ref : ndarray, shape (n, 7)
        Measured joint velocities and reference velocities [rad/s].
    tau : ndarray, shape (n, 7)
        Commanded joint torques [N m].
    ee : ndarray, shape (n, 3)
        Measured TCP position [m].
    ee_rot : ndarray, shape (n, 3, 3)
        Measured TCP orientation.
    v_cmd : ndarray, shape (n, 3)
        Planner's commanded TCP velocity [m/s].
    gripper_ref, gripper : ndarray, shape (n,)
        Finger opening reference and measured opening [m].
    blocks : ndarray, shape (n, n_blocks, 7)
        Block poses (position [m], quaternion w, x, y, z).
    qpos : ndarray, shape (n, nq)
        Full MuJoCo configuration (for rendering).
    state : ndarray of str, shape (n,)
        Planner state.
    block_names : tuple of str
        Block names, in the order of ``blocks``.
    decisions : tuple of Decision
        Every event with the planner's reaction.
    """

    t: np.ndarray
    q: np.ndarray
    q_ref: np.ndarray
    dq: np.ndarray
    dq_ref: np.ndarray
    tau: np.ndarray
    ee: np.ndarray
    ee_rot: np.ndarray
    v_cmd: np.ndarray
    gripper_ref: np.ndarray
    gripper: np.ndarray
    blocks: np.ndarray
    qpos: np.ndarray
    state: np.ndarray
    block_names: tuple[str, ...]
    decisions: tuple[Decision, ...]

    def block(self, name: str) -> np.ndarray:
        """Poses of one block over time, shape (n, 7)."""
        return self.blocks[:, self.block_names.index(name)]


class RobotSim:
    """The robot side of a live session: planner FSM, controller and MuJoCo Panda.

    Parameters
    ----------
    planner : PlannerParams, optional
        Planner speeds, limits and mapping.
    control : ControlParams, optional
        Controller gains and limits.
    scene : SceneSpec, optional
        Blocks on the table.
    q0 : ndarray, shape (7,), optional
        Initial joint angles [rad] (default: home).
    log_rate : float, optional
        Logging rate [Hz].
    on_event : callable, optional
        Called with every :class:`Decision` (e.g. to print events as they happen).

    Notes
    -----
    Event times and simulated time share one clock, starting at 0 when the object is created
    (``time_offset`` shifts event times: an event stamped ``t`` acts at sim time
    ``t - time_offset``). Events must be handed over in time order (late events act at once).
    """

    def __init__(
        self,
        planner: PlannerParams | None = None,
        control: ControlParams | None = None,
        scene: SceneSpec | None = None,
        q0: np.ndarray | None = None,
        log_rate: float = 50.0,
        on_event: Callable[[Decision], None] | None = None,
        time_offset: float = 0.0,
    ):
        self.sim = PandaSim(scene, control, q0)
        self.planner = Planner(planner, gripper_width=self.sim.gripper_width)
        self.log_rate = float(log_rate)
        self.on_event = on_event
        self.time_offset = float(time_offset)
        self._pending: list[Event] = []
        self._rows: dict[str, list] = {k: [] for k in SessionLog.__dataclass_fields__}
        self._next_log = 0.0
        self.command: Command | None = None
        self._log()

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self.sim.time

    def handle(self, event: Event) -> None:
        """Queue a recognition event; it acts at the first control period at or after its time."""
        self._pending.append(event)
        self._pending.sort(key=lambda e: (e.time, not e.is_stop))

    def step(self) -> None:
        """One control period: due events → planner → controller → physics."""
        sim = self.sim
        due = []
        while self._pending and self._pending[0].time - self.time_offset <= sim.time + 1e-12:
            due.append(self._pending.pop(0))
        for decision in self.planner.handle_many(due):
            if self.on_event is not None:
                self.on_event(decision)
        self.command = self.planner.step(sim.dt, sim.ee_pose())
        sim.step(self.command)
        if sim.time + 1e-12 >= self._next_log:
            self._log()

    def advance_to(self, t: float, progress: Callable[[float], None] | None = None) -> None:
        """Run control periods until simulated time ``t`` [s].

        Parameters
        ----------
        t : float
            Target simulated time [s].
        progress : callable, optional
            Called with the simulated time about every simulated second.
        """
        next_report = np.floor(self.time) + 1.0
        while self.time < t - 0.5 * self.sim.dt:
            self.step()
            if progress is not None and self.time >= next_report:
                progress(self.time)
                next_report += 1.0

    def _log(self) -> None:
        sim, r = self.sim, self._rows
        T = sim.ee_pose()
        c = sim.controller
        r["t"].append(sim.time)
        r["q"].append(sim.q)
        r["q_ref"].append(c.q_ref.copy())
        r["dq"].append(sim.dq)
        r["dq_ref"].append(c.dq_ref.copy())
        r["tau"].append(sim.data.ctrl[:7].copy())
        r["ee"].append(T[:3, 3].copy())
        r["ee_rot"].append(T[:3, :3].copy())
        r["v_cmd"].append(self.planner.velocity.copy())
        r["gripper_ref"].append(self.planner.gripper_width)
        r["gripper"].append(sim.gripper_width)
        r["blocks"].append(sim.block_poses())
        r["qpos"].append(sim.data.qpos.copy())
        r["state"].append(self.planner.state)
        self._next_log += 1.0 / self.log_rate

    def log(self) -> SessionLog:
        """The record so far."""
        r = self._rows
        arrays = {k: np.array(v) for k, v in r.items() if k not in ("block_names", "decisions")}
        n_blocks = len(self.sim.block_names)
        if arrays["blocks"].size == 0:
            arrays["blocks"] = np.zeros((len(arrays["t"]), n_blocks, 7))
        return SessionLog(
            **arrays,
            block_names=tuple(self.sim.block_names),
            decisions=tuple(self.planner.decisions),
        )


def run_events(
    events: Iterable[Event],
    duration: float | None = None,
    *,
    settle: float = 3.0,
    progress: Callable[[float], None] | None = None,
    **kwargs,
) -> SessionLog:
    """Run a timed list of events through planner, controller and simulation.

    Parameters
    ----------
    events : iterable of Event
        Events (their ``time`` is simulated time [s], minus ``time_offset`` if given).
    duration : float, optional
        Simulated duration [s] (default: last event + ``settle``).
    settle : float, optional
        Extra time after the last event when ``duration`` is not given [s].
    progress : callable, optional
        Called with the simulated time about every simulated second.
    **kwargs
        Passed to :class:`RobotSim` (``planner``, ``control``, ``scene``, ``q0``, ``log_rate``,
        ``on_event``, ``time_offset``).

    Returns
    -------
    SessionLog
    """
    events = list(events)
    robot = RobotSim(**kwargs)
    for e in events:
        robot.handle(e)
    if duration is None:
        last = max((e.time for e in events), default=0.0) - robot.time_offset
        duration = last + settle
    robot.advance_to(duration, progress)
    return robot.log()
