"""The demo over many sessions: does the robot stack the block for every held-out person?

Runs what ``framefree demo --seed k --no-render [--method M]`` runs, for k in ``--seeds``: the
paper's 18 stacking commands given by the held-out person ``1000 + (k mod 20)`` (never used for
tuning), models from the replica of seed 0 (``original_1``). Prints and writes per session: stacked
or not, commands obeyed, precision / recall / F1, false positives, which gestures were missed and
which events were false, and which commands the robot never received; then the totals.

    .venv/bin/python benchmarks/demo_seeds.py --seeds 0-9 --jobs 2
    .venv/bin/python benchmarks/demo_seeds.py --seeds 0-9 --method both --keep demo_runs

``--keep DIR`` keeps each session's ``framefree demo`` output (summary.json and the recognition
timeline) in ``DIR/<method>_seed<k>/``; otherwise they go to a temporary folder. ``--json`` (default
``benchmarks/results/demo_seeds.json``) replaces the results of the methods run and keeps the others.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from joblib import Parallel, delayed

from framefree.robot.demo import METHODS, build_recognizer, run_demo

_RECOGNIZERS: dict = {}


def _session(method: str, seed: int, out_root: str) -> dict:
    """One demo session (in a worker process; the recognizer is built once per process)."""
    import framefree.robot.sim  # noqa: F401  (chooses MuJoCo's offscreen GL before mujoco loads)

    if method not in _RECOGNIZERS:
        _RECOGNIZERS[method] = build_recognizer(method)
    out = Path(out_root) / f"{method}_seed{seed}"
    tic = time.perf_counter()
    res = run_demo(out, seed=seed, render=False, echo=None, progress=False,
                   recognizer=_RECOGNIZERS[method])
    summary = json.loads((out / "summary.json").read_text())
    rec = res.recognition
    return {
        "seed": seed,
        "method": method,
        "person": summary["person"]["style"],
        "stacked": res.stacked,
        "obeyed": res.obeyed,
        "commands": res.commands,
        "gestures_performed": summary["gestures_performed"],
        **{k: rec[k] for k in ("tp", "fp", "fn", "precision", "recall", "f1", "fp_per_minute",
                               "latency_median_s")},
        "missed": [f"{m['label']}@{m['start_t']:.1f}" for m in res.missed],
        "missed_details": res.missed,
        "false": [f"{e['label']}@{e['time']:.1f}({e['verdict']})" for e in res.events
                  if e["verdict"] != "tp"],
        "not_obeyed": [f"{c['label']}@{c['onset_s']:.1f}" for c in res.command_log
                       if not c["obeyed"]],
        "task": res.task,
        "output": str(out),
        "wall_s": time.perf_counter() - tic,
    }


def _seeds(text: str) -> list[int]:
    if "-" in text:
        a, b = text.split("-", 1)
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def _totals(rows: list[dict]) -> dict:
    tp, fp, fn = (sum(r[k] for r in rows) for k in ("tp", "fp", "fn"))
    p = tp / (tp + fp) if tp + fp else 1.0
    r = tp / (tp + fn) if tp + fn else 1.0
    return {
        "sessions": len(rows),
        "stacked": sum(r["stacked"] for r in rows),
        "obeyed": sum(r["obeyed"] for r in rows),
        "commands": sum(r["commands"] for r in rows),
        "tp": tp, "fp": fp, "fn": fn,
        "precision": p, "recall": r, "f1": 2 * p * r / (p + r) if p + r else 0.0,
    }


def _print(method: str, rows: list[dict], totals: dict) -> None:
    print(f"\n== {method}")
    print(" seed person tempo  size stacked obeyed   F1     FP  missed / false / not obeyed")
    for r in rows:
        st = r["person"]
        print(f" {r['seed']:4d} {st['seed']:6d} {st['tempo']:5.2f} {st['size']:5.2f} "
              f"{'yes' if r['stacked'] else 'NO':>7} {r['obeyed']:3d}/{r['commands']:<3d} "
              f"{100 * r['f1']:5.1f} % {r['fp']:3d}  {r['missed']} / {r['false']} / {r['not_obeyed']}")
    t = totals
    print(f" stacked {t['stacked']} of {t['sessions']}; obeyed {t['obeyed']} of {t['commands']}; "
          f"TP {t['tp']} FP {t['fp']} FN {t['fn']}; P {100 * t['precision']:.1f} % "
          f"R {100 * t['recall']:.1f} % F1 {100 * t['f1']:.1f} %")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", default="0-9", help="e.g. 0-9 or 0,3,5")
    ap.add_argument("--method", default="segments", choices=[*METHODS, "both"])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--keep", type=Path, help="keep each session's output under this folder")
    ap.add_argument("--json", type=Path, default=Path("benchmarks/results/demo_seeds.json"))
    args = ap.parse_args()
    seeds = _seeds(args.seeds)
    methods = list(METHODS) if args.method == "both" else [args.method]
    build_recognizer(methods[0])  # generate the replica once, before the workers need it
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        root = str(args.keep or tmp)
        rows = Parallel(n_jobs=args.jobs)(
            delayed(_session)(m, s, root) for m in methods for s in seeds)
    # results of other methods already in the file are kept (run the methods one at a time)
    out: dict = json.loads(args.json.read_text()) if args.json.is_file() else {}
    out.update({"models": "replica seed 0, original_1", "people": "held-out 1000 + (k mod 20)"})
    for m in methods:
        mrows = [r for r in rows if r["method"] == m]
        out[m] = {"command": f"framefree demo --seed k --no-render --method {m}, k in {args.seeds}",
                  "totals": _totals(mrows), "sessions": mrows}
        _print(m, mrows, out[m]["totals"])
    print(f"\nwall {time.perf_counter() - t0:.0f} s")
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(out, indent=1, default=str))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
