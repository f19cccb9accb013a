"""Exact pruning against vocabulary size: the live recognizer and the offline classifier, pruning
on and off side by side in one run.

Models: 7 HPM gestures × 5 takes performed by 1, 10, 100 (or 1000) simulated people of the replica
population (35, 350, 3 500, 35 000 distinct models; seeds 5000+, none of the development or held-out
people); thresholds and settings calibrated once on the replica's 35 ``original_1`` recordings.
Stream: a held-out person's session (gestures among everyday motion), at 50 Hz as recorded and
resampled to 120 Hz. One tracker (the live recognizer takes one).

Prints and writes ``benchmarks/results/pruning.json`` and ``docs/images/pruning.png``: mean and
p99 time per pose, time per pose sample that classifies candidates (mean, p99, max), and the
fraction of DTW cells computed; offline, time per query and cells, against the number of models.

    .venv/bin/python benchmarks/bench_pruning.py [--counts 35,350,3500] [--rates 50,120]
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


def _vocabulary(count: int, descriptor) -> tuple[list[np.ndarray], list[str]]:
    from framefree.datasets import GESTURES
    from framefree.replica import person, synthesize_gesture

    rng = np.random.default_rng(count)
    models, labels = [], []
    for k in range(-(-count // (5 * len(GESTURES)))):
        who = person(5000 + k)
        for g in GESTURES:
            for _ in range(5):
                models.append(descriptor.compute(synthesize_gesture(g, rng, person=who)))
                labels.append(g)
    return models[:count], labels[:count]


def _stream(rate: float):
    from framefree.replica.people import HELDOUT_PEOPLE, person
    from framefree.replica.people_streams import person_stream

    tr = person_stream(1, person(HELDOUT_PEOPLE[0]), n_gestures=20).traj
    if rate != 50:
        tr = tr.resampled(1.0 / rate)
    return tr


def _live(rec, tr) -> dict:
    rec.reset()
    cells0 = list(rec.classifier.cells)
    per_pose = np.empty(len(tr))
    classifies = np.zeros(len(tr), dtype=bool)
    events = []
    for k in range(len(tr)):
        a = time.perf_counter()
        events += rec.push(tr.t[k], tr.p[k], tr.q[k])
        per_pose[k] = time.perf_counter() - a
        classifies[k] = len(rec.observations) > 0
    cells = rec.classifier.cells[0] - cells0[0], rec.classifier.cells[1] - cells0[1]
    heavy = per_pose[classifies]
    return {
        "poses": len(tr), "classifying_poses": int(classifies.sum()),
        "mean_per_pose_ms": 1e3 * float(per_pose.mean()),
        "p99_per_pose_ms": 1e3 * float(np.percentile(per_pose, 99)),
        "mean_per_classifying_pose_ms": 1e3 * float(heavy.mean()) if heavy.size else 0.0,
        "p99_per_classifying_pose_ms": 1e3 * float(np.percentile(heavy, 99)) if heavy.size else 0.0,
        "max_per_pose_ms": 1e3 * float(per_pose.max()),
        "dtw_cells_fraction": cells[0] / cells[1] if cells[1] else None,
        "events": [(e.label, round(e.time, 3)) for e in events],
    }


def _offline(descriptor, models, labels, queries) -> dict:
    from framefree.core.pruning import ModelBank, pruned_nearest

    bank = ModelBank(models, descriptor.distance_spec())
    out = {}
    a = time.perf_counter()
    full = descriptor.distance_matrix(queries, models)
    out["unpruned_ms_per_query"] = 1e3 * (time.perf_counter() - a) / len(queries)
    a = time.perf_counter()
    found = [pruned_nearest(q, bank) for q in queries]
    out["pruned_ms_per_query"] = 1e3 * (time.perf_counter() - a) / len(queries)
    out["same_nearest"] = all(f.nearest == int(np.argmin(d)) for f, d in zip(found, full, strict=True))
    out["dtw_cells_fraction"] = sum(f.cells for f in found) / sum(f.full_cells for f in found)
    return out


def _print_live(rate: int, prune: bool, r: dict) -> None:
    print(f"  {rate:3d} Hz pruning {'on ' if prune else 'off'}: {r['mean_per_pose_ms']:.2f} ms/pose "
          f"(p99 {r['p99_per_pose_ms']:.2f}), classifying {r['mean_per_classifying_pose_ms']:.1f} ms "
          f"(p99 {r['p99_per_classifying_pose_ms']:.1f}, max {r['max_per_pose_ms']:.1f}), "
          f"cells {r['dtw_cells_fraction'] or 1:.2f}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--counts", default="35,350,3500")
    ap.add_argument("--rates", default="50,120")
    ap.add_argument("--json", default=str(ROOT / "benchmarks" / "results" / "pruning.json"))
    args = ap.parse_args()

    from framefree.datasets import GESTURES
    from framefree.datasets.layout import load_model_recordings
    from framefree.online import Recognizer
    from framefree.online.spotting import SegmentClassifier
    from framefree.replica import person, replica_path, synthesize_gesture

    trajs, labels = load_model_recordings(replica_path(0), "original_1")
    calibrated = Recognizer.from_trajectories(trajs, labels)
    descriptor = calibrated.classifier.descriptor
    rng = np.random.default_rng(1)
    queries = [descriptor.compute(synthesize_gesture(g, rng, person=person(9000 + k)))
               for k in range(3) for g in GESTURES]
    streams = {int(r): _stream(float(r)) for r in args.rates.split(",")}
    rows = []
    for count in (int(c) for c in args.counts.split(",")):
        a = time.perf_counter()
        models, model_labels = _vocabulary(count, descriptor)
        print(f"{count} models built in {time.perf_counter() - a:.0f} s", flush=True)
        row = {"models": count, "offline": _offline(descriptor, models, model_labels, queries), "live": {}}
        for rate, tr in streams.items():
            for prune in (False, True):
                rec = Recognizer(SegmentClassifier(descriptor, models, prune=prune), model_labels,
                                 calibrated.config)
                rec.warmup()
                row["live"][f"{rate} Hz, pruning {'on' if prune else 'off'}"] = r = _live(rec, tr)
                _print_live(rate, prune, r)
            on, off = row["live"][f"{rate} Hz, pruning on"], row["live"][f"{rate} Hz, pruning off"]
            row["live"][f"{rate} Hz, same events"] = on["events"] == off["events"]
        o = row["offline"]
        print(f"  offline: {o['unpruned_ms_per_query']:.1f} ms/query unpruned, "
              f"{o['pruned_ms_per_query']:.1f} pruned, cells {o['dtw_cells_fraction']:.2f}, "
              f"same nearest {o['same_nearest']}", flush=True)
        rows.append(row)
    out = {"benchmark": "exact pruning against vocabulary size", "rows": rows,
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count(),
                       "load_average": os.getloadavg()}}
    Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    _figure(rows, ROOT / "docs" / "images" / "pruning.png")
    print(f"wrote {args.json}")


def _figure(rows: list[dict], path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9, 3.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(1, 2)
    counts = [r["models"] for r in rows]
    for key, style in (("50 Hz, pruning off", "o--"), ("50 Hz, pruning on", "o-")):
        if key in rows[0]["live"]:
            ax1.plot(counts, [r["live"][key]["mean_per_classifying_pose_ms"] for r in rows], style,
                     label=f"mean, {key}")
            ax1.plot(counts, [r["live"][key]["p99_per_classifying_pose_ms"] for r in rows], style,
                     alpha=0.5, label=f"p99, {key}")
    ax1.set(xscale="log", yscale="log", xlabel="models", ylabel="time per classifying pose [ms]",
            title="Live: a pose where a movement unit ends")
    ax1.legend(fontsize=7)
    ax2.plot(counts, [r["offline"]["unpruned_ms_per_query"] for r in rows], "o--", label="unpruned")
    ax2.plot(counts, [r["offline"]["pruned_ms_per_query"] for r in rows], "o-", label="pruned")
    ax2.set(xscale="log", yscale="log", xlabel="models", ylabel="time per query [ms]",
            title="Offline 1-NN (BILTS+, recommended)")
    ax2.legend(fontsize=7)
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
