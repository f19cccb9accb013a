"""``framefree enroll`` and ``framefree check`` with takes of several trackers.

A source is of several trackers when it is a folder of multi-tracker recordings
(``<gesture>/<recording>``, as ``framefree record`` writes them from a multi-tracker source, or
``<person>/<gesture>/<recording>``) or a library file of several trackers
(:mod:`framefree.library.multi_library`). Sources of one tracker and of several are never mixed.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import click

from ..errors import FramefreeError

__all__ = ["check_multi", "enroll_multi_sources", "is_multi_source"]

#: Settings of ``enroll`` that a library of several trackers does not use.
_SINGLE_ONLY = ("resolution", "latency_min", "ds_scale", "up")


def is_multi_source(sources: tuple[str, ...]) -> bool:
    """Whether the sources hold takes of several trackers (one clear error when they mix)."""
    from ..datasets.multi_models import holds_several_trackers

    several = [holds_several_trackers(s) for s in sources]
    if any(several) and not all(several):
        one = next(s for s, m in zip(sources, several, strict=True) if not m)
        many = next(s for s, m in zip(sources, several, strict=True) if m)
        raise FramefreeError(f"{one} holds takes of one tracker and {many} of several; a library "
                             "holds takes of the same trackers")
    return bool(several) and all(several)


def _gather(sources: tuple[str, ...], merge: tuple[str, ...]) -> tuple[Any, dict | None, str | None]:
    """Takes of every source, the settings and invariance of the first library file."""
    from ..library.multi_library import load_multi_library, read_multi_takes
    from ..library.store import combine_takes

    parts, settings, invariance = [], None, None
    for src in sources:
        if Path(src).is_dir():
            parts.append((str(src), read_multi_takes(src)))
            continue
        lib = load_multi_library(src)
        parts.append((str(src), lib.takes))
        if settings is None:
            settings, invariance = dict(lib.config), lib.invariance
    return combine_takes(parts, merge), settings, invariance


def enroll_multi_sources(sources: tuple[str, ...], out: str, context: str | None,
                         removals: tuple[str, ...], sets: dict[str, Any], merges: tuple[str, ...],
                         invariance: str | None, force: bool) -> None:
    """``framefree enroll`` of takes of several trackers: a library file of several trackers."""
    from ..library.long_rests import long_rest_findings
    from ..library.multi_library import enroll_multi, load_multi_library, multi_fingerprint
    from ..online.config import RecognizerConfig

    if context is not None:
        raise FramefreeError("--context does not apply to takes of several trackers "
                             "(<gesture>/<recording> or <person>/<gesture>/<recording>)")
    given = [k for k in _SINGLE_ONLY if k in sets]
    if given:
        raise FramefreeError(f"{', '.join(given)}: not a setting of a library of several trackers "
                             "(its vertical is +z, kept with --invariance gravity)")
    takes, settings, stored = _gather(sources, merges)
    if removals:
        takes = takes.without(removals)
    invariance = invariance or stored or "gravity"
    base = RecognizerConfig.from_dict(settings) if settings else RecognizerConfig()
    try:
        config = base.replace(**sets)
    except (TypeError, ValueError) as exc:  # an unknown name, or a value out of its range
        raise click.BadParameter(str(exc), param_hint="--set") from None
    old = load_multi_library(out) if Path(out).is_file() and not force else None
    if old is not None:
        if old.fingerprint == multi_fingerprint(takes, config, invariance):
            click.echo(f"{out} is up to date ({len(takes)} takes of {len(takes.gestures)} "
                       "gestures); nothing to do (--force recalibrates)", err=True)
            return
    click.echo(f"building models and calibrating thresholds for {len(takes)} takes of "
               f"{len(takes.gestures)} gestures, {len(takes.trackers)} trackers "
               f"({', '.join(takes.trackers)}), invariance {invariance} ...", err=True)
    t0 = time.perf_counter()
    lib = enroll_multi(takes, config, invariance, [str(Path(s).resolve()) for s in sources])
    path = lib.save(out)
    click.echo(lib.summary())
    for finding in long_rest_findings(lib):
        click.echo(f"note: {finding.message}", err=True)
    click.echo(f"wrote {path} ({time.perf_counter() - t0:.1f} s). Next: framefree check {path}; "
               f"framefree live --models {path} --source lsl://NAME", err=True)


def check_multi(library: str, out_dir: Path, seed: int, invariance: str | None) -> None:
    """``framefree check`` of takes of several trackers: the report, its JSON and figures."""
    from ..library.check import CheckSettings
    from ..library.figures import plot_distance_map, plot_take_gallery
    from ..library.multi_check import check_multi_takes
    from ..library.multi_library import load_multi_library, read_multi_takes
    from ..library.store import TakeSet
    from ..online.config import RecognizerConfig

    lib_path = Path(library).resolve()
    if lib_path.is_dir():
        takes, config = read_multi_takes(lib_path), RecognizerConfig()
        invariance = invariance or "gravity"
    else:
        lib = load_multi_library(lib_path)
        if invariance is not None and invariance != lib.invariance:
            raise FramefreeError(f"--invariance {invariance}: {library} was enrolled with "
                                 f"{lib.invariance}; enroll it again to change it")
        takes, config, invariance = lib.takes, lib.recognizer_config(), lib.invariance
    click.echo(f"checking {len(takes)} takes of {len(takes.gestures)} gestures, "
               f"{len(takes.trackers)} trackers, invariance {invariance} ...", err=True)
    settings = CheckSettings(seed=seed)
    report = check_multi_takes(takes, invariance, config, settings)
    if not lib_path.is_dir():
        from ..library.long_rests import long_rest_findings

        report.findings += long_rest_findings(lib)
    click.echo(report.format())
    stem = lib_path.stem
    files = {"report": out_dir / f"{stem}_check.json",
             "distances": plot_distance_map(report, out_dir / f"{stem}_distances.png", settings)}
    for k, name in enumerate(takes.trackers):
        one = TakeSet(tuple(s.trackers[k] for s in takes.takes), takes.labels, takes.names)
        files[f"gallery {name}"] = plot_take_gallery(one, out_dir / f"{stem}_gallery_{name}.png")
    files["report"].write_text(json.dumps({**report.to_dict(), "library": str(lib_path),
                                           "distances": report.distances.tolist()},
                                          indent=1, default=float))
    for name, path in files.items():
        click.echo(f"  {name:<10} {path}")
    if not report.ok:
        raise SystemExit(1)
