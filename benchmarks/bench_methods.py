"""Cost per pose of the three live recognizers on the same stream: framefree's (``segments``), the
paper's (``paper``) and the practitioner's sliding-window baseline (``window``).

Each recognizer is built and calibrated first (not timed), warmed up, then every pose of one
stream is pushed and each ``push`` timed; classification is inline (on the pose path) for all
three, so the figures are what one pose costs where the work is done. Streams:

* ``replica``: a session of a held-out simulated person (gestures among everyday motion, 50 Hz),
  models the 35 *original_1* recordings of the HPM replica;
* ``sfinge``: with ``--sfinge DIR`` (the SFINGE3D folder, not part of framefree), one real
  sequence at 20 fps, models the dictionary's 144 examples of the four swipes.

Prints a table and writes JSON (default ``benchmarks/results/methods_cost.json``). Wall-clock
times depend on the machine and its load; tests never check them.

    .venv/bin/python benchmarks/bench_methods.py [--sfinge ../shared/data/sfinge_dev] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path
from typing import Any

import numpy as np

METHODS = ("segments", "paper", "window")
SWIPES = ("swipe_left", "swipe_right", "swipe_v", "swipe_o")


def _recognizer(method: str, trajs: list, labels: list) -> Any:
    from framefree.online import Recognizer
    from framefree.online.paper import PaperRecognizer
    from framefree.online.window_baseline import WindowSpotter

    cls = {"segments": Recognizer, "paper": PaperRecognizer, "window": WindowSpotter}[method]
    rec = cls.from_trajectories(trajs, labels)
    if hasattr(rec, "background"):
        rec.background = False
    rec.warmup()
    return rec


def _replica() -> tuple[list, list, Any, str]:
    from framefree.datasets.layout import load_model_recordings
    from framefree.replica import replica_path
    from framefree.replica.people import HELDOUT_PEOPLE, person
    from framefree.replica.people_streams import person_stream

    trajs, labels = load_model_recordings(replica_path(0), "original_1")
    item = person_stream(1, person(HELDOUT_PEOPLE[0]), n_gestures=20)
    return trajs, labels, item.traj, f"held-out person {HELDOUT_PEOPLE[0]}, 20 gestures"


def _sfinge(root: Path, sequence: str) -> tuple[list, list, Any, str]:
    from framefree.core.trajectory import Trajectory

    trajs, labels = [], []
    for g in SWIPES:
        for path in sorted((root / "templates" / g).glob("*.csv")):
            trajs.append(Trajectory.from_csv(path))
            labels.append(g)
    stream = Trajectory.from_csv(root / "streams" / f"{sequence}.csv")
    return trajs, labels, stream, f"SFINGE3D {sequence}"


def measure(rec: Any, traj: Any) -> dict[str, float]:
    """Time every ``push`` of ``traj`` (after a reset); milliseconds per pose."""
    rec.reset()
    cost = np.empty(len(traj))
    for k in range(len(traj)):
        a = time.perf_counter()
        rec.push(traj.t[k], traj.p[k], traj.q[k])
        cost[k] = time.perf_counter() - a
    ms = cost * 1e3
    return {"poses": len(traj), "mean_ms": float(ms.mean()), "median_ms": float(np.median(ms)),
            "p99_ms": float(np.percentile(ms, 99)), "max_ms": float(ms.max()),
            "pose_period_ms": float(1e3 * np.median(np.diff(traj.t)))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sfinge", type=Path, default=None, help="the SFINGE3D folder (optional)")
    ap.add_argument("--sequence", default="seq_19", help="SFINGE3D sequence to time")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--json", type=Path, default=Path("benchmarks/results/methods_cost.json"))
    args = ap.parse_args()
    methods = [m for m in args.methods.split(",") if m]
    bad = set(methods) - set(METHODS)
    if bad:
        ap.error(f"unknown methods {sorted(bad)}; choose from {', '.join(METHODS)}")
    data = {"replica": _replica()}
    if args.sfinge is not None:
        data["sfinge"] = _sfinge(args.sfinge, args.sequence)
    rows = []
    for name, (trajs, labels, traj, what) in data.items():
        for method in methods:
            rec = _recognizer(method, trajs, labels)
            r = {"data": name, "stream": what, "method": method, "models": len(labels),
                 **measure(rec, traj)}
            rows.append(r)
            print(f"{name:8s} {method:9s} {r['models']:4d} models: {r['mean_ms']:.3f} ms/pose "
                  f"(median {r['median_ms']:.3f}, p99 {r['p99_ms']:.2f}, max {r['max_ms']:.1f}; "
                  f"a pose every {r['pose_period_ms']:.0f} ms)", flush=True)
    out = {"benchmark": "cost per pose of the live recognizers (inline)", "results": rows,
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count(),
                       "load_average": list(os.getloadavg())}}
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(out, indent=2))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
