"""``framefree describe`` and ``framefree classify``: descriptors and 1-NN recognition of CSV files."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click
import numpy as np

from ..classifier import NearestNeighborClassifier
from ..descriptors import available_descriptors, get_descriptor
from ..descriptors.base import Descriptor
from ..errors import FramefreeError
from ..trajectory import Trajectory

__all__ = ["descriptor_from_options", "descriptor_options", "register"]


def descriptor_options(func: Callable[..., Any]) -> Callable[..., Any]:
    """Click options shared by every command that computes descriptors."""
    options = [
        click.option(
            "--descriptor",
            "-d",
            default="bilts+",
            show_default=True,
            type=click.Choice(available_descriptors(), case_sensitive=False),
            help="Descriptor to compute.",
        ),
        click.option(
            "--progress",
            default="screw",
            show_default=True,
            type=click.Choice(["screw", "angle", "arclength"]),
            help="Geometric progress the trajectory is resampled by.",
        ),
        click.option("--L", "L", type=float, default=None, help="Scale length L [m]."),
        click.option(
            "--ds-scale", type=float, default=None, help="BILTS window scale (m, or rad for angle)."
        ),
        click.option("--lam", type=float, default=None, help="λ weight (DHB, eFS, ISA)."),
        click.option(
            "--quat-order",
            default="wxyz",
            show_default=True,
            type=click.Choice(["wxyz", "xyzw"]),
            help="Quaternion column order of the input files.",
        ),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def descriptor_from_options(
    descriptor: str, progress: str, L: float | None, ds_scale: float | None, lam: float | None
) -> Descriptor:
    """Build a descriptor from the shared CLI options (unset options keep their defaults)."""
    params: dict[str, Any] = {"progress": progress}
    for key, value in (("L", L), ("ds_scale", ds_scale), ("lam", lam)):
        if value is not None:
            params[key] = value
    try:
        return get_descriptor(descriptor, **params)
    except TypeError as exc:
        raise click.UsageError(f"{descriptor}: {exc}") from None
    except ValueError as exc:
        raise click.UsageError(str(exc)) from None


def _feature_names(desc: Descriptor, width: int) -> list[str]:
    names = getattr(desc, "feature_names", None)
    if names is not None and len(names) == width:
        return list(names)
    return [f"f{i}" for i in range(width)]


@click.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False))
@descriptor_options
@click.option(
    "--out",
    "-o",
    type=click.Path(file_okay=False),
    default=None,
    help="Folder for the descriptor CSVs (default: next to each input, suffix _<descriptor>.csv).",
)
def describe(files, descriptor, progress, L, ds_scale, lam, quat_order, out):
    """Compute the descriptor of each pose FILE and write it as CSV (one row per sample)."""
    desc = descriptor_from_options(descriptor, progress, L, ds_scale, lam)
    tag = desc.name.replace("+", "plus")
    for name in files:
        path = Path(name)
        seq = desc.compute(Trajectory.from_csv(path, quat_order=quat_order))
        target_dir = Path(out) if out else path.parent
        target_dir.mkdir(parents=True, exist_ok=True)
        target = target_dir / f"{path.stem}_{tag}.csv"
        header = ",".join(_feature_names(desc, seq.shape[1]))
        np.savetxt(target, seq, delimiter=",", header=header, comments="", fmt="%.12g")
        click.echo(f"{path} -> {target}  ({seq.shape[0]} samples x {seq.shape[1]} features)")


def load_labelled_folder(
    root: Path, quat_order: str = "wxyz"
) -> tuple[list[Trajectory], list[str]]:
    """Trajectories of ``root/<label>/**/*.csv``, labelled by their first-level folder name."""
    trajs: list[Trajectory] = []
    labels: list[str] = []
    for label_dir in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")):
        for csv in sorted(label_dir.rglob("*.csv")):
            trajs.append(Trajectory.from_csv(csv, quat_order=quat_order))
            labels.append(label_dir.name)
    if not trajs:
        raise FramefreeError(f"{root}: no models found (expected <label>/*.csv files below it)")
    return trajs, labels


@click.command()
@click.argument("queries", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--models",
    "-m",
    required=True,
    type=click.Path(exists=True, file_okay=False),
    help="Folder with one sub-folder of CSV recordings per label (<label>/*.csv).",
)
@descriptor_options
@click.option(
    "--json", "json_path", type=click.Path(dir_okay=False), help="Also write results as JSON."
)
def classify(queries, models, descriptor, progress, L, ds_scale, lam, quat_order, json_path):
    """Recognize each QUERY pose file by its nearest labelled model (1-NN)."""
    desc = descriptor_from_options(descriptor, progress, L, ds_scale, lam)
    model_trajs, labels = load_labelled_folder(Path(models), quat_order)
    clf = NearestNeighborClassifier(desc).fit(model_trajs, labels)
    query_trajs = [Trajectory.from_csv(q, quat_order=quat_order) for q in queries]
    predicted = clf.predict(query_trajs)
    D = clf.distances_
    rows = []
    width = max(len(str(q)) for q in queries)
    click.echo(
        f"{'query':<{width}}  {'label':<16} {'distance':>10} {'runner-up':<16} {'margin':>8}"
    )
    for q, lab, d in zip(queries, predicted, D, strict=True):
        order = np.argsort(d, kind="stable")
        best = d[order[0]]
        others = [k for k in order if labels[k] != lab]
        runner = labels[others[0]] if others else "-"
        margin = (d[others[0]] / best if best > 0 else np.inf) if others else np.inf
        rows.append(
            {
                "query": str(q),
                "label": str(lab),
                "distance": float(best),
                "runner_up": runner,
                "margin": float(margin),
            }
        )
        click.echo(f"{q!s:<{width}}  {lab:<16} {best:>10.4g} {runner:<16} {margin:>7.2f}x")
    if json_path:
        Path(json_path).write_text(
            json.dumps({"descriptor": repr(desc), "results": rows}, indent=2)
        )


def register(group: click.Group) -> None:
    """Add ``describe`` and ``classify`` to the CLI."""
    group.add_command(describe)
    group.add_command(classify)
