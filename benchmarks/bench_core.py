"""Speed of the core: BILTS+ descriptor of a 4-second trial and BILTS+ distance of one pair.

Prints a table and writes JSON (default ``benchmarks/results/core.json``). Numba kernels are
compiled (or loaded from the cache) and warmed up before timing; each figure is the median of many
repetitions on one core.

    python benchmarks/bench_core.py [--json PATH] [--repeat N]

For comparison: the authors' MATLAB reference under GNU Octave takes about 70-150 ms per descriptor
and 21 ms per distance on this kind of machine (issue 2).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np

import framefree as ff
from framefree.core import se3
from framefree.core.progress import reparameterize
from framefree.core.smoothing import smooth_poses

HERE = Path(__file__).resolve().parent
REAL = next(
    (p for p in (HERE.parent / "shared", HERE.parent.parent / "shared") if p.is_dir()), None
)


def four_second_trials() -> list[ff.Trajectory]:
    """Two 4-second trials: a window of a real kettle recording and a synthetic hand motion."""
    trials = []
    if REAL is not None:
        rec = ff.Trajectory.from_csv(REAL / "data/real_motions/kettle_pour_trial1_ref_com.csv")
        t0 = rec.t[0] + 3.0
        trials.append(rec.slice_time(t0, t0 + 4.0))
    t = np.arange(200) * 0.02
    s = 0.5 * (1 - np.cos(np.pi * t / 4))
    p = np.column_stack([0.3 * np.sin(2 * s), 0.2 * np.cos(3 * s), 0.25 * s])
    rv = np.column_stack([0.8 * np.sin(2 * s), 0.6 * s, 0.5 * np.cos(2 * s)])
    trials.append(ff.Trajectory(t, p, se3.quaternion_from_matrix(se3.rotation_from_vector(rv))))
    return trials


def median_time(fn, repeat: int) -> float:
    """Median wall time of ``fn()`` in seconds over ``repeat`` calls (after two warm-up calls)."""
    fn()
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, default=HERE / "results" / "core.json")
    parser.add_argument("--repeat", type=int, default=300)
    args = parser.parse_args()

    desc = ff.get_descriptor("bilts+", progress="screw", L=0.5, ds_scale=0.09)
    trials = four_second_trials()
    seqs = [desc.compute(t) for t in trials]
    traj = trials[0]
    rep = reparameterize(traj, "screw", desc.L)

    stages = {
        "resample_50hz": lambda: traj.resampled(0.02),
        "reparameterize_screw": lambda: reparameterize(traj, "screw", desc.L),
        "smooth_and_twists": lambda: se3.central_spatial_twists(
            smooth_poses(rep.poses, desc.window), rep.ds
        ),
        "descriptor_from_reparameterized": lambda: desc.from_reparameterized(rep.poses, rep.ds),
        "descriptor_total": lambda: desc.compute(traj),
    }
    results = {k: median_time(fn, args.repeat) for k, fn in stages.items()}
    results["distance_pair"] = median_time(
        lambda: desc.distance(seqs[0], seqs[-1]), args.repeat * 10
    )
    models = [seqs[i % len(seqs)] for i in range(35)]
    per_call = median_time(lambda: desc.distance_matrix(seqs, models), max(10, args.repeat // 10))
    results["distance_in_matrix_per_pair"] = per_call / (len(seqs) * len(models))

    report = {
        "machine": {
            "processor": platform.processor() or platform.machine(),
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS"),
        },
        "trial": {
            "samples": len(traj),
            "duration_s": traj.duration,
            "descriptor_samples": int(seqs[0].shape[0]),
        },
        "descriptor": repr(desc),
        "seconds": results,
        "targets": {"descriptor_total": 1e-3, "distance_pair": 50e-6},
        "reference_octave": {"descriptor_total": [0.070, 0.150], "distance_pair": 0.021},
    }
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(report, indent=2))
    print(f"BILTS+ on a {traj.duration:.1f} s trial ({len(traj)} samples), median of repeated runs")
    for k, v in results.items():
        target = report["targets"].get(k)
        note = f"   target < {target * 1e6:.0f} us" if target else ""
        print(f"  {k:<34} {v * 1e6:9.1f} us{note}")
    print(f"written {args.json}")


if __name__ == "__main__":
    main()
