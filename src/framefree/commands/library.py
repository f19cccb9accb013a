"""``framefree record``, ``framefree enroll`` and ``framefree check``: your own gestures."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import click

__all__ = ["register"]

#: Seconds of stream time between two looks for finished takes while recording.
_POLL_PERIOD = 0.5


def _pose_source(spec: str, timeout: float):
    """Iterator of (t, p, q): a CSV file is read at once, anything else via ``open_source``."""
    from ..io.rosbag import is_bag

    path = Path(spec)
    if (path.suffix.lower() == ".csv" or path.is_file()) and not is_bag(spec.partition("#")[0]):
        from ..core.trajectory import Trajectory

        traj = Trajectory.from_csv(path)
        return zip(traj.t, traj.p, traj.q, strict=True)
    from ..io.sources import open_source

    return open_source(spec, speed=0.0, timeout=timeout)  # a bag is read as fast as possible


@click.command("record")
@click.option("--source", required=True,
              help="zmq://127.0.0.1:PORT (live, see `framefree stream`), lsl://NAME, a ROS 2 bag "
              "(BAG[#TOPIC]), 'openvr', or a CSV recording.")
@click.option("--gesture", required=True, help="Name of the gesture (folder name, e.g. wave).")
@click.option("--library", "library", required=True, type=click.Path(file_okay=False),
              help="Library folder; takes go to LIBRARY/GESTURE/CONTEXT/trial_<k>.csv.")
@click.option("--context", default="own", show_default=True, help="Context folder of the takes.")
@click.option("--takes", "max_takes", type=int, default=None, help="Stop after this many takes.")
@click.option("--timeout", type=float, default=10.0, show_default=True,
              help="Stop after this many seconds without a pose (live sources).")
@click.option("--min-rest", type=float, default=None, help="Shortest rest between takes [s] (0.9).")
@click.option("--margin", type=float, default=None, help="Rest kept before and after each take [s] (0.75).")
@click.option("--keep-all", is_flag=True,
              help="Keep every move as a take: also the moves back to the start between performances "
              "of an open stroke and small settling moves (left out by default).")
@click.option("--tracker-names", default=None, metavar="A,B",
              help="Names of the trackers of a live source of several trackers, in its order "
              "(default: the source's names, else tracker_0, tracker_1, ...).")
def record_cmd(source: str, gesture: str, library: str, context: str, max_takes: int | None,
               timeout: float, min_rest: float | None, margin: float | None, keep_all: bool,
               tracker_names: str | None = None):
    """Record takes of a gesture: perform it, rest a second, perform it again, ...

    \b
    Several trackers: a multi-tracker CSV file (t,NAME.x,...), an LSL stream of several trackers
    (lsl://NAME; lsl://NAME#K records tracker K alone), a ROS 2 bag with several pose topics
    (BAG#/right,/left) or ZeroMQ multi-tracker messages (zmq://127.0.0.1:PORT?trackers=N) are cut
    at the rests of all trackers together; the takes go to LIBRARY/GESTURE/trial_<k>.csv, a
    --models folder for live and evaluate-stream and a source of enroll.

    \b
    One long recording is cut into takes at the rests (frame-free motion speed), each trimmed to
    its motion with a short rest before and after, and written in the dataset layout.
    For a gesture that ends away from its start (a swipe, a Z), the move back to the start between
    performances is recognized and left out, with a line saying so; so are small settling moves.
    Two moves separated by a pause much shorter than your rests are one performance (a hesitation),
    unless the second goes back to the start by a shorter way than the first (a way back).
    Stop with Ctrl-C, --takes N, or by ending the stream.
    """
    from ..library.recorder import TakeRecorder
    from ..library.takes import TakeSettings, write_take
    from .multi_record import record_if_several

    changes = {k: v for k, v in (("min_rest", min_rest), ("margin", margin)) if v is not None}
    done, opened = record_if_several(source, gesture, library, TakeSettings(**changes), max_takes,
                                     timeout, tracker_names)
    if done:
        return
    recorder = TakeRecorder(TakeSettings(**changes), keep_all=keep_all)
    src = opened if opened is not None else _pose_source(source, timeout)
    click.echo(f"recording {gesture!r} from {source}: perform it, rest a second or two, perform it again "
               "... (Ctrl-C to stop)", err=True)
    written: list[Path] = []
    noted: list = []
    joined: list = []

    def save(found) -> None:
        while len(recorder.joined) > len(joined):
            first, second, _ = recorder.joined[len(joined)]
            joined.append(second)
            click.secho(f"the move at {second.onset:.1f}-{second.end:.1f} s followed the one at "
                        f"{first.onset:.1f}-{first.end:.1f} s after a pause much shorter than your "
                        "rests: joined as one performance", fg="yellow", err=True)
        while len(recorder.left_out) > len(noted):
            span, reason = recorder.left_out[len(noted)]
            noted.append(span)
            why = ("went back to where the last take began (the way back of an open stroke)"
                   if reason == "way back" else "is much smaller than the takes (settling the hand)")
            click.secho(f"the move at {span.onset:.1f}-{span.end:.1f} s {why}: not kept "
                        "(--keep-all keeps it)", fg="yellow", err=True)
        for span, take in found:
            path = write_take(take, library, gesture, context)
            written.append(path)
            click.secho(f"take {len(written)} recorded ({span.duration:.1f} s) — rest, then perform the next"
                        f"   [{path}]", fg="green", err=True)

    last = None
    try:
        for t, p, q in src:
            recorder.push(t, p, q)
            if last is None or t - last >= _POLL_PERIOD:
                last = t
                save(recorder.poll())
            if max_takes is not None and len(written) + recorder.pending >= max_takes:
                break
    except KeyboardInterrupt:
        pass
    if max_takes is None or len(written) < max_takes:
        save(recorder.finish()[: None if max_takes is None else max_takes - len(written)])
    folder = Path(library) / gesture / context
    total = len(list(folder.glob("*.csv"))) if folder.is_dir() else 0
    back = f"; {len(noted)} moves between takes left out" if noted else ""
    click.echo(f"{len(written)} takes of {gesture} written to {folder} ({total} there now{back}). "
               f"Next: framefree check {library}", err=True)
    if not written:
        raise click.ClickException("no take found: perform the gesture between rests of about a second")


def _multi_sources(sources: tuple[str, ...]) -> bool:
    """Whether the sources hold takes of several trackers (one line when they mix)."""
    from .multi_library_cli import is_multi_source

    return is_multi_source(sources)


_invariance_option = click.option(
    "--invariance", type=click.Choice(("full", "gravity")), default=None,
    help="Takes of several trackers only: what the comparison ignores (default gravity, which "
         "keeps the vertical, +z; full for a world of unknown vertical). Stored in the library.")


def _parse_sets(sets: tuple[str, ...]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in sets:
        key, sep, value = item.partition("=")
        if not sep:
            raise click.BadParameter(f"{item!r}: expected KEY=VALUE", param_hint="--set")
        try:
            out[key.strip()] = json.loads(value)
        except json.JSONDecodeError:
            out[key.strip()] = None if value.lower() == "none" else value
    return out


def _gather(sources: tuple[str, ...], context: str | None, merge: tuple[str, ...] = ()):
    """Takes of all sources (folders or library files) and the settings of the first library file.
    Two sources may not hold a gesture of one name unless it is in ``merge``, nor copies of a take."""
    from ..library.store import combine_takes, load_library, read_takes

    parts = []
    settings: dict[str, Any] | None = None
    for src in sources:
        if Path(src).is_dir():
            part = read_takes(src, context)
        else:
            lib = load_library(src)
            part = lib.takes
            settings = settings if settings is not None else dict(lib.settings)
        parts.append((str(src), part))
    return combine_takes(parts, merge), settings


def _changes(old, new) -> str:
    if old is None:
        return "new library"
    before, after = old.takes.counts(), new.counts()
    parts = [f"+{g} ({n})" for g, n in after.items() if g not in before]
    parts += [f"-{g}" for g in before if g not in after]
    parts += [f"{g} {before[g]}→{n} takes" for g, n in after.items() if g in before and before[g] != n]
    return "changes: " + (", ".join(parts) if parts else "same gestures and take counts")


@click.command("enroll")
@click.argument("sources", nargs=-1, required=True, type=click.Path(exists=True))
@click.option("-o", "--out", type=click.Path(dir_okay=False), default=None,
              help="Library file to write (default: FOLDER.npz beside a single source folder).")
@click.option("--context", default=None,
              help="Context folder to read in each gesture (default: own, else original_1, else the "
                   "only one).")
@click.option("--remove", "removals", multiple=True,
              help="Leave out a gesture (wave) or a take (wave/own/trial_3); repeatable.")
@click.option("--set", "sets", multiple=True,
              help="Recognizer setting KEY=JSON (a RecognizerConfig setting, descriptor setting "
                   "or constant, or a learned value to fix); repeatable.")
@click.option("--merge", "merges", multiple=True,
              help="Pool the takes of a gesture found in several sources (e.g. a second person's); "
                   "without it, one gesture name in two sources is an error. Repeatable.")
@click.option("--up", type=click.Choice(["+x", "-x", "+y", "-y", "+z", "-z"]), default=None,
              help="The axis of the takes' world that points up (+z: framefree's own frame, ROS; "
                   "+y: the OpenVR source, the replica). Then a Z is no N; the live world "
                   "must share that vertical. Default: no vertical, frame-free.")
@click.option("--force", is_flag=True, help="Recalibrate even if the library file is up to date.")
@_invariance_option
def enroll_cmd(sources: tuple[str, ...], out: str | None, context: str | None, removals: tuple[str, ...],
               sets: tuple[str, ...], merges: tuple[str, ...], up: str | None, force: bool,
               invariance: str | None = None):
    """Build the models and calibrate the thresholds once; write a library file for live use.

    \b
    SOURCES are library folders (<gesture>/<context>/trial_k.csv, <gesture>/<trial>.csv, or
    several people's <person>/<gesture>/<trial>.csv or <gesture>/<person>/<trial>.csv) and/or
    library files (.npz), merged.
    Takes of several trackers: folders <gesture>/<recording> (framefree record from a
    multi-tracker source) or <person>/<gesture>/<recording>, and their library files.
    Adding a gesture: framefree enroll lib.npz new_takes/ -o lib.npz
    Removing one:        framefree enroll lib.npz --remove wave -o lib.npz
    Then: framefree check / live / evaluate-stream / demo --models LIBRARY.npz
    """
    from ..library.long_rests import long_rest_findings
    from ..library.store import enroll, load_library
    from ..online.learned import split_settings
    from ..online.model_settings import takes_advice

    if out is None:
        if len(sources) != 1 or not Path(sources[0]).is_dir():
            raise click.UsageError("give the library file to write with -o/--out")
        folder = Path(sources[0]).resolve()
        out = str(folder.with_name(folder.name + ".npz"))
    if _multi_sources(sources):
        from .multi_library_cli import enroll_multi_sources

        extra = {"up": up} if up else {}
        enroll_multi_sources(sources, out, context, removals, {**_parse_sets(sets), **extra},
                             merges, invariance, force)
        return
    if invariance is not None:
        raise click.UsageError("--invariance applies to takes of several trackers; one tracker is "
                               "compared by BILTS+, invariant to every change of frame")
    takes, settings = _gather(sources, context, merges)
    if removals:
        takes = takes.without(removals)
    try:
        config, given = split_settings({**(settings or {}), **_parse_sets(sets),
                                        **({"up": up} if up else {})})
    except (TypeError, ValueError) as exc:
        raise click.BadParameter(str(exc), param_hint="--set") from None
    old = load_library(out) if Path(out).is_file() and not force else None
    if old is not None and old.fingerprint == _fingerprint(takes, {**config.to_dict(), **given}):
        click.echo(f"{out} is up to date ({len(takes)} takes of {len(takes.gestures)} gestures); "
                   "nothing to do (--force recalibrates)", err=True)
        return
    click.echo(f"{_changes(old, takes)}; building models and calibrating thresholds for "
               f"{len(takes)} takes of {len(takes.gestures)} gestures ...", err=True)
    t0 = time.perf_counter()
    lib = enroll(takes, config, built_from=[str(Path(s).resolve()) for s in sources], **given)
    path = lib.save(out)
    click.echo(lib.summary())
    for advice in takes_advice(takes.takes, config, lib.learned_settings(),
                               rest="rest_speed" not in given):
        click.echo(f"note: {advice}", err=True)
    for finding in long_rest_findings(lib):
        click.echo(f"note: {finding.message}", err=True)
    click.echo(f"wrote {path} ({time.perf_counter() - t0:.1f} s). Next: framefree check {path}; "
               f"framefree live --models {path} --source zmq://127.0.0.1:5556", err=True)


def _fingerprint(takes, settings: dict[str, Any]) -> str:
    from ..library.store import fingerprint

    return fingerprint(takes, settings)


@click.command("check")
@click.argument("library", type=click.Path(exists=True))
@click.option("--context", default=None, help="Context folder to read (library folders).")
@click.option("--out", type=click.Path(file_okay=False), default=".", show_default=True,
              help="Folder for the report (JSON) and figures; never inside the library.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random probes.")
@_invariance_option
def check_cmd(library: str, context: str | None, out: str, seed: int, invariance: str | None = None):
    """Can these gestures be told apart? Leave-one-out recognition, margins, robustness to frames
    and speed, closeness to stop signals and everyday motion, with advice.

    LIBRARY is a library folder or file, of one tracker or of several. For a library file of one
    tracker, its takes are also replayed through its recognizer: a take that fires another
    gesture holds a part that looks like that gesture; and a gesture whose takes lie as far
    apart as motion that is no gesture comes to them (its calibration found no gap) is named,
    and so is a take that rests far longer between its moves than any other (the spotter's
    limits leave it out: it may hold a second move). Exit status 1 when there is a problem.
    """
    from ..library.check import CheckSettings, check_takes
    from ..library.figures import plot_distance_map, plot_take_gallery
    from ..library.store import load_library, read_takes
    from ..online.config import RecognizerConfig

    lib_path = Path(library).resolve()
    out_dir = Path(out).resolve()
    if lib_path.is_dir() and (out_dir == lib_path or lib_path in out_dir.parents):
        raise click.UsageError(f"--out {out} is inside the library {library}; choose another folder")
    if _multi_sources((library,)):
        from .multi_library_cli import check_multi

        if context is not None:
            raise click.UsageError("--context does not apply to takes of several trackers")
        check_multi(library, out_dir, seed, invariance)
        return
    if invariance is not None:
        raise click.UsageError("--invariance applies to takes of several trackers")
    if lib_path.is_dir():
        takes, config = read_takes(lib_path, context), RecognizerConfig()
    else:
        lib = load_library(lib_path)
        takes, config = lib.takes, lib.recognizer_config()
    settings = CheckSettings(seed=seed)
    report = check_takes(takes, config, settings, progress=True)
    if not lib_path.is_dir():  # a built library: replay its takes through its recognizer
        from ..library.inside import fired_inside, inside_findings
        from ..library.long_rests import long_rest_findings
        from ..library.separation import separation_findings
        from ..library.store import load_recognizer

        rec = load_recognizer(lib_path)
        report.findings += inside_findings(fired_inside(rec, lib.takes, progress=True), lib.takes)
        report.findings += separation_findings(lib) + long_rest_findings(lib)
    click.echo(report.format())
    if not lib_path.is_dir():
        from ..online.model_settings import unseen_advice

        advice = unseen_advice(lib.learned_settings().unseen)
        if advice is not None:
            click.echo(f"note: {advice}")
    stem = lib_path.stem
    files = {
        "report": out_dir / f"{stem}_check.json",
        "distances": plot_distance_map(report, out_dir / f"{stem}_distances.png", settings),
        "gallery": plot_take_gallery(takes, out_dir / f"{stem}_gallery.png"),
    }
    files["report"].write_text(json.dumps({**report.to_dict(), "library": str(lib_path),
                                           "distances": report.distances.tolist()}, indent=1, default=float))
    for name, path in files.items():
        click.echo(f"  {name:<10} {path}")
    if not report.ok:
        raise SystemExit(1)


def register(group: click.Group) -> None:
    """Add ``record``, ``enroll`` and ``check`` to the CLI."""
    group.add_command(record_cmd)
    group.add_command(enroll_cmd)
    group.add_command(check_cmd)
