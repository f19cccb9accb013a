"""``framefree describe`` and ``framefree classify``: descriptors and 1-NN recognition of CSV files."""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click
import numpy as np

from ..classifier import PRESETS, RECOMMENDED, NearestNeighborClassifier
from ..core.posecsv import PlausibilityWarning
from ..core.trajectory import Trajectory
from ..datasets.people_layout import is_multi_tracker_file, load_labelled, read_recording
from ..descriptors import available_descriptors, get_descriptor
from ..descriptors.base import Descriptor
from ..descriptors.canonical import INVARIANCES
from ..errors import FramefreeError
from ..rejection import REJECTED
from .inputs import model_options, pose_file_options, read_models, writable_file, writable_folder

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
            "--preset", type=click.Choice(tuple(PRESETS)), default="recommended",
            show_default=True,
            help="Settings of BILTS+ left unset: recommended (L 0.1 m, ds_scale 0.06 m, "
            "pre-smoothing, open end, axis prior; as NearestNeighborClassifier()) or paper "
            "(L 0.5 m, ds_scale 0.09 m: the paper's Table I settings)."),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def descriptor_from_options(
    descriptor: str, progress: str, L: float | None, ds_scale: float | None, lam: float | None,
    preset: str = "recommended",
) -> Descriptor:
    """Build a descriptor from the shared CLI options (unset options take the preset's values for
    BILTS+, else the descriptor's defaults), as ``NearestNeighborClassifier`` does."""
    params: dict[str, Any] = {}
    chosen = PRESETS[preset]
    if descriptor == RECOMMENDED["descriptor"] and progress == chosen.get("progress", progress):
        params.update({k: v for k, v in chosen.items() if k != "descriptor"})
    params["progress"] = progress
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


def _describe_targets(files: tuple[str, ...], out: Path, tag: str) -> list[tuple[Path, Path]]:
    """(input, output) pairs; two inputs may not share an output, no output may be an input."""
    pairs = [(Path(f), out / f"{Path(f).stem}_{tag}.csv") for f in files]
    inputs = {p.resolve() for p, _ in pairs}
    seen: dict[Path, Path] = {}
    for src, target in pairs:
        key = target.resolve()
        if key in inputs:
            raise FramefreeError(f"{target}: would overwrite an input file; choose another --out")
        if key in seen and seen[key].resolve() != src.resolve():
            raise FramefreeError(
                f"{seen[key]} and {src} would both be written to {target}; "
                "describe them in separate runs with different --out folders"
            )
        seen[key] = src
    return pairs


@click.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(exists=True))
@descriptor_options
@pose_file_options
@click.option(
    "--out",
    "-o",
    type=click.Path(file_okay=False),
    default=".",
    show_default=True,
    help="Folder for the descriptor CSVs <stem>_<descriptor>.csv (never next to the inputs).",
)
def describe(files, descriptor, progress, L, ds_scale, lam, preset, quat_order, units, skip_header,
             out):
    """Compute the descriptor of each pose FILE and write it as CSV (one row per sample)."""
    desc = descriptor_from_options(descriptor, progress, L, ds_scale, lam, preset)
    tag = desc.name.replace("+", "plus")
    pairs = _describe_targets(files, Path(out), tag)
    # every input is read and described before anything is written: a bad file leaves no output
    trajs = [Trajectory.from_csv(path, quat_order=quat_order, units=units, skip_header=skip_header)
             for path, _ in pairs]
    seqs = [desc.compute(traj) for traj in trajs]
    writable_folder(out)
    for (path, target), traj, seq in zip(pairs, trajs, seqs, strict=True):
        header = ",".join(_feature_names(desc, seq.shape[1]))
        np.savetxt(target, seq, delimiter=",", header=header, comments="", fmt="%.12g")
        click.echo(f"{path} -> {target}  ({len(traj)} poses over {traj.duration:.4g} s -> "
                   f"{seq.shape[0]} samples x {seq.shape[1]} features)")
        _say_reduced(path, traj, seq.shape[0], desc)


def _say_reduced(path: str | Path, traj: Trajectory, n_out: int, desc: Descriptor) -> None:
    """A note on stderr when a recording is reduced to far fewer samples than it has poses: a
    descriptor of fixed length describes one gesture, not a long recording."""
    if len(traj) <= 10 * n_out:
        return
    progress = getattr(desc, "progress", None)
    how = f"resampled along its {progress} progress" if progress else "resampled"
    click.echo(f"note: {path}: {len(traj)} poses ({traj.duration:.4g} s) {how} to {n_out} "
               "samples; a descriptor describes one gesture, so a long recording keeps only its "
               "overall shape (cut it into gestures first)", err=True)


@click.command()
@click.argument("queries", nargs=-1, required=True, type=click.Path(exists=True))
@click.option(
    "--models",
    "-m",
    required=True,
    type=click.Path(exists=True),
    help="A dataset root <gesture>/<context>/*.csv (see --model-context), a folder of "
    "<label>/*.csv recordings, a library folder written by record, or a library file (.npz) from "
    "enroll (its descriptor settings and thresholds are used: motion that is no gesture is "
    "rejected).",
)
@model_options
@descriptor_options
@pose_file_options
@click.option(
    "--invariance", type=click.Choice(INVARIANCES), default="full", show_default=True,
    help="full: any change of world frame and grip; gravity: turns about the vertical only "
    "(keeps up and down apart; docs/real-people.md).",
)
@click.option("--reject", is_flag=True,
              help="Say no_gesture for a query farther from its nearest model than that gesture's "
              "threshold (computed from the models; a library file always rejects).")
@click.option("--force", is_flag=True,
              help="Classify files whose numbers look implausible (millimetres, scalar-last "
              "quaternions) instead of stopping, and queries far longer, larger or slower than "
              "every model instead of saying no_gesture.")
@click.option(
    "--json", "json_path", type=click.Path(dir_okay=False), help="Also write results as JSON."
)
def classify(queries, models, model_context, model_quat_order, descriptor, progress, L, ds_scale,
             lam, preset, quat_order, units, skip_header, invariance, reject, force, json_path):
    """Recognize each QUERY pose file by its nearest labelled model (1-NN).

    QUERY files with several trackers (a framefree multi-tracker CSV or a Machete recording) are
    compared with MODELS of the same kind, <label>/<recording>.
    """
    desc = descriptor_from_options(descriptor, progress, L, ds_scale, lam, preset)
    if json_path:
        writable_file(json_path, "--json")
    thresholds = "auto" if reject else None
    if any(is_multi_tracker_file(q) for q in queries):
        query_samples = [read_recording(q) for q in queries]
        model_samples, labels = load_labelled(models)
        click.echo(f"{models}: {len(model_samples)} multi-tracker recordings of "
                   f"{len(set(labels))} labels", err=True)
    else:
        query_samples = _plausible(lambda: [
            Trajectory.from_csv(q, quat_order=quat_order, units=units, skip_header=skip_header)
            for q in queries], force)
        if Path(models).is_file():
            desc, thresholds, model_samples, labels = _library_models(models)
        else:
            found = _plausible(lambda: read_models(models, model_context, model_quat_order, units,
                                                   skip_header), force)
            model_samples, labels = found.trajectories, found.labels
    clf = NearestNeighborClassifier(desc, invariance=invariance, thresholds=thresholds)
    clf.fit(model_samples, labels)
    predicted = clf.predict(query_samples).astype(object)
    reasons = [None] * len(queries) if force else _out_of_scope(queries, query_samples, model_samples)
    predicted[[r is not None for r in reasons]] = REJECTED
    _report(queries, predicted, clf.distance_matrix(query_samples), list(labels), desc,
            json_path, clf.thresholds_, reasons)


def _out_of_scope(queries, samples, models) -> list[str | None]:
    """Per query, why it lies far outside the models' range (a warning line each), or None."""
    from ..scope import model_scope, out_of_scope

    scope = model_scope(models)
    reasons = [out_of_scope(s, scope) for s in samples]
    for q, why in zip(queries, reasons, strict=True):
        if why is not None:
            click.echo(f"warning: {q}: {why}; said {REJECTED} (--force classifies it anyway)",
                       err=True)
    return reasons


def _plausible(read, force: bool):
    """``read()``, stopped with one line by a file whose numbers look wrong (unless ``force``)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PlausibilityWarning)
        out = read()
    for w in caught:
        if issubclass(w.category, PlausibilityWarning) and not force:
            raise FramefreeError(f"{w.message}; or --force to classify it anyway")
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return out


def _library_models(path: str):
    """Descriptor, thresholds, takes and labels of a gesture library file."""
    from ..library.store import load_library
    from ..online.model_settings import segment_descriptor

    lib = load_library(path)
    click.echo(f"models: {path} is a gesture library: {len(lib.takes)} takes of "
               f"{len(lib.takes.gestures)} gestures, with its descriptor and thresholds", err=True)
    desc = segment_descriptor(lib.recognizer_config(), lib.learned_settings().window_spacing)
    return desc, dict(lib.gesture_thresholds), list(lib.takes.takes), list(lib.takes.labels)


def _report(queries, predicted, D, labels, desc, json_path, thresholds=None, reasons=None) -> None:
    """One line per query: label, distance, and either the runner-up label and how much farther it
    lies, or, for a rejected query, the nearest gesture and how far beyond its threshold it lies
    (no margin for a query out of the models' scope, ``reasons``); the same as JSON."""
    reasons = reasons or [None] * len(queries)
    rows = []
    width = max(len(str(q)) for q in queries)
    click.echo(f"{'query':<{width}}  {'label':<16} {'distance':>10} {'runner-up/nearest':<18} "
               f"{'margin':>8}")
    for q, lab, d, why in zip(queries, predicted, D, reasons, strict=True):
        order = np.argsort(d, kind="stable")
        best, nearest = d[order[0]], labels[order[0]]
        if why is not None:
            runner, margin = nearest, np.nan
        elif thresholds is not None and lab != nearest:  # rejected: beyond the nearest's threshold
            runner, margin = nearest, best / thresholds[nearest]
        else:
            others = [k for k in order if labels[k] != lab]
            runner = labels[others[0]] if others else "-"
            margin = (d[others[0]] / best if best > 0 else np.inf) if others else np.inf
        rows.append({
            "query": str(q), "label": str(lab), "distance": float(best), "nearest": str(nearest),
            "threshold": None if thresholds is None else float(thresholds[nearest]),
            "runner_up": runner, "margin": None if why else float(margin), "out_of_scope": why,
        })
        shown = f"{'-':>8}" if why else f"{margin:>7.2f}x"
        click.echo(f"{q!s:<{width}}  {lab:<16} {best:>10.4g} {runner:<18} {shown}")
    if json_path:
        Path(json_path).write_text(json.dumps({"descriptor": repr(desc), "results": rows}, indent=2))


def register(group: click.Group) -> None:
    """Add ``describe`` and ``classify`` to the CLI."""
    group.add_command(describe)
    group.add_command(classify)
