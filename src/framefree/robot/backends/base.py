"""The backend interface and the session that runs the planner against any backend.

A backend is what the planner's :class:`~framefree.robot.planner.Command` goes to, one control
period at a time: it reports the measured TCP pose and executes the command. The planner and its
rules are the same for the simulation, a dry run and a real arm.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from ...online.events import Event
from ..planner import Command, Decision, Planner, PlannerParams

__all__ = ["RobotBackend", "RobotSession"]


class RobotBackend(Protocol):
    """What the session needs of a robot.

    Attributes
    ----------
    dt : float
        Control period [s].
    time : float
        The backend's clock [s] (0 at start).
    """

    dt: float

    @property
    def time(self) -> float: ...

    @property
    def gripper_width(self) -> float: ...

    def ee_pose(self) -> np.ndarray:
        """Measured TCP pose in the base frame, shape (4, 4)."""
        ...

    def apply(self, command: Command) -> None:
        """Execute one control period of ``command``."""
        ...

    def close(self) -> None:
        """Bring the robot to rest and release it."""
        ...


class RobotSession:
    """Planner + backend: events in, commands out, on the backend's clock.

    Parameters
    ----------
    backend : RobotBackend
    planner : PlannerParams, optional
    time_offset : float
        An event stamped ``t`` acts at backend time ``t - time_offset``.
    on_event : callable, optional
        Called with every :class:`Decision`.
    """

    def __init__(self, backend: RobotBackend, planner: PlannerParams | None = None,
                 time_offset: float = 0.0,
                 on_event: Callable[[Decision], None] | None = None) -> None:
        self.backend = backend
        self.planner = Planner(planner, gripper_width=backend.gripper_width)
        self.time_offset = float(time_offset)
        self.on_event = on_event
        self._pending: list[Event] = []
        self.command: Command | None = None
        self.halted = False

    @property
    def time(self) -> float:
        """Backend time [s]."""
        return self.backend.time

    def handle(self, event: Event) -> None:
        """Queue an event; it acts at the first control period at or after its time."""
        self._pending.append(event)
        self._pending.sort(key=lambda e: (e.time, not e.is_stop))

    def step(self) -> None:
        """One control period: due events -> planner -> backend."""
        due = []
        while self._pending and self._pending[0].time - self.time_offset <= self.time + 1e-12:
            due.append(self._pending.pop(0))
        for decision in self.planner.handle_many(due):
            if self.on_event is not None:
                self.on_event(decision)
        self.command = self.planner.step(self.backend.dt, self.backend.ee_pose())
        self.backend.apply(self.command)

    def advance_to(self, t: float) -> None:
        """Run control periods until backend time ``t`` [s] (none after :meth:`halt`)."""
        while not self.halted and self.time < t - 0.5 * self.backend.dt:
            self.step()

    def halt(self) -> None:
        """Stop at once (Ctrl-C): the backend brings the robot to rest and is released; no
        further control period runs."""
        self.halted = True
        self.backend.close()
