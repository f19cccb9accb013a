"""``framefree robot sim``: run a scripted gesture session on the simulated Panda, write figures."""

from __future__ import annotations

import time
from pathlib import Path

import click

__all__ = ["register"]


@click.group("robot")
def robot_group() -> None:
    """The gesture-commanded robot (planner FSM, controller, MuJoCo Panda)."""


@robot_group.command("sim")
@click.option(
    "--scenario",
    type=click.Choice(["stack", "stack-paper-times", "pick"]),
    default="stack",
    show_default=True,
    help="stack: the paper's detected events with gaps shortened; stack-paper-times: the paper's "
    "timing (0:31–3:05); pick: pick up one block and move it.",
)
@click.option(
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("robot_sim"),
    show_default=True,
    help="Folder for the figures.",
)
@click.option("--render/--no-render", default=True, show_default=True, help="Render images.")
@click.option("--frames", type=int, default=12, show_default=True, help="Frames in the strip.")
def sim_command(scenario: str, out: Path, render: bool, frames: int) -> None:
    """Run a scripted event timeline through planner, controller and simulated Panda."""
    from ..robot.render import plot_session
    from ..robot.session import run_events

    out.mkdir(parents=True, exist_ok=True)
    events, kwargs = _scenario_events(scenario)

    def report(decision) -> None:
        e = decision.event
        mark = "→" if decision.accepted else "·"
        click.echo(f"  t={decision.time:7.2f} s  {mark} {e.label:<14} {decision.reason}")

    click.echo(f"simulating {len(events)} events ({scenario}) …")
    t0 = time.perf_counter()
    log = run_events(events, settle=4.0, on_event=report, log_rate=25, **kwargs)
    wall = time.perf_counter() - t0
    click.echo(f"simulated {log.t[-1]:.1f} s in {wall:.1f} s of wall time")
    _report_outcome(scenario, log)
    fig = plot_session(log, out / "session.png", title=f"framefree robot sim — {scenario}")
    click.echo(f"wrote {fig}")
    if render:
        _render(log, out, frames, kwargs.get("scene"))


def _scenario_events(scenario: str) -> tuple[list, dict]:
    """The scripted events of a scenario and the run_events settings it needs."""
    from ..online.events import Event
    from ..robot.scenario import STACKING_PLANNER, STACKING_SCENE, STACKING_START, paper_events

    if scenario == "pick":
        script = [(0.5, "go_left"), (3.5, "go_down"), (6.5, "close_gripper"), (8.0, "go_up"),
                  (10.5, "go_right"), (13.5, "go_down"), (16.5, "open_gripper"), (18.0, "go_up"),
                  (20.5, "go_home")]
        return [Event(label, t, 0.0, -1) for t, label in script], {}
    events = paper_events(start=1.0)
    if scenario == "stack":
        events = _compress(events)
    return events, dict(planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START)


def _report_outcome(scenario: str, log) -> None:
    """Stacking success, or how far each block moved."""
    from ..robot.scenario import evaluate_stacking

    if scenario != "pick":
        res = evaluate_stacking(log)
        verdict = "SUCCESS" if res.success else "FAILED"
        click.echo(
            f"stacking {verdict}: block_b on block_a, horizontal offset "
            f"{1000 * res.horizontal_offset:.1f} mm, height difference "
            f"{1000 * res.height_difference:.1f} mm, tilt {res.tilt:.3f} rad"
        )
        return
    moved = {n: float(((log.block(n)[-1, :3] - log.block(n)[0, :3]) ** 2).sum() ** 0.5)
             for n in log.block_names}
    click.echo("block displacement: " + ", ".join(f"{n} {1000 * d:.0f} mm" for n, d in moved.items()))


def _render(log, out: Path, frames: int, scene) -> None:
    """A strip of frames and a GIF, when offscreen OpenGL works."""
    from ..robot.render import render_frames, rendering_available, save_gif, save_strip

    ok, message = rendering_available()
    if not ok:
        click.secho(f"no images: {message}", fg="yellow")
        return
    images = render_frames(log, n_frames=frames, scene=scene)
    click.echo(f"wrote {save_strip(images, out / 'strip.png')}")
    anim = render_frames(log, n_frames=max(2, int(log.t[-1])), scene=scene, width=320, height=240)
    gif = save_gif(anim, out / "session.gif", fps=6)
    click.echo(f"wrote {gif} (1 frame per simulated second)")


def _compress(events, motion_gap: float = 3.0, other_gap: float = 1.6):
    """Same events, same order, with gaps just long enough for each action to finish."""
    from ..online.events import Event

    out, t = [], events[0].time
    for i, e in enumerate(events):
        out.append(Event(e.label, t, e.dissimilarity, e.model))
        if i == 0:
            t += 4.0  # homing from the ready pose
        elif e.label.startswith("go_"):
            t += motion_gap
        else:
            t += other_gap
    return out


def register(group: click.Group) -> None:
    """Add the ``robot`` command group to the ``framefree`` CLI."""
    group.add_command(robot_group)
