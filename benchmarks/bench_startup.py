"""How long ``framefree live`` takes to become ready from a gesture library (no calibration).

The library holds the 35 *original_1* recordings of the HPM replica (enrolled once, here, if
``--library`` is not given). Two measurements:

* **fresh process**: ``python -m framefree.cli live --models LIB --source rest.csv`` is started
  ``--repeat`` times; the time from starting the process to the line that says the recognizer is
  ready (models loaded, kernels warmed up), and to the process's end (a one-second rest replayed
  as fast as possible);
* **in a running process**: the same steps one by one in a child process — importing
  :mod:`framefree.online`, :meth:`~framefree.online.Recognizer.load`, ``warmup()`` (the first
  compiled call pays numba's one-time initialization and loads every cached kernel).

Prints a table and writes JSON. Timings depend on the machine and on its load; the numba cache
must be warm (one unmeasured run comes first; the first run after installing compiles everything),
and so must Python's bytecode cache (where ``PYTHONDONTWRITEBYTECODE`` is set, run
``python -m compileall src/framefree`` once, or every import compiles framefree's source again).

Usage::

    .venv/bin/python benchmarks/bench_startup.py [--repeat 5] [--json benchmarks/results/startup.json]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

_STEPS = """
import json, time
t0 = time.perf_counter()
import framefree.online as fo
t1 = time.perf_counter()
rec = fo.Recognizer.load({path!r})
t2 = time.perf_counter()
rec.warmup()
t3 = time.perf_counter()
print(json.dumps({{"import_s": t1 - t0, "load_s": t2 - t1, "warmup_s": t3 - t2}}))
"""


def _library(folder: Path) -> Path:
    from framefree.library import enroll, read_takes
    from framefree.replica import replica_path

    takes = read_takes(replica_path(), "original_1")
    return enroll(takes, built_from=[str(replica_path())]).save(folder / "hpm.npz")


def _rest_csv(folder: Path) -> Path:
    rows = [f"{0.02 * k:.2f},0.1,0.2,1.0,1,0,0,0" for k in range(50)]
    path = folder / "rest.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


def fresh_process(library: Path, source: Path) -> dict[str, float]:
    """Seconds from starting ``framefree live`` to its ready line and to its end."""
    argv = [sys.executable, "-m", "framefree.cli", "live", "--models", str(library),
            "--source", str(source), "--speed", "0", "--no-view"]
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
    ready = float("nan")
    for line in proc.stderr:
        if " models, " in line and ready != ready:
            ready = time.perf_counter() - t0
    proc.wait()
    if proc.returncode != 0:
        raise RuntimeError(f"framefree live exited with {proc.returncode}")
    return {"ready_s": ready, "total_s": time.perf_counter() - t0}


def in_process(library: Path) -> dict[str, float]:
    """Import, load and warm-up times measured inside one fresh child process."""
    out = subprocess.run([sys.executable, "-c", _STEPS.format(path=str(library))],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _summary(runs: list[dict[str, float]]) -> dict[str, dict[str, float]]:
    return {k: {"median": statistics.median(r[k] for r in runs), "min": min(r[k] for r in runs),
                "max": max(r[k] for r in runs)} for k in runs[0]}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--library", type=Path, default=None, help="library file (default: enroll HPM)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        library = args.library or _library(folder)
        source = _rest_csv(folder)
        fresh_process(library, source)  # fills the numba cache if it is cold
        fresh = [fresh_process(library, source) for _ in range(args.repeat)]
        steps = [in_process(library) for _ in range(args.repeat)]
    out = {"library": str(args.library or "HPM replica original_1 (35 takes)"),
           "repeat": args.repeat, "machine": platform.platform(), "cpus": os.cpu_count(),
           "load_average": os.getloadavg()[0], "python": platform.python_version(),
           "fresh_process": _summary(fresh), "in_process": _summary(steps)}
    print(f"framefree live from a gesture library ({out['library']}), {args.repeat} runs, median "
          f"(min-max) [s]; load average {out['load_average']:.2f}")
    for group in ("fresh_process", "in_process"):
        for key, v in out[group].items():
            print(f"  {group:<14}{key:<10}{v['median']:7.3f}  ({v['min']:.3f}-{v['max']:.3f})")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
