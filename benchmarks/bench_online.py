"""Speed of the live recognizers: cost per pose sample, and per sample that does the heavy work.

``--method segments`` (framefree's recognizer, the default): the stream is a session of a held-out
simulated person (gestures among everyday motion); the heavy samples are those where a movement
unit ends and its candidate segments are classified against every model (DTW). ``--method paper``:
the stream is a concatenation of other-context recordings; the heavy samples are descriptor samples
(every matcher updated); the refractory reset is off so no event interrupts the matchers;
``--prune-factor none`` measures the unpruned matchers.

Models: the 35 *original_1* recordings of the HPM replica, replicated ×10 and ×100 for 350 and
3 500 models (copies of the same descriptors, with the thresholds calibrated once on the 35).

Usage::

    .venv/bin/python benchmarks/bench_online.py [--method segments|paper]
        [--json benchmarks/results/online_segments.json] [--threads N] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np


def _models_and_stream():
    from framefree.datasets.layout import load_model_recordings

    try:
        from framefree.replica.build import replica_path

        root = replica_path(0)
        trajs, labels = load_model_recordings(root, "original_1")
        from framefree.datasets import load_dataset

        ds = load_dataset(root)
        queries = [tr.trajectory for tr in ds.queries("all")][:40]
        origin = f"HPM replica {root.name}"
    except Exception as exc:  # pragma: no cover - fallback when the replica cannot be built
        from framefree.datasets import GESTURES
        from framefree.replica import synthesize_gesture

        rng = np.random.default_rng(0)
        trajs, labels = [], []
        for g in GESTURES:
            for _ in range(5):
                trajs.append(synthesize_gesture(g, rng))
                labels.append(g)
        queries = [synthesize_gesture(g, rng) for g in GESTURES for _ in range(5)]
        origin = f"synthetic gestures ({exc})"
    t, p, q = [], [], []
    t_end = 0.0
    for tr in queries:
        t.append(tr.t - tr.t[0] + t_end + 0.02)
        p.append(tr.p)
        q.append(tr.q)
        t_end = t[-1][-1] + 1.0  # a gap restarts the stream between queries
    return trajs, labels, np.concatenate(t), np.concatenate(p), np.concatenate(q), origin


def _measure(rec, t, p, q, repeat: int) -> dict:
    best = None
    for _ in range(repeat):
        rec.reset()
        per_pose = np.empty(len(t))
        had_desc = np.zeros(len(t), dtype=bool)
        for k in range(len(t)):
            a = time.perf_counter()
            rec.push(t[k], p[k], q[k])
            per_pose[k] = time.perf_counter() - a
            had_desc[k] = len(rec.observations) > 0
        r = {
            "pose_samples": len(t),
            "descriptor_samples": int(had_desc.sum()),
            "mean_per_pose_ms": float(per_pose.mean() * 1e3),
            "p99_per_pose_ms": float(np.percentile(per_pose, 99) * 1e3),
            "max_per_pose_ms": float(per_pose.max() * 1e3),
            "mean_pose_without_descriptor_ms": float(per_pose[~had_desc].mean() * 1e3),
            "mean_per_descriptor_sample_ms": float(per_pose[had_desc].mean() * 1e3),
            "p99_per_descriptor_sample_ms": float(np.percentile(per_pose[had_desc], 99) * 1e3),
        }
        if best is None or r["mean_per_pose_ms"] < best["mean_per_pose_ms"]:
            best = r
    return best


def _person_stream():
    from framefree.replica.people import HELDOUT_PEOPLE, person
    from framefree.replica.people_streams import person_stream

    item = person_stream(1, person(HELDOUT_PEOPLE[0]), n_gestures=20)
    tr = item.traj
    return tr.t, tr.p, tr.q


def _segments(trajs, labels, counts, repeat, threads):
    import numba

    from framefree.online import Recognizer
    from framefree.online.segment_classifier import SegmentClassifier

    calibrated = Recognizer.from_trajectories(trajs, labels)
    t, p, q = _person_stream()
    numba.set_num_threads(threads)
    results = []
    for count in counts:
        reps = -(-count // len(labels))
        models = (calibrated.classifier.models * reps)[:count]
        many = SegmentClassifier(calibrated.classifier.descriptor, models)
        rec = Recognizer(many, (list(labels) * reps)[:count], calibrated.config,
                         calibrated.learned_)
        rec.warmup()
        r = _measure(rec, t, p, q, repeat)
        r.update({"models": count, "threads": threads})
        results.append(r)
        print(f"{count:5d} models ({threads} threads): {r['mean_per_pose_ms']:.3f} ms/pose "
              f"(p99 {r['p99_per_pose_ms']:.3f}, max {r['max_per_pose_ms']:.1f}), "
              f"{r['mean_per_descriptor_sample_ms']:.3f} ms per classifying sample "
              f"({r['descriptor_samples']} of {r['pose_samples']})", flush=True)
    return calibrated.describe(), len(t), results


def _paper(trajs, labels, counts, repeat, threads, prune_factor, t, p, q):
    import numba

    from framefree.online.paper import PaperConfig, PaperRecognizer
    from framefree.online.paper.models import GestureModels

    cfg = PaperConfig()
    if prune_factor != "default":
        cfg = cfg.replace(prune_factor=None if prune_factor == "none" else float(prune_factor))
    calibrated = PaperRecognizer.from_trajectories(trajs, labels, cfg)
    models = calibrated.models
    cfg = calibrated.config.replace(stop_threshold=1e9, refractory_reset=False)
    results = []
    for count in counts:
        reps = -(-count // len(models))
        many = GestureModels((models.labels * reps)[:count], (models.descriptors * reps)[:count],
                             models.resolution)
        rec = PaperRecognizer(many, cfg, gesture_thresholds=calibrated.gesture_thresholds)
        numba.set_num_threads(1 if not rec.bank.parallel else threads)
        rec.warmup()
        r = _measure(rec, t, p, q, repeat)
        r.update({"models": count, "threads": 1 if not rec.bank.parallel else threads,
                  "kabsch_per_descriptor_sample": int(rec.bank.A.shape[0])})
        results.append(r)
        print(f"{count:5d} models ({r['threads']} thread{'s' if r['threads'] > 1 else ''}): "
              f"{r['mean_per_pose_ms']:.3f} ms/pose (p99 {r['p99_per_pose_ms']:.3f}), "
              f"{r['mean_per_descriptor_sample_ms']:.3f} ms/descriptor sample "
              f"(p99 {r['p99_per_descriptor_sample_ms']:.3f})", flush=True)
    return calibrated.describe(), len(t), results


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--method", choices=["segments", "paper"], default="segments")
    ap.add_argument("--json", default=None,
                    help="default: benchmarks/results/online_<method>.json")
    ap.add_argument("--threads", type=int, default=None, help="numba threads")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--counts", default="35,350,3500")
    ap.add_argument("--prune-factor", default="default",
                    help="paper: matcher pruning cutoff factor (a number, 'none', or the default)")
    args = ap.parse_args()

    import numba

    trajs, labels, t, p, q, origin = _models_and_stream()
    threads = args.threads or numba.config.NUMBA_NUM_THREADS
    counts = [int(c) for c in args.counts.split(",")]
    if args.method == "segments":
        described, n, results = _segments(trajs, labels, counts, args.repeat, threads)
        stream = f"held-out person session ({n} pose samples)"
    else:
        described, n, results = _paper(trajs, labels, counts, args.repeat, threads,
                                       args.prune_factor, t, p, q)
        stream = f"concatenated replica recordings ({n} pose samples)"
    out = {
        "benchmark": f"online recognizer ({args.method})",
        "models_from": origin,
        "stream": stream,
        "recognizer": described,
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "cpu_count": os.cpu_count(), "numba_threads_available": threads},
        "results": results,
    }
    path = Path(args.json or f"benchmarks/results/online_{args.method}.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(out, indent=2, default=float))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
