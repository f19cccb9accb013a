"""Time of the full Table I benchmark (18 rows, grid search included) and where it goes.

Runs the protocol of docs/algorithms/table1-protocol.md on a dataset (default: the HPM replica)
after a warm-up on a small subset (so that numba compilation or cache loading is not counted),
prints the stage times and the split between descriptor computation and matching (DTW + distances),
and writes JSON (default ``benchmarks/results/table1.json``).

    python benchmarks/bench_table1.py [--data DIR] [--jobs N ...] [--methods all] [--json PATH]

``--jobs 1 2`` times both the in-process run (numba threads over all cores) and two joblib worker
processes. "descriptors" and "matching" are compute seconds summed over workers; "wall" is the
elapsed time of the whole run. The target on the 2-core development machine is under 60 s for
the whole table (17 paper rows + the recommended row, 16 contexts of the replica).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from dataclasses import replace
from pathlib import Path

from framefree.benchmark import load_benchmark_data, make_backend, parse_methods, run_benchmark
from framefree.benchmark.protocol import BenchmarkData
from framefree.descriptors import available_descriptors

HERE = Path(__file__).resolve().parent


def subset(data: BenchmarkData, per_gesture: int = 1) -> BenchmarkData:
    """A small copy of ``data`` (first trials of each gesture) for the warm-up run."""

    def first(trials):  # type: ignore[no-untyped-def]
        seen: dict[str, int] = {}
        out = []
        for t in trials:
            if seen.get(t.gesture, 0) < per_gesture:
                seen[t.gesture] = seen.get(t.gesture, 0) + 1
                out.append(t)
        return out

    return replace(data, models=first(data.models), train=first(data.train), test=first(data.test))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=None, help="dataset folder (default: the HPM replica)")
    ap.add_argument("--model-context", default="original_1")
    ap.add_argument("--methods", default="all")
    ap.add_argument(
        "--contexts", default=None, help="comma-separated query contexts (default: all on disk)"
    )
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--json", type=Path, default=HERE / "results" / "table1.json")
    args = ap.parse_args()

    load_at_start = os.getloadavg()
    contexts = args.contexts.split(",") if args.contexts else None
    t0 = time.perf_counter()
    data = load_benchmark_data(args.data, args.model_context, contexts)
    load_s = time.perf_counter() - t0
    specs = parse_methods(args.methods, available_descriptors())
    print(f"{data.root}: {data.summary()}; {len(specs)} rows; loading took {load_s:.1f} s")

    runs = []
    for jobs in args.jobs:
        with make_backend("joblib", jobs) as bk:
            run_benchmark(subset(data), specs, bk)  # warm-up: compile / load numba caches
            result = run_benchmark(data, specs, bk)
        t = result.timing
        rows = {
            r.spec.key: {
                "descriptor_s": round(r.descriptor_seconds, 3),
                "matching_s": round(r.matching_seconds, 3),
                "grid_points": len(r.grid),
            }
            for r in result.rows
        }
        run = {
            "backend": result.backend,
            "jobs": jobs,
            "wall_s": round(t["total"], 2),
            "stages_wall_s": {
                k: round(t[k], 2) for k in ("resample", "reparameterize", "grid", "test")
            },
            "compute_s": {
                "descriptors": round(t["descriptors"], 2),
                "matching": round(t["matching"], 2),
            },
            "rows": rows,
        }
        runs.append(run)
        c = run["compute_s"]
        share = 100 * c["descriptors"] / max(1e-9, c["descriptors"] + c["matching"])
        print(
            f"{result.backend}: {t['total']:.1f} s wall for {len(specs)} rows "
            f"(resample {t['resample']:.1f} s, reparameterize {t['reparameterize']:.1f} s, "
            f"grid search {t['grid']:.1f} s, test {t['test']:.1f} s); compute: descriptors "
            f"{c['descriptors']:.1f} s ({share:.0f} %), matching {c['matching']:.1f} s"
        )
        for key, r in rows.items():
            print(
                f"  {key:16s} descriptors {r['descriptor_s']:6.2f} s  matching {r['matching_s']:6.2f} s"
            )

    out = {
        "what": "full Table I benchmark (grid search + test), after a warm-up run",
        "data": data.root,
        "counts": {"models": len(data.models), "train": len(data.train), "test": len(data.test)},
        "contexts": data.contexts,
        "load_average_at_start": load_at_start,
        "load_s": round(load_s, 2),
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "platform": platform.platform(),
            "load_average_at_end": os.getloadavg(),
        },
        "runs": runs,
    }
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(out, indent=2) + "\n")
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
