"""The robots ``framefree live --robot`` drives: the MuJoCo Panda, a dry run, a Franka arm."""

from __future__ import annotations

import sys
from typing import Any

import click

from ..errors import FramefreeError

__all__ = ["finish_robot", "robot_factory"]


def _robot_dry_run():
    """Factory ``time_offset -> RobotSession`` for ``--robot dry-run``: the planner's commands,
    as JSON lines on standard error, instead of a robot (see docs/robot.md)."""
    from ..robot.backends import DryRunBackend, RobotSession
    from ..robot.kinematics import PandaKinematics
    from ..robot.scenario import STACKING_PLANNER, STACKING_START

    def make(time_offset: float) -> RobotSession:
        # the commands go to stderr beside the other robot messages, not among the events
        backend = DryRunBackend(PandaKinematics().tcp_pose(STACKING_START), log=sys.stderr,
                                dt=0.01)
        return RobotSession(backend, STACKING_PLANNER, time_offset=time_offset)

    return make


def robot_factory(robot: str, host: str | None) -> Any:
    """The robot factory of ``--robot`` (None for ``none``); checked before the models are built."""
    if host is not None and robot != "franka":
        raise FramefreeError("--robot-host needs --robot franka")
    if robot == "franka":
        if not host:
            raise FramefreeError("--robot franka needs --robot-host HOST (the arm's FCI address, "
                                 "or 127.0.0.1 for franky-sim on this machine)")
        return _robot_franka(host)
    return {"sim": _robot_sim, "dry-run": _robot_dry_run}.get(robot, lambda: None)()


def _robot_franka(host: str):
    """Factory ``time_offset -> RobotSession`` for ``--robot franka``: the arm is connected at
    the first pose, and every event acts at its time on the arm's clock."""
    try:
        import franky  # noqa: F401
    except ImportError:
        raise FramefreeError("--robot franka needs franky: pip install 'framefree[franka]'"
                             ) from None
    from ..robot.backends import FrankaBackend, RobotSession
    from ..robot.scenario import STACKING_PLANNER

    def on_event(decision) -> None:
        ev = decision.event
        verdict = "->" if decision.accepted else "(ignored)"
        click.echo(f"{ev.time:9.2f} s  robot {verdict} {ev.label} [{decision.reason}]", err=True)

    def make(time_offset: float) -> RobotSession:
        backend = FrankaBackend(host, open_width=STACKING_PLANNER.gripper_open_width)
        click.echo(f"robot: Franka at {host} connected", err=True)
        return RobotSession(backend, STACKING_PLANNER, time_offset=time_offset, on_event=on_event)

    return make


def finish_robot(sim: Any, robot_settle: float, robot_plot: str | None) -> None:
    sim.advance_to(sim.time + robot_settle)
    if getattr(getattr(sim, "backend", None), "host", None) is not None:  # a Franka arm
        sim.halt()
        log = sim.planner.decisions
        click.echo(f"robot (Franka at {sim.backend.host}): {len(log)} events handled, "
                   f"{sum(d.accepted for d in log)} changed the plan, {_where(sim)}"
                   f"{sim.time:.1f} s on the arm's clock", err=True)
        return
    if not hasattr(sim, "log"):  # dry run
        sim.backend.close()
        click.echo(f"robot (dry run): {len(sim.backend.commands)} commands logged, "
                   f"{sim.time:.1f} s", err=True)
        return
    log = sim.log()
    acted = sum(1 for d in log.decisions if d.accepted)
    click.echo(f"robot: {len(log.decisions)} events handled, {acted} changed the plan, "
               f"{sim.time:.1f} s simulated", err=True)
    if robot_plot:
        from ..robot.render import plot_session

        click.echo(f"robot session figure: {plot_session(log, robot_plot)}", err=True)


def _where(session: Any) -> str:
    """Where the arm's TCP ended and where the planner's ideal arm (the same events, an arm that
    moves exactly as commanded) ends, as a phrase."""
    import numpy as np

    from ..robot.franka_demo import ideal_path

    trace = session.backend.trace
    if not trace:
        return ""
    start = np.eye(4)
    start[:3, 3] = trace[0][1]
    planned = ideal_path([d.event for d in session.planner.decisions], start, len(trace),
                         session.backend.dt, session.planner.params, float(trace[0][3]),
                         session.time_offset)[-1]
    end = trace[-1][1]
    apart = 1000 * float(np.linalg.norm(end - planned))
    return ("TCP at ({:.3f}, {:.3f}, {:.3f}) m, ".format(*end)
            + "planned ({:.3f}, {:.3f}, {:.3f}) m, {:.1f} mm apart, ".format(*planned, apart))


def _robot_sim():
    """Factory ``time_offset -> RobotSim`` for ``--robot sim``; a clear error without MuJoCo.

    :mod:`framefree.robot.sim` is imported first: it chooses MuJoCo's GL backend (EGL without a
    display), which MuJoCo fixes at its first import.
    """
    try:
        from ..robot import sim as _sim
    except ImportError as exc:
        raise FramefreeError(f"--robot sim is not available: {exc}") from None
    try:
        _sim.import_mujoco()
    except _sim.SimulatorMissing as exc:
        raise FramefreeError(f"--robot sim: {exc}") from None
    from ..robot.scenario import STACKING_PLANNER, STACKING_SCENE, STACKING_START
    from ..robot.session import RobotSim

    def on_event(decision) -> None:
        ev = decision.event
        verdict = "->" if decision.accepted else "(ignored)"
        click.echo(f"{ev.time:9.2f} s  robot {verdict} {ev.label} [{decision.reason}]", err=True)

    def make(time_offset: float) -> RobotSim:
        return RobotSim(planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START,
                        time_offset=time_offset, on_event=on_event)

    return make
