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
    "paper: the paper's recognizer (fixed windows).",
)
@click.option("--no-render", is_flag=True, help="Skip the MuJoCo images even if OpenGL works.")
@click.option("--models", type=click.Path(exists=True, dir_okay=False), default=None,
              help="Gesture library file (framefree enroll) with the seven HPM gestures.")
def demo(out, seed, method, no_render, models):
    """Replica dataset → gesture models → a person gives the paper's stacking commands by hand
    gestures → live recognition → planner → simulated Panda stacking blocks.
    """
    # robot.sim chooses MuJoCo's offscreen GL backend, which is fixed at mujoco's first import
    from ..robot.sim import SimulatorMissing, import_mujoco

    try:
        import_mujoco()
    except SimulatorMissing as exc:
        raise click.ClickException(str(exc)) from None
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


def register(group: click.Group) -> None:
    """Add ``demo`` to the CLI."""
    group.add_command(demo)
