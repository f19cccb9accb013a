"""The demo's person and recognizer driving a Franka arm through franky, checked against the plan.

:func:`run_franka_session` is the demo of :mod:`framefree.robot.demo` with the MuJoCo Panda
replaced by :class:`~framefree.robot.backends.FrankaBackend`: by default against the FR3 of
:class:`~framefree.robot.franka_sim.ProtocolSimulator` (started and stopped here, on loopback),
or against an arm at a given host. The person performs the commands live, the recognizer turns
the stream into events, the planner into velocity commands, franky into the libfranka protocol.
The protocol simulator has no table and no blocks: the run checks what the arm did against what
the planner asked (:class:`FrankaRun`), not a stacked block.

The reference for "what the planner asked" is :func:`ideal_path`: the same events, at the same
times, through the same planner driving an arm that moves exactly as commanded
(:class:`~framefree.robot.backends.DryRunBackend`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..online.events import Event
from .backends import DryRunBackend, FrankaBackend, RobotSession
from .backends.franka import FrankaLimits
from .closed_loop import PersonPolicy, run_commands
from .demo import build_loop
from .franka_sim import ProtocolSimulator
from .planner import Decision, PlannerParams
from .scenario import STACKING_PLANNER, STACKING_START

__all__ = ["FrankaRun", "ideal_path", "run_franka_session"]


@dataclass
class FrankaRun:
    """What a session on a Franka arm did, against the plan.

    Attributes
    ----------
    host : str
        The arm's address.
    decisions : list of Decision
        Every event the planner handled, with its reaction.
    accepted : list of str
        Labels of the events that changed the plan, in order.
    command_log : list of dict
        The person's commands (onset, gesture, attempts, obeyed).
    end_position, planned_end : ndarray, shape (3,)
        Measured TCP position at the end, and where the ideal arm ends [m].
    path_error : float
        Largest distance between the measured TCP and the ideal arm's over the session [m].
    gripper_widths : list of (str, float)
        Per accepted gripper event: its label and the measured finger opening 2 s later [m].
    robot_seconds, wall_seconds : float
        Session length on the arm's clock and on the wall clock [s].
    replans : int
        Motions sent again after franky's motion planner failed
        (:attr:`~framefree.robot.backends.FrankaBackend.replans`).
    """

    host: str
    decisions: list[Decision]
    accepted: list[str]
    command_log: list[dict[str, Any]]
    end_position: np.ndarray
    planned_end: np.ndarray
    path_error: float
    gripper_widths: list[tuple[str, float]]
    robot_seconds: float
    wall_seconds: float
    replans: int = 0

    @property
    def end_error(self) -> float:
        """Distance between the measured and the planned end position [m]."""
        return float(np.linalg.norm(self.end_position - self.planned_end))


def ideal_path(events: Sequence[Event], start_pose: np.ndarray, periods: int, dt: float,
               planner: PlannerParams = STACKING_PLANNER, gripper_width: float = 0.07,
               time_offset: float = 0.0) -> np.ndarray:
    """TCP positions of an arm that moves exactly as the planner commands, one per period.

    Parameters
    ----------
    events : sequence of Event
        The events, stamped on the session's clock [s].
    start_pose : ndarray, shape (4, 4)
        Initial TCP pose [m].
    periods : int
        Number of control periods.
    dt : float
        Control period [s].
    planner : PlannerParams
    gripper_width : float
        Initial finger opening [m].
    time_offset : float
        An event stamped ``t`` acts at session time ``t - time_offset`` [s].

    Returns
    -------
    ndarray, shape (periods, 3)
        TCP position at the start of every period [m].
    """
    session = RobotSession(DryRunBackend(start_pose, gripper_width, dt=dt), planner,
                           time_offset=time_offset)
    for ev in events:
        session.handle(ev)
    out = np.empty((periods, 3))
    for k in range(periods):
        out[k] = session.backend.ee_pose()[:3, 3]
        session.step()
    return out


def run_franka_session(recognizer: Any, commands: Sequence[tuple[float, str]], seed: int = 0,
                       host: str | None = None, limits: FrankaLimits | None = None,
                       echo: Callable[[str], None] | None = None) -> FrankaRun:
    """A demo person gives ``commands``; the events drive a Franka arm through franky.

    Parameters
    ----------
    recognizer : Recognizer or PaperRecognizer
        Built and warmed up (:func:`framefree.robot.demo.build_recognizer`).
    commands : sequence of (float, str)
        (onset [s], gesture), e.g. :func:`framefree.robot.demo.demo_commands`.
    seed : int
        Demo seed (the person and their session).
    host : str, optional
        A real arm's FCI address; default: a protocol simulator started here at Franka's ready
        pose and stopped at the end.
    limits : FrankaLimits, optional
    echo : callable, optional
        Where the robot's reactions are reported.

    Returns
    -------
    FrankaRun
    """
    wall0 = time.perf_counter()
    sim = ProtocolSimulator(q0=STACKING_START) if host is None else None
    try:
        address = sim.start() if sim is not None else str(host)
        backend = FrankaBackend(address, limits=limits,
                                open_width=STACKING_PLANNER.gripper_open_width)
        try:
            start = backend.ee_pose()
            session = RobotSession(backend, STACKING_PLANNER)
            loop = build_loop(recognizer, seed, echo, robot=session)
            run_commands(loop, commands, PersonPolicy(), progress=False)
            end = backend.ee_pose()[:3, 3]
        finally:
            backend.close()
    finally:
        if sim is not None:
            sim.stop()
    decisions = list(session.planner.decisions)
    trace = backend.trace
    ideal = ideal_path([d.event for d in decisions], start, len(trace), backend.dt,
                       gripper_width=float(trace[0][3]))
    measured = np.array([row[1] for row in trace])
    times = np.array([row[0] for row in trace])
    widths = []
    for d in decisions:
        if d.accepted and d.event.label in ("open_gripper", "close_gripper"):
            k = min(int(np.searchsorted(times, d.time + 2.0)), len(trace) - 1)
            widths.append((d.event.label, float(trace[k][3])))
    return FrankaRun(
        host=address, decisions=decisions, accepted=[d.event.label for d in decisions if d.accepted],
        command_log=list(loop.command_log), end_position=end, planned_end=ideal[-1],
        path_error=float(np.max(np.linalg.norm(measured - ideal, axis=1))),
        gripper_widths=widths, robot_seconds=float(backend.time),
        wall_seconds=time.perf_counter() - wall0, replans=backend.replans)
