"""``framefree dataset make|info`` and ``framefree plot``: the HPM replica, dataset summaries, figures."""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from ..errors import FramefreeError
from .inputs import dataset_file_options, pose_file_options, writable_file

__all__ = ["register", "trajectory_stats"]


def trajectory_stats(traj: Trajectory) -> tuple[float, float, float]:
    """(duration [s], path length of the origin [m], largest rotation from the first pose [deg])."""
    length = float(np.linalg.norm(np.diff(traj.p, axis=0), axis=1).sum())
    R = traj.rotations()
    angle = np.linalg.norm(se3.vector_from_rotation(R[0].T @ R), axis=1).max()
    return traj.duration, length, float(np.degrees(angle))


def _range(values: list[float], fmt: str) -> str:
    v = np.asarray(values)
    return f"{format(v.mean(), fmt)} ({format(v.min(), fmt)}–{format(v.max(), fmt)})"


@click.group("dataset")
def dataset_group() -> None:
    """Make the synthetic HPM replica or summarize a gesture dataset."""


@dataset_group.command("make")
@click.option("--out", "-o", type=click.Path(file_okay=False, path_type=Path), default=None,
              help="Folder to write to (default: the cached replica, created if missing).")
@click.option("--seed", "-s", type=int, default=0, show_default=True, help="Random seed.")
@click.option("--streams", "-k", "n_streams", type=int, default=3, show_default=True,
              help="Number of continuous labelled streams.")
def make_command(out: Path | None, seed: int, n_streams: int) -> None:
    """Write the replica: 7 gestures × 16 contexts (the paper's 12 and 4 stress contexts) × 5 trials,
    plus streams.

    \b
    Layout: OUT/<gesture>/<context>/trial_<k>.csv and OUT/streams/stream_<i>.csv
    with OUT/streams/stream_<i>_labels.csv (label,start_t,end_t).
    Without --out: the cached replica in $FRAMEFREE_CACHE (default ~/.cache/framefree).
    """
    from ..replica import make_replica, replica_path

    if out is None:
        path = replica_path(seed)
        click.echo(f"replica (seed {seed}) at {path} (the cache: $FRAMEFREE_CACHE, default "
                   "~/.cache/framefree)")
        return
    make_replica(out, seed=seed, n_streams=n_streams)
    trials = sum(1 for _ in Path(out).glob("*/*/trial_*.csv"))
    click.echo(f"wrote {trials} trials and {n_streams} streams to {out}")


@dataset_group.command("info")
@click.argument("root", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.option("--model-context", default="original_1", show_default=True)
@dataset_file_options
def info_command(root: Path, model_context: str, quat_order: str, units: str) -> None:
    """Summarize a dataset: gestures × contexts × trials, durations, path lengths, rotations."""
    from ..datasets import load_dataset

    ds = load_dataset(root, model_context=model_context, quat_order=quat_order, units=units)
    click.echo(f"{ds.root}: {len(ds.gestures)} gestures × {len(ds.contexts)} contexts, {len(ds)} trials "
               f"(model context {ds.model_context!r}: {len(ds.models())}; "
               f"train {len(ds.queries('train'))}, test {len(ds.queries('test'))})")
    click.echo("")
    click.echo(f"model context {ds.model_context}: mean (min–max)")
    cols = ("duration [s]", "path length [m]", "rotation [deg]")
    head = f"{'gesture':15s} {'trials':>6s}  " + "  ".join(f"{c:>18s}" for c in cols)
    click.echo(head)
    click.echo("-" * len(head))
    for g in ds.gestures:
        stats = [trajectory_stats(t.trajectory) for t in ds.select(g, ds.model_context)]
        d, L, a = zip(*stats, strict=True)
        click.echo(f"{g:15s} {len(stats):6d}  {_range(d, '.2f'):>18s}  {_range(L, '.2f'):>18s}  "
                   f"{_range(a, '.0f'):>18s}")
    click.echo("")
    head = f"{'context':15s} {'trials':>6s}  {'samples':>16s}  {'duration [s]':>18s}"
    click.echo(head)
    click.echo("-" * len(head))
    for c in ds.contexts:
        trials = ds.select(context=c)
        n = [len(t.trajectory) for t in trials]
        d = [t.trajectory.duration for t in trials]
        click.echo(f"{c:15s} {len(trials):6d}  {_range(n, '.0f'):>16s}  {_range(d, '.2f'):>18s}")


@click.command("plot")
@click.argument("target", type=click.Path(exists=True, path_type=Path))
@click.option("--out", "-o", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="PNG file (default: in the working folder, <gesture>_<context>_<trial>.png for a "
              "trial file (its last two folders and its name), <name>_gallery.png for a dataset; "
              "never inside TARGET).")
@click.option("--context", default=None,
              help="Context shown in a dataset gallery (default: the model context).")
@click.option("--trial", default=None, help="Trial shown per gesture in a gallery (default: the first).")
@pose_file_options
def plot_command(target: Path, out: Path | None, context: str | None, trial: str | None,
                 quat_order: str, units: str, skip_header: bool) -> None:
    """Draw TARGET as a PNG: a trial file (3-D path with orientation triads) or a dataset folder
    (a gallery with one trial per gesture)."""
    from ..plots import plot_gallery, plot_trajectory

    name = target.resolve().name or "dataset"
    if target.is_dir():
        from ..datasets import load_dataset

        out = writable_file(out or Path(f"{name}_gallery.png"))
        ds = load_dataset(target, quat_order=quat_order, units=units, skip_header=skip_header)
        plot_gallery(ds, out, context=context, trial=trial)
    else:
        # named after the file and its folders (go_up_original_1_trial_1.png), so that trials of
        # different gestures or contexts do not overwrite each other
        out = writable_file(out or Path("_".join(target.resolve().with_suffix("").parts[-3:]) + ".png"))
        if out.resolve() == target.resolve():
            raise FramefreeError(f"{out}: would overwrite the input; choose another --out")
        traj = Trajectory.from_csv(target, quat_order=quat_order, units=units,
                                   skip_header=skip_header)
        title = "/".join(target.with_suffix("").parts[-3:])
        plot_trajectory(traj, path=out, title=title)
    click.echo(f"wrote {out}")


def register(group: click.Group) -> None:
    """Add ``dataset`` and ``plot`` to the ``framefree`` command."""
    group.add_command(dataset_group)
    group.add_command(plot_command)
