"""``framefree evaluate-stream``: event-level metrics of a live recognizer on labelled streams."""

from __future__ import annotations

import contextlib
import json
import time
from pathlib import Path
from typing import Any

import click

from ..core.posecsv import QUAT_ORDERS
from ..errors import FramefreeError
from ..labels import METHODS
from .inputs import writable_file, writable_folder
from .multi_cli import check_trackers, match_trackers
from .online import (
    _check_emit,
    _emit_option,
    _emitters,
    _human_to_stderr,
    _model_options,
    _recognizer,
    _rerun_view,
    _save_option,
    _seconds,
)

__all__ = ["evaluate_stream_cmd", "register"]


@click.command("evaluate-stream")
@click.argument("more_streams", nargs=-1, type=click.Path(exists=True, dir_okay=False),
                metavar="[STREAM]...")
@_model_options
@click.option("--stream", "streams", multiple=True,
              type=click.Path(exists=True, dir_okay=False),
              help="Stream CSV (with <name>_labels.csv beside it), one tracker or several "
              "(framefree's multi-tracker CSV); repeatable, or give the streams as arguments.")
@click.option("--quat-order", default="wxyz", show_default=True, type=click.Choice(QUAT_ORDERS),
              help="Quaternion column order of the stream files.")
@click.option("--tolerance", type=float, default=0.5, show_default=True,
              help="Seconds after a gesture's end during which its detection counts.")
@click.option("--json", "json_path", type=click.Path(dir_okay=False), default=None,
              help="Write all metrics and events to this JSON file.")
@click.option("--figures", type=click.Path(file_okay=False), default=None,
              help="Folder for one timeline figure per stream (PNG).")
@click.option("--compare/--no-compare", default=False, show_default=True,
              help="Also evaluate the other methods (default settings) on the same streams and "
              "report them side by side.")
@click.option("--gestures", "gesture_list", default=None, metavar="G1,G2,...",
              help="Evaluate these gestures only: only their models are used, and the streams' "
              "other labels count as non-gesture motion (a library file must hold exactly these).")
@click.option("--explain", is_flag=True, default=False,
              help="Say why each gesture was missed (the first stage of the spotter it did not "
              "pass, and the candidate that came closest) and what fired each false positive.")
@_emit_option
@_save_option
def evaluate_stream_cmd(more_streams: tuple[str, ...], models: str, model_context: str,
                        model_quat_order: str, units: str, streams: tuple[str, ...],
                        quat_order: str, tolerance: float, json_path: str | None,
                        figures: str | None, compare: bool, method: str,
                        emit: tuple[str, ...] = (), save_rrd: str | None = None,
                        gesture_list: str | None = None, explain: bool = False, **kw: Any):
    """Event-level precision, recall, F1, false positives per minute and latency on labelled streams
    (--stream FILE, repeatable, and/or STREAM arguments)."""
    from ..datasets.multi_models import holds_several_trackers
    from ..datasets.stream_files import load_stream

    streams = (*streams, *more_streams)
    if not streams:
        raise click.UsageError("give at least one labelled stream (--stream FILE)")
    if units != "m":
        raise click.BadParameter("labelled streams are read in metres", param_hint="--units")
    if json_path:
        writable_file(json_path, "--json")
    if save_rrd:
        writable_file(save_rrd, "--save")
    _check_emit(emit)
    err = _human_to_stderr(emit)
    if figures:
        writable_folder(figures, "--figures")
    gestures = [g.strip() for g in gesture_list.split(",") if g.strip()] if gesture_list else None
    loaded = [(path, *load_stream(path, quat_order=quat_order)) for path in streams]
    several = holds_several_trackers(models)
    if explain and method != "segments":
        raise click.BadParameter("only --method segments can explain its misses: the other "
                                 "recognizers form no candidates", param_hint="--explain")
    if several and (compare or method != "segments"):
        raise FramefreeError("--compare and --method paper: the paper's recognizer takes one "
                             "tracker, and these models have several")
    for path, traj, _ in loaded:
        check_trackers(several, getattr(traj, "n_trackers", 1), path)
    if gestures:
        loaded = [(path, traj, [s for s in segs if s.label in gestures]) for path, traj, segs in loaded]
    rec = _recognizer(models, model_context, model_quat_order, units, method, gestures, **kw)
    loaded = [(path, match_trackers(rec, traj, path), segs) for path, traj, segs in loaded]
    _note_unknown_labels(rec, loaded, models, err)
    out = _emitters(emit, rec)
    rview = _rerun_view(rec, False, save_rrd)
    try:
        total, per_stream = _evaluate(rec, loaded, tolerance, figures, out, rview, err=err,
                                      explain=explain)
    finally:
        if out is not None:
            out.close()
        if rview is not None:
            rview.close()
    out = {"total": total, "streams": per_stream, "recognizer": rec.describe(), "method": method,
           "tolerance_s": tolerance}
    if compare:
        totals = [(method, total)]
        for other in (m for m in METHODS if m != method):
            rec2 = _recognizer(models, model_context, model_quat_order, units, other, gestures)
            total2, per_stream2 = _evaluate(rec2, loaded, tolerance, None, err=err)
            out.setdefault("compare", {"method": other, "total": total2, "streams": per_stream2,
                                       "recognizer": rec2.describe()})
            out.setdefault("compare_all", {})[other] = {"total": total2, "streams": per_stream2,
                                                        "recognizer": rec2.describe()}
            totals.append((other, total2))
        for name, t in totals:
            click.echo(f"{name:>9}: precision {t['precision']:.3f} recall {t['recall']:.3f} "
                       f"F1 {t['f1']:.3f} FP {t['fp']} FP/min {t['fp_per_minute']:.3f}", err=err)
    if json_path:
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        Path(json_path).write_text(json.dumps(out, indent=2, default=float))


def _note_unknown_labels(rec: Any, loaded: list, models: str, err: bool) -> None:
    """One line when the streams label gestures the recognizer does not know: they count as
    misses, which ``--gestures`` avoids."""
    from ..online.events import STOP

    known = {*getattr(rec, "gestures", ()), STOP}
    unknown = sorted({s.label for _, _, segs in loaded for s in segs} - known)
    if unknown:
        click.echo(f"note: the streams label {', '.join(unknown)}, which {models} does not hold: "
                   "they count as misses (--gestures G1,G2,... evaluates only some gestures, the "
                   "streams' other labels then counting as non-gesture motion)", err=True)


def _evaluate(rec: Any, loaded: list, tolerance: float, figures: str | None, emit: Any = None,
              rview: Any = None, err: bool = False, explain: bool = False) -> tuple[dict, dict]:
    """Run ``rec`` over every loaded ``(path, traj, segments)``; print (on stderr when ``err``)
    and return the pooled and per-stream metrics (with ``explain``, why each miss and false
    positive happened: :mod:`framefree.online.diagnosis`)."""
    from ..online.diagnosis import explain as explain_misses
    from ..online.diagnosis import logging_candidates
    from ..online.evaluation import combine, match_events, per_gesture, plot_timeline, run_stream

    per_stream = {}
    results = []
    reasons: dict[str, int] = {}
    for path, traj, segs in loaded:
        t0 = time.perf_counter()
        with logging_candidates(rec) if explain else contextlib.nullcontext() as log:
            events, trace = run_stream(rec, traj, rview)
        wall = time.perf_counter() - t0
        for ev in events if emit is not None else ():
            emit(ev)
        res = match_events(events, segs, float(traj.t[-1] - traj.t[0]), tolerance)
        results.append(res)
        click.echo(f"{Path(path).name}: TP {res.tp} FP {res.fp} FN {res.fn}  P {res.precision:.3f} "
                   f"R {res.recall:.3f} F1 {res.f1:.3f}  ({wall:.1f} s for {len(traj)} poses)",
                   err=err)
        per_stream[str(path)] = {**res.summary(), "events": res.details, "missed": res.missed,
                                 "stats": dict(rec.stats), "wall_s": wall}
        if explain:
            why = explain_misses(res, segs, log, rec.labels, rec.spotter)
            per_stream[str(path)]["explain"] = why
            for miss in why["missed"]:
                reasons[miss["reason"]] = reasons.get(miss["reason"], 0) + 1
            _print_explanation(why, err)
        if figures:
            fig = plot_timeline(Path(figures) / f"{Path(path).stem}_timeline.png", segs, events,
                                trace, rec.gesture_thresholds, title=Path(path).name)
            per_stream[str(path)]["figure"] = str(fig)
    total = combine(results).summary()
    total["gestures"] = per_gesture(results)
    _print_gestures(total["gestures"], err)
    click.echo(
        f"all: TP {total['tp']} FP {total['fp']} FN {total['fn']}  precision {total['precision']:.3f} "
        f"recall {total['recall']:.3f} F1 {total['f1']:.3f}  FP/min {total['fp_per_minute']:.3f}  "
        f"latency after end: median {_seconds(total['latency_median_s'])}", err=err
    )
    if explain:
        total["miss_reasons"] = reasons
        click.echo("misses by reason: " + (", ".join(f"{k} {v}" for k, v in reasons.items())
                                           or "none"), err=err)
    return total, per_stream


def _candidate_text(c: dict | None, label: str = "") -> str:
    if c is None:
        return "the stop detector" if label == "stop" else ""
    travel = "" if c["travel_m"] is None else f" travel {c['travel_m']:.2f} m"
    return (f"{c['start_t']:.2f}-{c['end_t']:.2f} s nearest {c['gesture']} at {c['ratio']:.2f} τ, "
            f"size {c['size_m']:.2f} m{travel}")


def _print_explanation(why: dict, err: bool = False) -> None:
    """One line per miss and per false positive of a stream (:func:`~framefree.online.diagnosis.explain`)."""
    for m in why["missed"]:
        limits = f" ({', '.join(m['limits'])})" if m.get("limits") else ""
        click.echo(f"  missed {m['label']} {m['start_t']:.2f}-{m['end_t']:.2f} s: {m['reason']}"
                   f"{limits}  {_candidate_text(m['candidate'])}", err=err)
    for f in why["false_positives"]:
        during = f" during {', '.join(f['overlaps'])}" if f["overlaps"] else ""
        click.echo(f"  false {f['label']} at {f['time']:.2f} s{during}  "
                   f"{_candidate_text(f['candidate'], f['label'])}", err=err)


def _print_gestures(table: dict[str, dict], err: bool = False) -> None:
    """One line per gesture: its counts and latency after its end (on stderr when ``err``)."""
    for g, row in table.items():
        click.echo(f"  {g:>16}: TP {row['tp']:3d} FP {row['fp']:3d} FN {row['fn']:3d}  "
                   f"F1 {row['f1']:.3f}  latency median {_seconds(row['latency_median_s'])}", err=err)


def register(group: click.Group) -> None:
    """Add ``evaluate-stream`` to the ``framefree`` command."""
    group.add_command(evaluate_stream_cmd)
