"""What each kind of tracker fault costs the live recognizer, in F1 points.

The same streams of simulated people (``--people heldout`` by default: these numbers are reported,
nothing is chosen on them) are run clean and with one fault kind injected
(:mod:`framefree.replica.faults`: dropouts up to 0.5 s, ±8 ms time-stamp jitter, duplicated
samples, quaternion sign flips, single-sample 0.5 m outliers and orientation glitches, NaN samples),
each with its default parameters and a fixed seed per stream.

    .venv/bin/python benchmarks/online_faults.py --people heldout --per-person 1 \\
        --json benchmarks/results/online_faults.json
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from joblib import Parallel, delayed
from online_people import _parse_set, _recognizer

from framefree.online.evaluation import combine, match_events
from framefree.replica.faults import FAULT_KINDS, inject
from framefree.replica.people import DEV_PEOPLE, FRESH_PEOPLE, HELDOUT_PEOPLE
from framefree.replica.people_streams import make_person_streams


def _run(method: str, overrides: dict, item, kind: str):
    rec = _recognizer(method, overrides)
    tr = item.traj
    t, p, q = tr.t, tr.p, tr.q
    if kind != "clean":
        t, p, q = inject(kind, t, p, q, np.random.default_rng(item.stream_seed))
    rec.reset()
    events = []
    for k in range(t.shape[0]):
        events.extend(rec.push(t[k], p[k], q[k]))
    return kind, match_events(events, item.segments, tr.duration), dict(rec.stats)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--people", default="heldout", help="dev, heldout, fresh, or comma-separated seeds")
    ap.add_argument("--per-person", type=int, default=1)
    ap.add_argument("--method", default="segments", choices=["segments", "paper"])
    ap.add_argument("--set", action="append", default=[], help="recognizer setting KEY=VALUE")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    seeds = {"dev": DEV_PEOPLE, "heldout": HELDOUT_PEOPLE, "fresh": FRESH_PEOPLE}.get(args.people)
    if seeds is None:
        seeds = [int(s) for s in args.people.split(",")]
    overrides = _parse_set(args.set) if args.method == "segments" else {}
    t0 = time.perf_counter()
    items = make_person_streams(seeds, n_streams_per_person=args.per_person)
    kinds = ["clean", *FAULT_KINDS]
    rows = Parallel(n_jobs=args.jobs)(
        delayed(_run)(args.method, overrides, it, kind) for kind in kinds for it in items)
    out = {"people": args.people, "method": args.method, "settings": overrides, "faults": {}}
    clean = None
    for kind in kinds:
        res = combine([r for k, r, _ in rows if k == kind]).summary()
        clean = res if kind == "clean" else clean
        cost = 100 * (clean["f1"] - res["f1"])
        out["faults"][kind] = {**res, "f1_cost_points": cost}
        print(f"{kind:18s} P {res['precision']:.3f} R {res['recall']:.3f} F1 {res['f1']:.3f} "
              f"FP {res['fp']:3d}  cost {cost:+.1f} F1 points")
    print(f"wall {time.perf_counter() - t0:.0f} s")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
