"""``framefree stream``, ``framefree live`` and ``framefree evaluate-stream``."""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import click

from ..core.posecsv import QUAT_ORDERS, UNITS
from ..errors import FramefreeError
from ..labels import METHODS
from .inputs import pose_file_options, read_models, writable_file
from .robot_live import finish_robot, robot_factory

__all__ = ["register"]


def _model_options(f):
    opts = [
        click.option("--models", "models", required=True, type=click.Path(exists=True),
                     help="A dataset root <gesture>/<context>/*.csv (see --model-context), a "
                     "folder of <label>/*.csv recordings, a folder of people "
                     "<person>/<label>/*.csv or <label>/<person>/*.csv (several people's "
                     "examples; the motions tell which level is the label), or a gesture library "
                     "file from `framefree enroll` (nothing recalibrated); for several trackers, a folder "
                     "of people <person>/<gesture>/<recording> or of <label>/<recording> "
                     "(Machete files or multi-tracker CSV)."),
        click.option("--model-context", default="original_1", show_default=True,
                     help="Context folder of the models when --models is a dataset root."),
        click.option("--model-quat-order", default="wxyz", show_default=True,
                     type=click.Choice(QUAT_ORDERS), help="Quaternion column order of the model files."),
        click.option("--units", default="m", show_default=True, type=click.Choice(tuple(UNITS)),
                     help="Unit of the positions of the models and of the pose source."),
        click.option("--method", type=click.Choice(METHODS), default="segments", show_default=True,
                     help="segments: framefree's recognizer (whole gestures spotted and classified "
                     "as offline); paper: the paper's recognizer (fixed windows); window: a "
                     "practitioner's baseline (sliding windows of palm positions, 1-NN by DTW, "
                     "a threshold)."),
        click.option("--threshold", type=float, default=None,
                     help="One decision threshold for every gesture (default: calibrated per gesture)."),
        click.option("--stop-threshold", type=float, default=None,
                     help="Stop threshold (segments: angular speed [rad/s]; paper: |dq/dt| [1/s]); "
                     "default: from the model recordings."),
        click.option("--L", "L", type=float, default=None, help="Scale length [m]."),
        click.option("--ds-scale", type=float, default=None, help="BILTS+ window scale [m]."),
        click.option("--resolution", type=float, default=None,
                     help="paper: screw-path resolution [m] (default: automatic)."),
        click.option("--latency-min", type=click.Choice(["0", "1"]), default=None,
                     help="paper: smallest latency searched (default: 0)."),
        click.option("--hand-frame/--no-hand-frame", "hand_frame", default=None,
                     help="segments, one tracker: whether the way the hand moves and turns in "
                     "the tracker's frame counts as evidence (default: it does; a motion that "
                     "moves or turns outside the cones of a gesture's takes must match it more "
                     "closely). "
                     "--no-hand-frame: nothing depends on how the tracker sits in the hand."),
        click.option("--invariance", type=click.Choice(INVARIANCES), default=None,
                     help="Models of several trackers only: what the offline classifier's "
                     "comparison ignores, as in evaluate-people (default: gravity, which needs "
                     "z up in the poses: multi-tracker CSV and Machete files are; full for a "
                     "world of unknown vertical)."),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


#: ``framefree.descriptors.canonical.INVARIANCES``, written out: importing it loads numba, which
#: ``framefree live --help`` must not (tests/online/test_multi_cli.py checks they agree)
INVARIANCES = ("full", "gravity")

#: Options that only the paper's recognizer has.
_PAPER_ONLY = ("resolution", "latency_min")


def _thresholds(rec: Any) -> str:
    """The decision thresholds in force: one per gesture, or the single one."""
    per_gesture = rec.gesture_thresholds
    values = set(per_gesture.values())
    if len(values) == 1:
        return f"threshold {values.pop():.4g}"
    return "thresholds " + ", ".join(f"{g} {per_gesture[g]:.4g}" for g in rec.gestures)


def _stop_and_resolution(rec: Any) -> str:
    if getattr(rec, "method", "paper") == "segments":
        return f"stop above {rec.stop_threshold:.3g} rad/s"
    if getattr(rec, "method", "paper") == "window":
        durations = ", ".join(f"{d:.2f}" for d in rec.config.durations)
        return (f"stop above {rec.stop_threshold:.3g} rad/s, windows of {durations} s every "
                f"{rec.config.stride:g} s")
    return (f"stop |dq/dt| > {rec.stop_threshold:.3g}/s, resolution "
            f"{rec.models.resolution:.4g} m")


def _recognizer(models: str, model_context: str, model_quat_order: str, units: str,
                method: str = "segments", gestures: list[str] | None = None, **kw: Any):
    from ..online import Recognizer
    from ..online.paper import PaperRecognizer
    from ..online.window_baseline import WindowSpotter

    overrides = {k: v for k, v in kw.items()
                 if v is not None and (v is not False or k == "hand_frame")}
    invariance = overrides.pop("invariance", None)
    if "hand_frame" in overrides and method != "segments":
        flag = "--hand-frame" if overrides["hand_frame"] else "--no-hand-frame"
        raise FramefreeError(f"{flag} applies to --method segments")
    if method == "window":
        given = [k for k in overrides if k not in ("threshold", "stop_threshold")]
        if given:
            names = ", ".join("--" + k.replace("_", "-") for k in given)
            raise FramefreeError(f"{names} do not apply to --method window")
    if method == "segments":
        given = [k for k in _PAPER_ONLY if k in overrides]
        if given:
            names = ", ".join("--" + k.replace("_", "-") for k in given)
            raise FramefreeError(f"{names} only apply to --method paper")
    if "latency_min" in overrides:
        overrides["latency_min"] = int(overrides["latency_min"])
    if Path(models).is_file():
        if invariance is not None:
            overrides["invariance"] = invariance  # refused below, as every other setting
        return _library_recognizer(models, method, overrides, gestures)
    from ..datasets.multi_models import find_multi_models

    multi = find_multi_models(models)
    if multi is not None:  # several trackers: framefree.commands.multi_cli
        from .multi_cli import multi_recognizer

        return multi_recognizer(multi, method, gestures, overrides, models,
                                invariance or "gravity")
    if invariance is not None:
        raise FramefreeError("--invariance applies to models of several trackers; one tracker is "
                             "compared by BILTS+, invariant to every change of frame")
    found = read_models(models, model_context, model_quat_order, units)
    if gestures:
        found = _only(found, gestures, models)
    click.echo(f"building the gesture models ({method} method) and calibrating ...", err=True)
    t0 = time.perf_counter()
    cls = {"segments": Recognizer, "paper": PaperRecognizer, "window": WindowSpotter}[method]
    rec = cls.from_trajectories(found.trajectories, found.labels, **overrides)
    rec.warmup()
    click.echo(
        f"{len(rec.labels)} models, {len(rec.gestures)} gestures, {_thresholds(rec)}, "
        f"{_stop_and_resolution(rec)} ({time.perf_counter() - t0:.1f} s)",
        err=True,
    )
    if method == "segments":
        from ..online.model_settings import takes_advice

        for advice in takes_advice(found.trajectories, rec.config, rec.learned_):
            click.echo(f"note: {advice}", err=True)
    return rec


def _only(found: Any, gestures: list[str], models: str) -> Any:
    """The model recordings of ``gestures`` only (a one-line error naming any that has none)."""
    missing = [g for g in gestures if g not in set(found.labels)]
    if missing:
        raise FramefreeError(f"{models}: no model recordings of {', '.join(missing)} (it has "
                             f"{', '.join(sorted(set(found.labels)))})")
    keep = [k for k, g in enumerate(found.labels) if g in gestures]
    return dataclasses.replace(found, trajectories=[found.trajectories[k] for k in keep],
                               labels=[found.labels[k] for k in keep])


def _library_recognizer(path: str, method: str, overrides: dict[str, Any],
                        gestures: list[str] | None = None):
    """A recognizer from a gesture library file (:mod:`framefree.library`): no calibration.
    ``gestures`` (``--gestures``) must be the library's own."""
    from ..datasets.multi_models import is_multi_library
    from ..online import Recognizer

    if method != "segments" or overrides:
        given = (f"--method {method}" if method != "segments"
                 else "--" + next(iter(overrides)).replace("_", "-"))
        raise FramefreeError(f"{given} does not apply to a gesture library file; its settings are fixed "
                             "when enrolling (framefree enroll ... --set KEY=VALUE)")
    if is_multi_library(path):  # several trackers: framefree.commands.multi_cli
        from .multi_cli import library_multi_recognizer

        rec = library_multi_recognizer(path)
    else:
        click.echo(f"loading gesture library {path} ...", err=True)
        t0 = time.perf_counter()
        rec = Recognizer.load(path)
        rec.warmup()
        click.echo(f"{len(rec.labels)} models, {len(rec.gestures)} gestures, {_thresholds(rec)}, "
                   f"{_stop_and_resolution(rec)} ({time.perf_counter() - t0:.1f} s)", err=True)
    if gestures and sorted(set(gestures)) != sorted(rec.gestures):
        raise FramefreeError(
            f"--gestures {','.join(gestures)}: {path} holds {', '.join(sorted(rec.gestures))}; "
            "a library file's gestures are fixed when enrolling (framefree enroll LIBRARY "
            "--remove GESTURE -o OTHER.npz)")
    return rec


def _seconds(value: float | None) -> str:
    """A latency for people: ``0.05 s``, or ``-`` when there is none."""
    return "-" if value is None or not math.isfinite(value) else f"{value:.2f} s"


def _view_line(t: float, dissimilarities: dict[str, float], short: dict[str, str],
               thresholds: dict[str, float]) -> str:
    """One status line that fits the terminal: time, then a bar per gesture (shorter bars, then
    fewer gestures, on narrow terminals)."""
    columns = shutil.get_terminal_size((80, 24)).columns - 1
    head = f"{t:8.2f} s "
    items = list(dissimilarities.items())
    for width in (6, 4, 2):
        line = head + " ".join(f"{short[g]} {_bar(v, thresholds[g], width)}" for g, v in items)
        if len(line) <= columns:
            return line
    return line[:max(columns, 10)]


def _bar(d: float, threshold: float, width: int = 6) -> str:
    """Closeness of ``d`` to ``threshold`` as a bar: full at the threshold, empty at 10 times it."""
    if not math.isfinite(d):
        return "·" * width
    x = 1.0 - min(max(math.log10(max(d, 1e-12) / threshold), 0.0), 1.0)
    n = round(x * width)
    return "█" * n + "·" * (width - n)


@click.command("stream")
@click.argument("file", type=click.Path(exists=True, dir_okay=False))
@click.option("--port", type=click.IntRange(1, 65535), default=5556, show_default=True,
              help="Port on 127.0.0.1.")
@click.option("--rate", type=float, default=None,
              help="Samples per second (default: follow the file's time stamps).")
@click.option("--speed", type=float, default=1.0, show_default=True,
              help="Replay speed factor when following time stamps (0: as fast as possible).")
@click.option("--format", "fmt", type=click.Choice(["binary", "json"]), default="binary",
              show_default=True, help="Message format (binary: 8 little-endian float64).")
@click.option("--join-wait", type=float, default=1.0, show_default=True,
              help="Seconds to wait after binding before the first message (slow joiners).")
@pose_file_options
def stream_cmd(file: str, port: int, rate: float | None, speed: float, fmt: str, join_wait: float,
               quat_order: str, units: str, skip_header: bool):
    """Publish a recording FILE over ZeroMQ on tcp://127.0.0.1:PORT (PUB, binds).

    \b
    Message: 8 little-endian float64 t,x,y,z,qw,qx,qy,qz (or JSON); an empty message ends it.
    A multi-tracker CSV (t,NAME.x,...) sends every tracker in one message: t, then x,y,z,qw,qx,
    qy,qz of each tracker.
    In another terminal: framefree live --models DIR --source zmq://127.0.0.1:PORT
    """
    from ..core.trajectory import Trajectory
    from ..io.multicsv import has_tracker_header, read_multi_csv
    from ..io.sources import CsvReplay, ZmqPublisher

    if has_tracker_header(file):  # several trackers: one message carries them all
        traj = read_multi_csv(file)
    else:
        traj = Trajectory.from_csv(file, quat_order=quat_order, units=units,
                                   skip_header=skip_header)
    src = CsvReplay(traj, speed=speed, rate=rate)
    pub = ZmqPublisher(f"tcp://127.0.0.1:{port}", join_wait=join_wait, fmt=fmt)
    click.echo(f"publishing {len(src.traj)} poses of {file} on tcp://127.0.0.1:{port}", err=True)
    try:
        n = pub.publish(src)
    except KeyboardInterrupt:
        n = pub.sent
    finally:
        pub.close()
    click.echo(f"sent {n} poses", err=True)


_save_option = click.option(
    "--save", "save_rrd", type=click.Path(dir_okay=False), default=None,
    help="Record the rerun view to this .rrd file (no viewer opens); needs framefree[view].")

_emit_option = click.option(
    "--emit", "emit", multiple=True, metavar="SPEC",
    help="Also send every event to an output (repeatable): jsonl:- (stdout), jsonl:FILE, "
    "osc://HOST:PORT/ADDRESS, lsl://NAME (marker stream). See docs/io.md.")


@click.command("live")
@_model_options
@click.option("--source", required=True,
              help="zmq://127.0.0.1:PORT, lsl://NAME[#TRACKER], a ROS 2 bag BAG[#TOPIC], a CSV "
              "file (replayed in real time), or 'openvr[#DEVICE,...]'. With models of several "
              "trackers: a multi-tracker CSV file, lsl://NAME (all its trackers), or openvr "
              "(every controller and tracker, or the devices named).")
@click.option("--quat-order", default="wxyz", show_default=True, type=click.Choice(QUAT_ORDERS),
              help="Quaternion order of the source (a CSV file's columns or the messages).")
@click.option("--speed", type=float, default=1.0, show_default=True,
              help="Replay speed of a CSV source (0: as fast as possible).")
@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=10.0,
              show_default=True,
              help="ZeroMQ: give up after this many seconds without a pose (an error if none came).")
@click.option("--view", "view_kind", type=click.Choice(["terminal", "rerun"]), default="terminal",
              show_default=True, help="terminal: a one-line live view of the per-gesture "
              "dissimilarities; rerun: open a rerun viewer (trackers, speed, cuts, distances "
              "against thresholds, stop detector, events).")
@click.option("--no-view", is_flag=True, help="No terminal view.")
@_save_option
@click.option("--robot", type=click.Choice(["none", "sim", "dry-run", "franka"]), default="none",
              show_default=True,
              help="sim: drive the simulated Panda (MuJoCo, block stacking) with the events; "
              "dry-run: the planner's commands as JSON lines on stderr, no robot; franka: a "
              "Franka arm (FR3 or Panda) through franky at --robot-host (docs/robot.md).")
@click.option("--robot-host", default=None, metavar="HOST",
              help="With --robot franka: the arm's FCI address, or the address franky-sim "
              "reports (127.0.0.1 for the first simulator on this machine).")
@click.option("--robot-plot", type=click.Path(dir_okay=False), default=None,
              help="With --robot sim: write the session figure (PNG) at the end.")
@click.option("--robot-settle", type=float, default=3.0, show_default=True,
              help="With --robot sim: simulated seconds after the last pose.")
@click.option("--classify", type=click.Choice(["background", "inline"]), default=None,
              help="Where candidates are classified: on a worker thread, so that a large "
                   "vocabulary never stalls the source (default with --method segments), or "
                   "inline on the pose path (the paper's method always is). Same events.")
@_emit_option
def live_cmd(models: str, model_context: str, model_quat_order: str, units: str, source: str,
             quat_order: str, speed: float, timeout: float, robot: str,
             robot_plot: str | None, robot_settle: float, robot_host: str | None = None,
             emit: tuple[str, ...] = (),
             view_kind: str = "terminal", no_view: bool = False, save_rrd: str | None = None,
             classify: str | None = None, **kw: Any):
    """Recognize gestures live from a pose source and print events as they happen.

    With ``--robot sim`` the events drive the simulated robot: the simulation clock follows the
    stream's time stamps (time 0 = first pose) and every event acts at its time.
    """
    from ..datasets.multi_models import holds_several_trackers
    from ..io.sources import open_source
    from .multi_cli import check_trackers

    if robot_plot:
        writable_file(robot_plot, "--robot-plot")
    if save_rrd:
        writable_file(save_rrd, "--save")
    _check_emit(emit)
    err = _human_to_stderr(emit)
    view = view_kind == "terminal" and not no_view
    sim = robot_factory(robot, robot_host)
    # the source and the viewer are checked (a ZeroMQ subscriber connected, a rerun viewer on
    # 127.0.0.1 started) before the slow model building
    several = holds_several_trackers(models)
    src = open_source(source, speed=speed, timeout=timeout, quat_order=quat_order, units=units,
                      several=several)
    if not several:
        check_trackers(several, getattr(src, "n_trackers", 1), source)
    viewer = _start_viewer() if view_kind == "rerun" and not save_rrd else None
    rec = _recognizer(models, model_context, model_quat_order, units, **kw)
    _match_source(rec, src, source)
    if classify == "background" and not hasattr(rec, "background"):
        raise FramefreeError("--classify background needs --method segments")
    if hasattr(rec, "background"):
        rec.background = classify != "inline"
    out = _emitters(emit, rec)
    rview = _rerun_view(rec, view_kind == "rerun", save_rrd, viewer)
    try:
        n, t0, sim = _run_live(rec, src, view, sim, out, rview, err=err)
    finally:
        if out is not None:
            out.close()
        if rview is not None:
            rview.close()
    if n == 0 and getattr(src, "timed_out", False):
        raise FramefreeError(
            f"{source}: no pose arrived within {timeout:g} s; is a publisher running "
            "(framefree stream FILE --port PORT)? Raise --timeout to wait longer"
        )
    if getattr(src, "timed_out", False):
        click.echo(f"no pose for {timeout:g} s: stopped", err=True)
    skipped = {k: v for k, v in rec.stats.items() if v and k not in ("samples", "accepted")}
    click.echo(f"{n} poses; {json.dumps(skipped)}", err=True)
    if sim is not None and t0 is not None:
        finish_robot(sim, robot_settle, robot_plot)


def _match_source(rec: Any, src: Any, spec: str) -> None:
    """One clear error when the source brings other trackers than the models have; a replayed
    multi-tracker file gets its trackers in the models' order."""
    from .multi_cli import match_trackers, n_trackers

    inner = getattr(src, "source", src)
    if hasattr(inner, "expect"):  # ZeroMQ: every message must bring the models' trackers
        inner.expect(n_trackers(rec))
    have = getattr(src, "n_trackers", 1)
    if hasattr(src, "traj"):
        src.traj = match_trackers(rec, src.traj, spec)
    elif have != n_trackers(rec):
        raise FramefreeError(f"{spec}: {have} tracker(s), but the models have {n_trackers(rec)}")


def _check_emit(specs: tuple[str, ...]) -> None:
    """Catch a malformed ``--emit`` before the slow model building."""
    from ..io.outputs import check_spec

    for spec in specs:
        check_spec(spec)


def _human_to_stderr(specs: tuple[str, ...]) -> bool:
    """True when an ``--emit`` writes JSON lines to stdout: the human lines then go to stderr."""
    from ..io.outputs import to_stdout

    return to_stdout(specs)


def _emitters(specs: tuple[str, ...], rec: Any):
    """The ``--emit`` outputs (None when there are none)."""
    if not specs:
        return None
    from ..io.outputs import Emitters

    return Emitters(specs, rec.gesture_thresholds)


def _start_viewer() -> str:
    """A rerun viewer on 127.0.0.1 (its URL), or one line saying why none can start."""
    from ..view.viewer import start_viewer

    return start_viewer()


def _rerun_view(rec: Any, spawn: bool, save: str | None, url: str | None = None):
    """The rerun view (None unless ``--view rerun`` or ``--save``)."""
    if not spawn and not save:
        return None
    from ..view.rerun_view import RerunView

    return RerunView(rec, save=save, spawn=spawn, url=url)


def _run_live(rec: Any, src: Any, view: bool, sim: Any, emit: Any = None, rview: Any = None,
              err: bool = False) -> tuple[int, float | None, Any]:
    """Push every pose of ``src``; print events (and a live view) on stdout, or on stderr when
    ``err``. Returns (poses, t0, robot)."""
    t0: float | None = None
    tty = view and (sys.stderr if err else sys.stdout).isatty()
    short = {g: g.replace("go_", "").replace("_gripper", "")[:6] for g in rec.gestures}
    thresholds = rec.gesture_thresholds
    n = 0
    last_view = 0.0

    def deliver(events: list) -> None:
        for ev in events:
            if tty:
                click.echo("\r\033[K", nl=False, err=err)
            d = "" if ev.is_stop else f"  d={ev.dissimilarity:.4g}  model {ev.model}"
            click.secho(f"{ev.time:9.2f} s  {ev.label.upper():<14}{d}", bold=True,
                        fg="red" if ev.is_stop else "green", err=err)
            if emit is not None:
                emit(ev)
            if sim is not None:
                sim.handle(ev)

    try:
        for t, p, q in src:
            n += 1
            if sim is not None and t0 is None:
                t0 = float(t)
                sim = sim(t0)
            events = rec.push(t, p, q)
            if rview is not None:
                rview.update(t, p, q, events)
            deliver(events)
            if sim is not None:
                sim.advance_to(float(t) - t0)
            now = time.perf_counter()
            if tty and now - last_view > 0.1:
                last_view = now
                line = _view_line(t, rec.gesture_dissimilarities(), short, thresholds)
                click.echo(f"\r\033[K{line}", nl=False, err=err)
    except KeyboardInterrupt:
        if hasattr(sim, "halt"):  # Ctrl-C stops the arm at once
            sim.halt()
            click.echo("interrupted: robot stopped", err=True)
    finally:
        final = _finish(rec)
        if rview is not None:
            rview.log_events(final)
        deliver(final)
    if tty:
        click.echo(err=err)
    return n, t0, sim


def _finish(rec: Any) -> list:
    """Events the worker still held at the end of the stream; the worker is stopped."""
    if not getattr(rec, "background", False):
        return []
    events = rec.finish()
    rec.close()
    return events


def register(group: click.Group) -> None:
    """Add the online subcommands to the ``framefree`` command."""
    group.add_command(stream_cmd)
    group.add_command(live_cmd)

