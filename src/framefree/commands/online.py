"""``framefree stream``, ``framefree live`` and ``framefree evaluate-stream``."""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import click

__all__ = ["register"]


def _model_options(f):
    opts = [
        click.option("--models", "models", required=True, type=click.Path(exists=True),
                     help="Dataset folder <gesture>/<context>/*.csv with the model recordings, or a "
                          "gesture library file from `framefree enroll` (no recalibration)."),
        click.option("--model-context", default="original_1", show_default=True,
                     help="Context folder holding the model recordings."),
        click.option("--threshold", type=float, default=None,
                     help="Decision threshold (default: automatic calibration)."),
        click.option("--stop-threshold", type=float, default=None,
                     help="Stop threshold on |dq/dt| [1/s] (default: from the model recordings)."),
        click.option("--L", "L", type=float, default=None, help="Scale length [m]."),
        click.option("--ds-scale", type=float, default=None, help="BILTS+ window scale [m]."),
        click.option("--resolution", type=float, default=None,
                     help="Screw-path resolution [m] (default: automatic)."),
        click.option("--latency-min", type=click.Choice(["0", "1"]), default=None,
                     help="Smallest latency searched (default 1)."),
    ]
    for o in reversed(opts):
        f = o(f)
    return f


def _recognizer(models: str, model_context: str, **kw: Any):
    from ..online import Recognizer

    overrides = {k: v for k, v in kw.items() if v is not None}
    if "latency_min" in overrides:
        overrides["latency_min"] = int(overrides["latency_min"])
    t0 = time.perf_counter()
    if Path(models).is_file():  # a gesture library (framefree.library): thresholds stored
        if overrides:
            raise click.UsageError(f"--{next(iter(overrides)).replace('_', '-')} does not apply to a library "
                                   "file; set it when enrolling: framefree enroll ... --set KEY=VALUE")
        click.echo(f"loading gesture library {models} ...", err=True)
        rec = Recognizer.load(models)
    else:
        click.echo(f"building models from {models}/<gesture>/{model_context} ...", err=True)
        rec = Recognizer.from_dataset(models, model_context=model_context, **overrides)
    rec.warmup()
    taus = list(rec.gesture_thresholds.values())
    click.echo(
        f"{len(rec.labels)} models, {len(rec.gestures)} gestures, "
        f"thresholds {min(taus):.4g}–{max(taus):.4g}, stop above {rec.stop_threshold:.3g} rad/s "
        f"({time.perf_counter() - t0:.1f} s)",
        err=True,
    )
    return rec


def _bar(d: float, threshold: float, width: int = 6) -> str:
    if not math.isfinite(d):
        return "·" * width
    # full bar at the threshold, empty at 10× the threshold (log scale)
    x = 1.0 - min(max(math.log10(max(d, 1e-12) / threshold), 0.0), 1.0)
    n = round(x * width)
    return "█" * n + "·" * (width - n)


@click.command("stream")
@click.argument("file", type=click.Path(exists=True, dir_okay=False))
@click.option("--port", type=int, default=5556, show_default=True, help="Port on 127.0.0.1.")
@click.option("--rate", type=float, default=None,
              help="Samples per second (default: follow the file's time stamps).")
@click.option("--speed", type=float, default=1.0, show_default=True,
              help="Replay speed factor when following time stamps (0: as fast as possible).")
@click.option("--format", "fmt", type=click.Choice(["binary", "json"]), default="binary",
              show_default=True, help="Message format (binary: 8 little-endian float64).")
@click.option("--join-wait", type=float, default=1.0, show_default=True,
              help="Seconds to wait after binding before the first message (slow joiners).")
def stream_cmd(file: str, port: int, rate: float | None, speed: float, fmt: str, join_wait: float):
    """Publish a recording FILE over ZeroMQ on tcp://127.0.0.1:PORT (PUB, binds).

    \b
    Message: 8 little-endian float64 t,x,y,z,qw,qx,qy,qz (or JSON); an empty message ends it.
    In another terminal: framefree live --models DIR --source zmq://127.0.0.1:PORT
    """
    from ..online.sources import CsvReplay, ZmqPublisher

    src = CsvReplay(file, speed=speed, rate=rate)
    pub = ZmqPublisher(f"tcp://127.0.0.1:{port}", join_wait=join_wait, fmt=fmt)
    click.echo(f"publishing {len(src.traj)} poses of {file} on tcp://127.0.0.1:{port}", err=True)
    try:
        n = pub.publish(src)
    except KeyboardInterrupt:
        n = pub.sent
    finally:
        pub.close()
    click.echo(f"sent {n} poses", err=True)


@click.command("live")
@_model_options
@click.option("--source", required=True,
              help="zmq://127.0.0.1:PORT, a CSV file (replayed in real time), or 'openvr'.")
@click.option("--speed", type=float, default=1.0, show_default=True,
              help="Replay speed of a CSV source (0: as fast as possible).")
@click.option("--timeout", type=float, default=10.0, show_default=True,
              help="Stop after this many seconds without a pose (ZeroMQ).")
@click.option("--view/--no-view", default=True, show_default=True,
              help="Show a one-line live view of the per-gesture dissimilarities.")
@click.option("--robot", type=click.Choice(["none", "sim"]), default="none", show_default=True,
              help="sim: drive the simulated Panda (MuJoCo, block stacking) with the events.")
@click.option("--robot-plot", type=click.Path(dir_okay=False), default=None,
              help="With --robot sim: write the session figure (PNG) at the end.")
@click.option("--robot-settle", type=float, default=3.0, show_default=True,
              help="With --robot sim: simulated seconds after the last pose.")
def live_cmd(models: str, model_context: str, source: str, speed: float, timeout: float,
             view: bool, robot: str, robot_plot: str | None, robot_settle: float, **kw: Any):
    """Recognize gestures live from a pose source and print events as they happen.

    With ``--robot sim`` the events drive the simulated robot (issue 6): the simulation clock
    follows the stream's time stamps (time 0 = first pose) and every event acts at its time.
    """
    from ..online.sources import open_source

    sim = _robot_sim() if robot == "sim" else None
    rec = _recognizer(models, model_context, **kw)
    src = open_source(source, speed=speed, timeout=timeout)
    t0: float | None = None
    tty = view and sys.stdout.isatty()
    short = {g: g.replace("go_", "").replace("_gripper", "")[:6] for g in rec.gestures}
    n = 0
    last_view = 0.0
    try:
        for t, p, q in src:
            n += 1
            if sim is not None and t0 is None:
                t0 = float(t)
                sim = sim(t0)
            for ev in rec.push(t, p, q):
                if tty:
                    click.echo("\r\033[K", nl=False)
                d = "" if ev.is_stop else f"  d={ev.dissimilarity:.4g}  model {ev.model}"
                click.secho(f"{ev.time:9.2f} s  {ev.label.upper():<14}{d}", bold=True,
                            fg="red" if ev.is_stop else "green")
                if sim is not None:
                    sim.handle(ev)
            if sim is not None:
                sim.advance_to(float(t) - t0)
            now = time.perf_counter()
            if view and now - last_view > 0.1:
                last_view = now
                gd = rec.gesture_dissimilarities()
                line = " ".join(f"{short[g]} {_bar(v, rec.gesture_thresholds[g])}" for g, v in gd.items())
                if tty:
                    click.echo(f"\r\033[K{t:8.2f} s {line}", nl=False)
    except KeyboardInterrupt:
        pass
    if tty:
        click.echo()
    skipped = {k: v for k, v in rec.stats.items() if v and k not in ("samples", "accepted")}
    click.echo(f"{n} poses; {json.dumps(skipped)}", err=True)
    if sim is not None and t0 is not None:
        sim.advance_to(sim.time + robot_settle)
        log = sim.log()
        acted = sum(1 for d in log.decisions if d.accepted)
        click.echo(f"robot: {len(log.decisions)} events handled, {acted} changed the plan, "
                   f"{sim.time:.1f} s simulated", err=True)
        if robot_plot:
            from ..robot.render import plot_session

            click.echo(f"robot session figure: {plot_session(log, robot_plot)}", err=True)


def _robot_sim():
    """Factory ``time_offset -> RobotSim`` for ``--robot sim``; a clear error without MuJoCo.

    :mod:`framefree.robot.sim` is imported first: it chooses MuJoCo's GL backend (EGL without a
    display), which MuJoCo fixes at its first import.
    """
    try:
        from ..robot import sim as _sim
    except ImportError as exc:
        raise click.ClickException(f"--robot sim is not available: {exc}") from None
    try:
        _sim.import_mujoco()
    except _sim.SimulatorMissing as exc:
        raise click.ClickException(f"--robot sim: {exc}") from None
    from ..robot.scenario import STACKING_PLANNER, STACKING_SCENE, STACKING_START
    from ..robot.session import RobotSim

    def on_event(decision) -> None:
        ev = decision.event
        verdict = "->" if decision.accepted else "(ignored)"
        click.echo(f"{ev.time:9.2f} s  robot {verdict} {ev.label} [{decision.reason}]", err=True)

    def make(time_offset: float) -> RobotSim:
        return RobotSim(planner=STACKING_PLANNER, scene=STACKING_SCENE, q0=STACKING_START,
                        time_offset=time_offset, on_event=on_event)

    return make


@click.command("evaluate-stream")
@_model_options
@click.option("--stream", "streams", required=True, multiple=True,
              type=click.Path(exists=True, dir_okay=False),
              help="Stream CSV (with <name>_labels.csv beside it); repeatable.")
@click.option("--tolerance", type=float, default=0.5, show_default=True,
              help="Seconds after a gesture's end during which its detection counts.")
@click.option("--json", "json_path", type=click.Path(dir_okay=False), default=None,
              help="Write all metrics and events to this JSON file.")
@click.option("--figures", type=click.Path(file_okay=False), default=None,
              help="Folder for one timeline figure per stream (PNG).")
def evaluate_stream_cmd(models: str, model_context: str, streams: tuple[str, ...], tolerance: float,
                        json_path: str | None, figures: str | None, **kw: Any):
    """Event-level precision, recall, F1, false positives per minute and latency on labelled streams."""
    from ..online.evaluation import combine, match_events, plot_timeline, run_stream

    try:
        from ..datasets.streams import load_stream
    except ImportError:  # pragma: no cover - the dataset module ships with framefree
        raise click.ClickException("framefree.datasets is needed to read labelled streams") from None
    rec = _recognizer(models, model_context, **kw)
    per_stream = {}
    results = []
    for path in streams:
        traj, segs = load_stream(path)
        t0 = time.perf_counter()
        events, trace = run_stream(rec, traj)
        wall = time.perf_counter() - t0
        res = match_events(events, segs, float(traj.t[-1] - traj.t[0]), tolerance)
        results.append(res)
        s = res.summary()
        click.echo(f"{Path(path).name}: TP {res.tp} FP {res.fp} FN {res.fn}  P {res.precision:.3f} "
                   f"R {res.recall:.3f} F1 {res.f1:.3f}  ({wall:.1f} s for {len(traj)} poses)")
        per_stream[str(path)] = {**s, "events": res.details, "missed": res.missed,
                                 "stats": dict(rec.stats), "wall_s": wall}
        if figures:
            fig = plot_timeline(Path(figures) / f"{Path(path).stem}_timeline.png", segs, events,
                                trace, rec.gesture_thresholds, title=Path(path).name)
            per_stream[str(path)]["figure"] = str(fig)
    total = combine(results).summary()
    click.echo(
        f"all: TP {total['tp']} FP {total['fp']} FN {total['fn']}  precision {total['precision']:.3f} "
        f"recall {total['recall']:.3f} F1 {total['f1']:.3f}  FP/min {total['fp_per_minute']:.3f}  "
        f"latency after end: median {total['latency_median_s']} s"
    )
    if json_path:
        out = {"total": total, "streams": per_stream, "recognizer": rec.describe(),
               "tolerance_s": tolerance}
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        Path(json_path).write_text(json.dumps(out, indent=2, default=float))


def register(group: click.Group) -> None:
    """Add the online subcommands to the ``framefree`` command."""
    group.add_command(stream_cmd)
    group.add_command(live_cmd)
    group.add_command(evaluate_stream_cmd)
