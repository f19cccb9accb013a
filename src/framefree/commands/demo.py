"""``framefree demo``: the whole pipeline, from a person's hand to a stacked block."""

from __future__ import annotations

import click

from ..robot.demo import DEMO_PEOPLE, METHODS, PAPER_RESULT


@click.command()
@click.option(
    "--out",
    "-o",
    type=click.Path(file_okay=False),
    default="demo_output",
    show_default=True,
    help="Folder for the figures and summary.json.",
)
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=0,
    show_default=True,
    help=f"Session seed k: the person is the held-out person "
    f"{DEMO_PEOPLE.start} + (k mod {len(DEMO_PEOPLE)}), never used for tuning (the models always "
    "come from the replica of seed 0).",
)
@click.option(
    "--method",
    type=click.Choice(METHODS),
    default=METHODS[0],
    show_default=True,
    help="segments: framefree's recognizer (whole gestures spotted and classified as offline); "
    "paper: the paper's recognizer (fixed windows); window: a practitioner's baseline "
    "(sliding windows of palm positions, 1-NN, a threshold).",
)
@click.option("--no-render", is_flag=True, help="Skip the MuJoCo images even if OpenGL works.")
@click.option("--models", type=click.Path(exists=True, dir_okay=False), default=None,
              help="Gesture library file (framefree enroll) with the seven HPM gestures.")
@click.option("--robot", type=click.Choice(["mujoco", "franka-sim"]), default="mujoco",
              show_default=True,
              help="mujoco: framefree's Panda scene with the blocks; franka-sim: the same session "
              "drives an FR3 served by franky-sim over the libfranka protocol on loopback, "
              "through franky, in real time (a few minutes; no blocks in that scene).")
def demo(out, seed, method, no_render, models, robot):
    """Replica dataset → gesture models → a person gives the paper's stacking commands by hand
    gestures → live recognition → planner → simulated Panda stacking blocks.
    """
    # robot.sim chooses MuJoCo's offscreen GL backend, which is fixed at mujoco's first import
    from ..robot.sim import SimulatorMissing, import_mujoco

    try:
        import_mujoco()
    except SimulatorMissing as exc:
        raise click.ClickException(str(exc)) from None
    if robot == "franka-sim":
        _franka_sim_demo(out, seed, method, models)
        return
    from ..robot.demo import run_demo

    result = run_demo(out, seed=seed, render=not no_render, echo=click.echo, method=method,
                      models=models)
    rec = result.recognition
    click.echo("")
    click.echo(
        f"  commands obeyed    {result.obeyed:5d} of {result.commands}  (the person repeats an "
        "ignored command up to twice)"
    )
    click.echo(f"                      {method:<9}     paper (its Table II)")
    for key in ("precision", "recall", "f1"):
        click.echo(f"  {key:<18} {100 * rec[key]:9.1f} %  {100 * PAPER_RESULT[key]:9.1f} %")
    click.echo(f"  false positives    {rec['fp']:9d}    {0:9d}")
    if rec["latency_median_s"] is not None:
        click.echo(f"  median latency     {rec['latency_median_s']:9.2f} s after the gesture ends")
    task = result.task
    where = (
        f"offset {1000 * task['horizontal_offset_m']:.1f} mm, "
        f"height difference {1000 * task['height_difference_m']:.1f} mm"
    )
    verdict = (
        "SUCCESS: green block stacked on red" if result.stacked else "FAILED: green not on red"
    )
    click.echo(f"  task               {verdict} ({where})")
    for miss in result.missed:
        click.echo(f"  missed             {miss['label']} at {miss['start_t']:.1f} s")
    click.echo("")
    for name, path in result.files.items():
        click.echo(f"  {name:<22} {path}")


def _franka_sim_demo(out: str, seed: int, method: str, models: str | None) -> None:
    """``framefree demo --robot franka-sim``: the demo's session against the protocol simulator."""
    import json
    from pathlib import Path

    from ..errors import FramefreeError
    from ..robot.demo import _demo_recognizer, demo_commands
    from ..robot.franka_demo import run_franka_session

    try:
        import franky  # noqa: F401
        import franky_sim  # noqa: F401
    except ImportError:
        raise FramefreeError("--robot franka-sim needs franky and franky-sim: "
                             "pip install 'framefree[franka]'") from None
    recognizer = _demo_recognizer(None, models, method, 0, click.echo)
    commands = demo_commands()
    click.echo(f"2/3  {len(commands)} commands by hand gestures drive an FR3 (franky-sim, "
               "libfranka protocol on loopback) through franky, in real time ...")
    run = run_franka_session(recognizer, commands, seed, echo=click.echo)
    wanted = [label for _, label in commands]
    click.echo("")
    click.echo(f"  commands obeyed    {sum(c['obeyed'] for c in run.command_log):5d} of "
               f"{len(commands)}; in the demo's order: {'yes' if run.accepted == wanted else 'no'}")
    for label, width in run.gripper_widths:
        click.echo(f"  {label:<18} fingers at {1000 * width:.1f} mm two seconds later")
    click.echo(f"  path               within {1000 * run.path_error:.1f} mm of the ideal arm; ends "
               f"{1000 * run.end_error:.1f} mm from the planned end")
    click.echo(f"  time               {run.robot_seconds:.1f} s on the arm's clock, "
               f"{run.wall_seconds:.1f} s wall"
               + (f"; {run.replans} motion(s) sent again after franky's planner failed"
                  if run.replans else ""))
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    summary = {"robot": "franka-sim", "host": run.host, "seed": seed, "accepted": run.accepted,
               "commands": run.command_log, "path_error_m": run.path_error,
               "end_error_m": run.end_error, "end_position_m": run.end_position.tolist(),
               "planned_end_m": run.planned_end.tolist(), "gripper_widths_m": run.gripper_widths,
               "robot_seconds": run.robot_seconds, "wall_seconds": run.wall_seconds,
               "replans": run.replans}
    path = folder / "summary_franka_sim.json"
    path.write_text(json.dumps(summary, indent=2))
    click.echo(f"  summary            {path}")


def register(group: click.Group) -> None:
    """Add ``demo`` to the CLI."""
    group.add_command(demo)
