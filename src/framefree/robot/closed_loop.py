"""A simulated person commanding the simulated robot by hand gestures, through a live recognizer.

The person acts (:class:`~framefree.replica.LivePerson`), everything they did is streamed sample by
sample to the recognizer, every event goes to the robot (:class:`~framefree.robot.session.RobotSim`,
the stacking scene of ``docs/robot.md``), and the robot simulation advances to the person's time.
The person watches the robot and repeats a command it did not obey (:class:`PersonPolicy`).

>>> loop = ClosedLoop(recognizer, LivePerson(0))                  # doctest: +SKIP
>>> loop.command(6.0, "go_home", PersonPolicy())                  # doctest: +SKIP
True
>>> log = loop.finish()                                            # doctest: +SKIP
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["ClosedLoop", "PersonPolicy", "run_commands"]


@dataclass(frozen=True)
class PersonPolicy:
    """How the simulated person reacts to the robot.

    Attributes
    ----------
    watch : float
        After a gesture the person holds still this long [s] and watches whether the robot obeys
        (the recognizer decides within about 0.5 s of a gesture's end).
    max_repeats : int
        How often an ignored command is performed again (the paper's user repeated once).
    """

    watch: float = 1.5
    max_repeats: int = 2


def _say(echo: Callable[[str], None] | None, text: str) -> None:
    if echo is not None:
        echo(text)


class ClosedLoop:
    """A person, the recognizer and the robot wired together, advancing as the person acts.

    Parameters
    ----------
    recognizer : Recognizer or PaperRecognizer
        Reset on construction (wrapped in a
        :class:`~framefree.online.evaluation.TracingRecognizer` that keeps events and traces).
    person : LivePerson
        The simulated person; nothing is streamed until they have acted.
    echo : callable, optional
        Where the robot's reaction to every event is reported (``None``: silent).
    robot : RobotSim or RobotSession, optional
        The robot (default: a :class:`~framefree.robot.session.RobotSim` of the stacking scene);
        a :class:`~framefree.robot.backends.RobotSession` drives any backend, e.g. a Franka arm.

    Attributes
    ----------
    tracer : TracingRecognizer
    robot : RobotSim or RobotSession
        The planner and the robot it drives.
    reactions : dict of int to str
        The robot's verdict on each event, keyed by ``id(event)``.
    command_log : list of dict
        Per command given through :meth:`command`: onset [s], gesture, attempts, obeyed.
    timing : dict
        Wall time [s] spent in recognition and in the robot simulation, and samples streamed.
    """

    def __init__(self, recognizer: Any, person: Any, echo: Callable[[str], None] | None = None,
                 robot: Any = None):
        from ..online.evaluation import TracingRecognizer

        self.person = person
        self.echo = echo
        self.tracer = TracingRecognizer(recognizer)
        self.reactions: dict[int, str] = {}
        if robot is None:
            from .scenario import STACKING_PLANNER, STACKING_SCENE, STACKING_START
            from .session import RobotSim

            robot = RobotSim(planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START)
        robot.on_event = self._on_decision
        self.robot = robot
        self.command_log: list[dict[str, Any]] = []
        self.timing: dict[str, float] = {"recognition": 0.0, "robot": 0.0, "samples": 0}

    def _on_decision(self, decision: Any) -> None:
        self.reactions[id(decision.event)] = decision.reason
        mark = "->" if decision.accepted else "--"
        ev = decision.event
        _say(self.echo, f"     [{ev.time:6.1f} s] {ev.label:<14} d={ev.dissimilarity:7.4f}  "
                        f"{mark} robot: {decision.reason}")

    def stream_to_robot(self) -> list:
        """Feed everything the person has done so far to the recognizer and the robot.

        Returns
        -------
        list of Event
            The events of the samples just streamed.
        """
        t0 = time.perf_counter()
        ts, ps, qs = self.person.samples_until()
        events = []
        for k in range(ts.shape[0]):
            for ev in self.tracer.push(ts[k], ps[k], qs[k]):
                self.robot.handle(ev)
                events.append(ev)
        t1 = time.perf_counter()
        if ts.size:
            self.robot.advance_to(float(ts[-1]))
        self.timing["recognition"] += t1 - t0
        self.timing["robot"] += time.perf_counter() - t1
        self.timing["samples"] += ts.shape[0]
        return events

    def command(self, onset: float, label: str, policy: PersonPolicy) -> bool:
        """The person gives one command, watches, and repeats it while the robot ignores it.

        Parameters
        ----------
        onset : float
            Intended start [s] (later when the session is behind schedule after repeats).
        label : str
            Gesture.
        policy : PersonPolicy

        Returns
        -------
        bool
            Whether an event of ``label`` reached the robot.
        """
        attempts, obeyed = 0, False
        while not obeyed and attempts <= policy.max_repeats:
            self._perform(onset, label, repeat=attempts > 0)
            attempts += 1
            self.person.hold(policy.watch)
            obeyed = any(ev.label == label for ev in self.stream_to_robot())
        self.command_log.append(
            {"onset_s": onset, "label": label, "attempts": attempts, "obeyed": obeyed}
        )
        return obeyed

    def _perform(self, onset: float, label: str, repeat: bool) -> None:
        person = self.person
        if repeat:
            _say(self.echo, f"     [{person.time:6.1f} s] person: the robot ignored {label}; again")
            person.perform(label, gap=0.0)
            return
        with warnings.catch_warnings():  # behind schedule after repeats: start late
            warnings.simplefilter("ignore")
            person.perform(label, start_t=max(onset, person.time))

    def finish(self, rest: float = 3.0, settle: float = 2.0) -> Any:
        """The person rests, the last samples are streamed, the robot settles.

        Parameters
        ----------
        rest : float
            Seconds the person holds still after the last command.
        settle : float
            Seconds the robot runs on after the person's last sample.

        Returns
        -------
        SessionLog or None
            The MuJoCo robot's log of the whole session (None for another robot: its planner's
            decisions and its backend tell what happened).
        """
        self.person.hold(rest)
        self.stream_to_robot()
        self.robot.advance_to(self.person.time + settle)
        return self.robot.log() if hasattr(self.robot, "log") else None


def run_commands(loop: ClosedLoop, commands: Sequence[tuple[float, str]], policy: PersonPolicy,
                 progress: bool = True) -> Any:
    """Give every command in turn (repeating ignored ones), then let the session end.

    Parameters
    ----------
    loop : ClosedLoop
    commands : sequence of (float, str)
        (onset [s], gesture).
    policy : PersonPolicy
    progress : bool
        Show a progress bar over the commands.

    Returns
    -------
    SessionLog
        The robot's log.
    """
    from tqdm import tqdm

    echo = loop.echo
    if progress and echo is not None:
        loop.echo = tqdm.write  # a line above the bar, never on the bar's own line
    try:
        for onset, label in tqdm(commands, unit="command", disable=not progress, leave=False):
            loop.command(onset, label, policy)
    finally:
        loop.echo = echo
    return loop.finish()
