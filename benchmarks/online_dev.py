"""Development metrics of the paper's recognizer (PaperRecognizer) on dev streams of the replica.

The held-out test set is the replica's ``streams/stream_{1,2,3}`` (``make_stream(1..3)``). Every
parameter of :class:`framefree.online.paper.PaperConfig` is chosen here, on streams generated with
seeds 100-119 by :func:`framefree.replica.make_stream`, with the models and the automatic
calibration from the replica's ``original_1`` recordings.

Usage::

    .venv/bin/python benchmarks/online_dev.py [--set decision=first --set L=0.3 ...]
        [--seeds 100-119] [--jobs 2] [--verbose] [--json FILE]

``--set KEY=VALUE`` overrides a config field (VALUE parsed as JSON when possible).
"""

from __future__ import annotations

import argparse
import json
import time
from multiprocessing import get_context

import numpy as np

from framefree.online.evaluation import combine, match_events, run_stream
from framefree.online.paper import PaperRecognizer
from framefree.replica import make_stream, replica_path

_REC = None


def _one(seed: int):
    traj, segs = make_stream(seed)
    events, _ = run_stream(_REC, traj)
    res = match_events(events, segs, float(traj.t[-1] - traj.t[0]))
    return seed, res


def _r(x: float | None) -> float | None:
    return None if x is None else round(x, 3)


def _parse(kv: list[str]) -> dict:
    out = {}
    for item in kv:
        k, v = item.split("=", 1)
        try:
            out[k] = json.loads(v)
        except json.JSONDecodeError:
            out[k] = v
    return out


def main() -> None:
    global _REC
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--set", action="append", default=[], help="config override KEY=VALUE")
    ap.add_argument("--seeds", default="100-119")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    a, b = (int(x) for x in args.seeds.split("-"))
    seeds = list(range(a, b + 1))
    if min(seeds) < 100:
        raise SystemExit("dev seeds must be >= 100 (seeds 1-3 are the held-out test streams)")
    overrides = _parse(args.set)
    t0 = time.perf_counter()
    _REC = PaperRecognizer.from_dataset(replica_path(0), model_context="original_1", **overrides)
    _REC.warmup()
    build = time.perf_counter() - t0
    with get_context("fork").Pool(args.jobs) as pool:
        results = pool.map(_one, seeds)
    tot = combine([r for _, r in results]).summary()
    fps: dict[str, int] = {}
    misses: dict[str, int] = {}
    for seed, r in results:
        for d in r.details:
            if d["verdict"] != "tp":
                fps[d["label"]] = fps.get(d["label"], 0) + 1
        for m in r.missed:
            misses[m["label"]] = misses.get(m["label"], 0) + 1
        if args.verbose:
            bad = [(d["label"], round(d["time"], 1), d["verdict"]) for d in r.details if d["verdict"] != "tp"]
            miss = [(m["label"], round(m["start_t"], 1), round(m["end_t"], 1)) for m in r.missed]
            print(f"seed {seed}: TP {r.tp} FP {r.fp} FN {r.fn}  fp {bad}  missed {miss}")
    print(f"overrides {overrides}  (build {build:.1f} s)")
    print("thresholds", {g: round(v, 3) for g, v in _REC.gesture_thresholds.items()},
          "stop", round(_REC.stop_threshold, 3), "resolution", round(_REC.models.resolution, 5))
    print(f"DEV seeds {a}-{b}: TP {tot['tp']} FP {tot['fp']} FN {tot['fn']}  P {tot['precision']:.3f} "
          f"R {tot['recall']:.3f} F1 {tot['f1']:.3f}  FP/min {tot['fp_per_minute']:.3f}  "
          f"latency median {_r(tot['latency_median_s'])} s max {_r(tot['latency_max_s'])} s")
    print("  false positives by label", fps, " misses by label", misses)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"overrides": overrides, "total": tot, "fp_by_label": fps, "missed_by_label": misses,
                       "describe": _REC.describe()}, fh, indent=2, default=float)


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
