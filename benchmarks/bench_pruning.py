"""Real time against vocabulary size: exact pruning on and off, inline and in the background, one
and two trackers, 50 and 120 Hz.

Models: 7 HPM gestures × 5 takes performed by 1, 10, 100, 1000 simulated people of the replica
population (35, 350, 3 500, 35 000 distinct models; seeds 5000+, none of the development or held-out
people); thresholds and settings calibrated once on the replica's 35 ``original_1`` recordings.
Streams: sessions of held-out people (eight gestures among everyday motion), as recorded at
50 Hz and resampled to 120 Hz; with two trackers, two people's sessions side by side, one
recognizer each.

Two measurements:

* **cost** (as fast as the machine goes, classification inline): time per pose step (both
  trackers), per step that classifies candidates, and per movement unit; DTW cells computed. The
  lateness of each event is what a single-threaded loop fed at the source's rate would see: the
  steps queue behind a slow one (``finish_k = max(arrival_k, finish_{k-1}) + cost_k``).
* **real time** (``--realtime``, background classification): the poses are pushed at their time
  stamps on the wall clock; time per push, and each event's lateness, the wall time it was handed
  out minus the time its firing pose was due.

Prints and writes ``benchmarks/results/pruning.json`` and ``docs/images/pruning.png``.

    .venv/bin/python benchmarks/bench_pruning.py [--counts 35,350,3500,35000] [--rates 50,120]
        [--unpruned-up-to 3500] [--realtime 3500,35000] [--cache DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _vocabulary(count: int, descriptor, cache: Path | None) -> tuple[list[np.ndarray], list[str]]:
    from framefree.datasets import GESTURES
    from framefree.replica import person, synthesize_gesture

    path = None if cache is None else cache / f"vocabulary_{count}.npz"
    if path is not None and path.is_file():
        z = np.load(path)
        return np.split(z["data"], np.cumsum(z["lengths"])[:-1]), [str(s) for s in z["labels"]]
    rng = np.random.default_rng(count)
    models, labels = [], []
    for k in range(-(-count // (5 * len(GESTURES)))):
        who = person(5000 + k)
        for g in GESTURES:
            for _ in range(5):
                models.append(descriptor.compute(synthesize_gesture(g, rng, person=who)))
                labels.append(g)
    models, labels = models[:count], labels[:count]
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez(path, data=np.concatenate(models), lengths=[len(m) for m in models], labels=labels)
    return models, labels


def _streams(rate: float, trackers: int):
    from framefree.replica.people import HELDOUT_PEOPLE, person
    from framefree.replica.people_streams import person_stream

    out = []
    for k in range(trackers):
        tr = person_stream(1 + k, person(HELDOUT_PEOPLE[k]), n_gestures=8).traj
        out.append(tr if rate == 50 else tr.resampled(1.0 / rate))
    n = min(len(tr) for tr in out)
    return [(tr.t[:n] - tr.t[0], tr.p[:n], tr.q[:n]) for tr in out]


def _lateness(arrival: np.ndarray, cost: np.ndarray, fired_at: list[int]) -> list[float]:
    """Event lateness of a single-threaded loop fed at ``arrival`` (module docstring)."""
    finish = np.empty_like(arrival)
    done = -np.inf
    for k in range(arrival.size):
        done = max(arrival[k], done) + cost[k]
        finish[k] = done
    return [float(finish[k] - arrival[k]) for k in fired_at]


def _ms(x: np.ndarray, q: float | None = None) -> float:
    if x.size == 0:
        return 0.0
    return 1e3 * float(np.mean(x) if q is None else np.percentile(x, q))


def _cost(recs, streams) -> dict:
    """Inline, as fast as possible (module docstring)."""
    for rec in recs:
        rec.reset()
    t = streams[0][0]
    per_step = np.empty(t.size)
    classifying = np.zeros(t.size, dtype=bool)
    events, fired_at = [], []
    for k in range(t.size):
        a = time.perf_counter()
        for rec, (tt, p, q) in zip(recs, streams, strict=True):
            got = rec.push(tt[k], p[k], q[k])
            events += [(e.label, round(e.time, 3)) for e in got if not e.is_stop]
            fired_at += [k] * sum(not e.is_stop for e in got)
            classifying[k] |= len(rec.observations) > 0
        per_step[k] = time.perf_counter() - a
    cells = recs[0].classifier.cells  # the trackers' recognizers share one classifier
    late = _lateness(t, per_step, fired_at)
    heavy = per_step[classifying]
    units = sum(rec.stats["units"] for rec in recs)
    return {
        "poses_per_tracker": int(t.size),
        "mean_per_step_ms": _ms(per_step), "p99_per_step_ms": _ms(per_step, 99),
        "max_per_step_ms": _ms(per_step, 100),
        "classifying_steps": int(classifying.sum()),
        "mean_per_classifying_step_ms": _ms(heavy), "p99_per_classifying_step_ms": _ms(heavy, 99),
        "mean_per_unit_ms": 1e3 * float(heavy.sum()) / max(units, 1),
        "dtw_cells_fraction": cells[0] / cells[1] if cells[1] else None,
        "max_event_lateness_s": max(late, default=0.0),
        "events_later_than_0.1_s": sum(x > 0.1 for x in late),
        "events": sorted(events),
    }


def _realtime(recs, streams) -> dict:
    """Background classification, poses pushed at their time stamps (module docstring)."""
    for rec in recs:
        rec.reset()
        rec.background = True
    t = streams[0][0]
    push = np.empty(t.size)
    late, events = [], []
    start = time.perf_counter()
    try:
        for k in range(t.size):
            due = start + t[k]
            while time.perf_counter() < due:
                time.sleep(max(0.0, min(due - time.perf_counter(), 0.002)))
            a = time.perf_counter()
            got = []
            for rec, (tt, p, q) in zip(recs, streams, strict=True):
                got += rec.push(tt[k], p[k], q[k])
            now = time.perf_counter()
            push[k] = now - a
            for e in got:
                if not e.is_stop:
                    fired = start + t[np.searchsorted(t, e.time - 1e-9)]
                    late.append(now - fired)
                    events.append((e.label, round(e.time, 3)))
        for rec in recs:
            events += [(e.label, round(e.time, 3)) for e in rec.finish() if not e.is_stop]
    finally:
        for rec in recs:
            rec.close()
    return {
        "mean_per_step_ms": _ms(push), "p99_per_step_ms": _ms(push, 99),
        "max_per_step_ms": _ms(push, 100),
        "max_event_lateness_s": max(late, default=0.0),
        "events_later_than_0.1_s": sum(x > 0.1 for x in late),
        "events": sorted(events),
    }


def _recognizers(classifier_for, labels, config, trackers: int):
    from framefree.online import Recognizer

    recs = [Recognizer(classifier_for(), labels, *config) for _ in range(trackers)]
    recs[0].warmup()
    return recs


def _print(label: str, r: dict) -> None:
    extra = ""
    if "mean_per_unit_ms" in r:
        extra = (f", per unit {r['mean_per_unit_ms']:.1f} ms, classifying p99 "
                 f"{r['p99_per_classifying_step_ms']:.1f} ms, cells {r['dtw_cells_fraction'] or 1:.3f}")
    print(f"  {label}: {r['mean_per_step_ms']:.2f} ms/step (p99 {r['p99_per_step_ms']:.2f}, max "
          f"{r['max_per_step_ms']:.1f}){extra}; latest event {r['max_event_lateness_s']:.3f} s, "
          f"{r['events_later_than_0.1_s']} later than 0.1 s", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--counts", default="35,350,3500,35000")
    ap.add_argument("--rates", default="50,120")
    ap.add_argument("--trackers", default="1,2")
    ap.add_argument("--unpruned-up-to", type=int, default=3500,
                    help="largest vocabulary also run without pruning")
    ap.add_argument("--realtime", default="3500,35000",
                    help="vocabularies also replayed in real time in the background (120 Hz)")
    ap.add_argument("--cache", type=Path, default=None, help="folder to keep built vocabularies in")
    ap.add_argument("--json", default=str(ROOT / "benchmarks" / "results" / "pruning.json"))
    args = ap.parse_args()

    from framefree.datasets.layout import load_model_recordings
    from framefree.online import Recognizer
    from framefree.online.segment_classifier import SegmentClassifier
    from framefree.replica import replica_path

    trajs, labels = load_model_recordings(replica_path(0), "original_1")
    calibrated = Recognizer.from_trajectories(trajs, labels)
    descriptor = calibrated.classifier.descriptor
    rates = [int(r) for r in args.rates.split(",")]
    trackers = [int(n) for n in args.trackers.split(",")]
    realtime = {int(c) for c in args.realtime.split(",") if c}
    streams = {(r, n): _streams(float(r), n) for r in rates for n in trackers}
    rows = []
    for count in (int(c) for c in args.counts.split(",")):
        a = time.perf_counter()
        models, model_labels = _vocabulary(count, descriptor, args.cache)
        print(f"{count} models ({time.perf_counter() - a:.0f} s to build)", flush=True)
        row: dict = {"models": count, "cost": {}, "realtime": {}}
        for prune in ((False, True) if count <= args.unpruned_up_to else (True,)):
            clf = SegmentClassifier(descriptor, models, prune=prune)
            for rate in rates:
                for n in trackers:
                    key = f"{rate} Hz, {n} tracker{'s' if n > 1 else ''}, pruning {'on' if prune else 'off'}"
                    recs = _recognizers(lambda c=clf: c, model_labels,
                                        (calibrated.config, calibrated.learned_), n)
                    row["cost"][key] = r = _cost(recs, streams[(rate, n)])
                    _print(key, r)
        if count in realtime:
            clf = SegmentClassifier(descriptor, models, prune=True)
            for n in trackers:
                key = f"120 Hz, {n} tracker{'s' if n > 1 else ''}, background, real time"
                recs = _recognizers(lambda c=clf: c, model_labels,
                                    (calibrated.config, calibrated.learned_), n)
                row["realtime"][key] = r = _realtime(recs, streams[(120, n)])
                _print(key, r)
        row["same_events"] = all(
            v["events"] == row["cost"][k.replace("pruning off", "pruning on")]["events"]
            for k, v in row["cost"].items() if "pruning off" in k) and all(
            v["events"] == row["cost"][k.replace("background, real time", "pruning on")]["events"]
            for k, v in row["realtime"].items())
        rows.append(row)
    out = {"benchmark": "real time against vocabulary size", "rows": rows,
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count(),
                       "load_average_at_end": os.getloadavg()}}
    Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    _figure(rows, ROOT / "docs" / "images" / "pruning.png")
    print(f"wrote {args.json}")


def _figure(rows: list[dict], path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 3.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(1, 2)
    for key, style in (("120 Hz, 1 tracker, pruning off", "o--"), ("120 Hz, 1 tracker, pruning on", "o-"),
                       ("120 Hz, 2 trackers, pruning on", "s-")):
        have = [r for r in rows if key in r["cost"]]
        if have:
            counts = [r["models"] for r in have]
            ax1.plot(counts, [r["cost"][key]["mean_per_unit_ms"] for r in have], style, label=key)
            ax2.plot(counts, [r["cost"][key]["p99_per_step_ms"] for r in have], style, label=key)
    for key, style in (("120 Hz, 1 tracker, background, real time", "^:"),
                       ("120 Hz, 2 trackers, background, real time", "v:")):
        have = [r for r in rows if key in r["realtime"]]
        if have:
            ax2.plot([r["models"] for r in have], [r["realtime"][key]["p99_per_step_ms"] for r in have],
                     style, label=key)
    ax1.set(xscale="log", yscale="log", xlabel="models", ylabel="ms",
            title="Classifying one movement unit (mean)")
    ax2.axhline(1000 / 120, color="grey", lw=0.8)
    ax2.set(xscale="log", yscale="log", xlabel="models", ylabel="ms",
            title="p99 time per pose step (grey: 120 Hz period)")
    for ax in (ax1, ax2):
        ax.legend(fontsize=7)
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
