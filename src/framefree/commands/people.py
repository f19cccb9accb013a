"""``framefree evaluate-people``: recognition of people the models never saw."""

from __future__ import annotations

import json
from pathlib import Path

import click
import numpy as np

from ..benchmark.people import FRAMES, PEOPLE_METHODS, PeopleResult, evaluate_people
from ..datasets.people_layout import load_people
from ..descriptors.canonical import INVARIANCES
from ..io.conventions import CONVENTIONS
from .inputs import writable_file

__all__ = ["register"]


def _print_result(result: PeopleResult) -> None:
    s = result.settings
    click.echo(f"{s['method']} (invariance {s['invariance']}), world frames {s['frames']}, "
               f"{s['protocol']}: {s['queries']} queries, {s['models']} models")
    width = max(len(p) for p in result.per_person)
    for person, acc in result.per_person.items():
        click.echo(f"  {person:<{width}}  {100 * acc:6.1f} %")
    click.echo(f"accuracy {result.accuracy:.4f}")
    mistakes = result.mistakes()
    if mistakes:
        click.echo("most frequent confusions (true -> recognized):")
        for true, guess, n in mistakes[:8]:
            click.echo(f"  {true} -> {guess}: {n}")


@click.command("evaluate-people")
@click.argument("data", type=click.Path(exists=True, file_okay=False))
@click.option("--models", "-m", type=click.Path(exists=True, file_okay=False), default=None,
              help="Model people <person>/<gesture>/<recordings>; every recording of DATA is "
              "classified against all of them. Without it, one person of DATA is left out at a time.")
@click.option("--invariance", type=click.Choice(INVARIANCES), default="full", show_default=True,
              help="full: any change of world frame and grip; gravity: only turns about the "
              "vertical (keeps up and down apart).")
@click.option("--method", type=click.Choice(PEOPLE_METHODS), default="framefree", show_default=True,
              help="framefree, or a method to compare with (docs/real-people.md).")
@click.option("--frames", type=click.Choice(FRAMES), default="recorded", show_default=True,
              help="World frame of every recording: as recorded, turned about the vertical, or "
              "tilted at random (seeded).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the world frames.")
@click.option("--convention", type=click.Choice(sorted(CONVENTIONS)), default=None,
              help="Coordinate convention of the recordings (default: each format's own: unity for "
              "Machete files, framefree for CSV).")
@click.option("--json", "json_path", type=click.Path(dir_okay=False), default=None,
              help="Also write the result as JSON.")
def evaluate_people_command(data, models, invariance, method, frames, seed, convention, json_path):
    """Recognize the gestures of people the models never saw.

    DATA (and MODELS) are folders <person>/<gesture>/<recording>: Machete recordings as published,
    or framefree CSV files (multi-tracker with a header, or single-tracker). Prints the accuracy
    (a fraction), each person's accuracy and the most frequent confusions.
    """
    from tqdm import tqdm

    if json_path:
        writable_file(json_path, "--json")
    queries = load_people(data, convention, progress=True)
    pool = load_people(models, convention, progress=True) if models else None
    if pool is None and len(queries.people) < 2:
        raise click.UsageError(f"{data} holds one person; leave-one-person-out needs two or more "
                               "(or give --models)")
    folds = 1 if pool is not None else len(queries.people)
    result = evaluate_people(queries, pool, method, invariance, frames, seed,
                             progress=lambda it: tqdm(it, total=folds, desc="people", unit="fold",
                                                      leave=False))
    _print_result(result)
    if json_path:
        out = result.to_dict()
        out["settings"].update({"data": str(data), "models": str(models) if models else None})
        Path(json_path).write_text(json.dumps(out, indent=2, default=lambda x: np.asarray(x).tolist()))
        click.echo(f"wrote {json_path}")


def register(group: click.Group) -> None:
    """Add ``evaluate-people`` to the CLI."""
    group.add_command(evaluate_people_command)
