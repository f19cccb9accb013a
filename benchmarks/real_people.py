"""Real people, real trackers: every method, one person left out at a time, in three world frames.

Data: the HTC Vive recordings of ``../shared/data/machete_vive`` (six people, a controller in each
hand, 11 gestures × 5). Each query person is classified against the other five; every recording
is seen from its own world frame — as recorded, turned about the vertical by a random angle, or
tilted at random (seeded; the stated vertical stays +z, as a tilted tracking system would claim).

Methods (framefree.benchmark.people): framefree with ``--invariance gravity`` and ``full`` (canonical
paths of both controllers), the paper's BILTS+ per controller and framefree's recommended
single-tracker recognizer per controller (distance matrices summed), and two practitioner's
baselines (start-relative positions, 32 points, Euclidean 1-NN; and the same heading-normalised).

Data: ``--data DIR``; without it ``../shared/data/machete_vive`` beside the clone where it exists,
else the two people shipped in ``tests/data/machete_vive`` (said on the first line). Writes
``real_people.json`` and ``real_people.png`` to ``--out`` (default ``benchmarks/results/local/``,
ignored by git: a run never overwrites the committed results) and prints the table of
docs/real-people.md. The figure's title is built from the data actually used. To refresh the
committed results and figure, name them::

    .venv/bin/python benchmarks/real_people.py --out benchmarks/results --figure docs/images/real_people.png

Usage::

    .venv/bin/python benchmarks/real_people.py [--data DIR] [--seeds 0,1,2] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

from framefree.benchmark.people import FRAMES, evaluate_people
from framefree.datasets.people_layout import load_people

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "machete_vive"
SHIPPED = ROOT / "tests" / "data" / "machete_vive"
DEFAULT_OUT = ROOT / "benchmarks" / "results" / "local"
ROWS = [
    ("the paper's BILTS+ (per controller, summed)", "paper", "full"),
    ("framefree recommended (per controller, summed)", "recommended", "full"),
    ("baseline: start-relative positions, 1-NN", "baseline", "full"),
    ("baseline, heading-normalised", "baseline-heading", "full"),
    ("framefree, invariance full", "framefree", "full"),
    ("framefree, invariance gravity", "framefree", "gravity"),
]


def title_of(data) -> str:
    """The figure's title, from the data set used: people, trackers per recording, gestures."""
    trackers = sorted({r.sample.n_trackers for r in data.recordings})
    per = "/".join(map(str, trackers))
    return (f"{len(data.people)} real people, {per} tracker{'s' if trackers != [1] else ''} each, "
            f"{len(data.gestures)} gestures: accuracy by world frame")


def plot(rows: list[dict], path: Path, title: str) -> None:
    """Grouped bars: accuracy of every method in every world-frame condition; the axis starts
    low enough to show every bar, and each bar carries its value."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.5, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    width = 0.8 / len(FRAMES)
    colours = ("#4c72b0", "#dd8452", "#c44e52")
    x = np.arange(len(rows))
    lowest = min(100 * r["frames"][f]["accuracy"] for r in rows for f in FRAMES)
    floor = min(50.0, 10.0 * math.floor((lowest - 5.0) / 10.0))
    for k, frames in enumerate(FRAMES):
        acc = [100 * r["frames"][frames]["accuracy"] for r in rows]
        bars = ax.bar(x + (k - 1) * width, acc, width, label=frames, color=colours[k])
        ax.bar_label(bars, fmt="%.0f", fontsize=6, padding=1)
    short = {"paper": "paper's BILTS+\nper controller", "recommended": "recommended\nper controller",
             "baseline": "baseline\n(positions)", "baseline-heading": "baseline\nheading-normalised"}
    ax.set_xticks(x, [short.get(r["method"], f"framefree\ninvariance {r['invariance']}") for r in rows],
                  fontsize=8)
    ax.set_ylabel("recognized, one person left out [%]")
    ax.set_ylim(max(floor, 0.0), 103)
    for level in (97, 99):
        ax.axhline(level, color="0.5", lw=0.8, ls=":")
        ax.text(len(rows) - 0.5, level, f"{level} %", fontsize=7, va="bottom", ha="right", color="0.4")
    ax.set_title(title)
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, title="world frame of each recording",
              title_fontsize=8)
    fig.savefig(path, dpi=110)


def arguments() -> argparse.Namespace:
    """The command line; ``--data`` resolved (one line and exit 2 when there is no data)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=None,
                    help=f"people data set (default: {SHARED} where it exists, else {SHIPPED})")
    ap.add_argument("--seeds", default="0,1,2", help="seeds of the random world frames (averaged)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT,
                    help="folder for real_people.json and real_people.png (default: %(default)s)")
    ap.add_argument("--figure", type=Path, default=None, help="the figure's path (default: in --out)")
    args = ap.parse_args()
    if args.data is None:
        args.data = SHARED if SHARED.is_dir() else SHIPPED
        if args.data == SHIPPED:
            print(f"{SHARED} not found: using the {SHIPPED.relative_to(ROOT)} sample "
                  "(pass --data DIR for a full people data set)")
    if not args.data.is_dir():
        print(f"error: {args.data}: no such folder; pass --data DIR, a people data set "
              "(<person>/<gesture>/<recording>), e.g. tests/data/machete_vive", file=sys.stderr)
        sys.exit(2)
    return args


def evaluate_rows(data, seeds: list[int]) -> list[dict]:
    """Every row of :data:`ROWS` in every world-frame condition (random frames: mean over seeds)."""
    rows = []
    for title, method, invariance in ROWS:
        row = {"row": title, "method": method, "invariance": invariance, "frames": {}}
        for frames in FRAMES:
            runs = [evaluate_people(data, method=method, invariance=invariance, frames=frames, seed=s)
                    for s in (seeds if frames != "recorded" else seeds[:1])]
            row["frames"][frames] = {
                "accuracy": float(np.mean([r.accuracy for r in runs])),
                "per_seed": [r.accuracy for r in runs],
                "per_person": {p: float(np.mean([r.per_person[p] for r in runs])) for p in data.people},
                "mistakes": runs[0].mistakes()[:6],
            }
        rows.append(row)
        cells = " | ".join(f"{100 * row['frames'][f]['accuracy']:.1f}" for f in FRAMES)
        print(f"| {title} | {cells} |", flush=True)
    return rows


def main() -> None:
    args = arguments()
    seeds = [int(s) for s in args.seeds.split(",")]
    data = load_people(args.data)
    print(data.summary())
    start = time.perf_counter()
    rows = evaluate_rows(data, seeds)
    title = title_of(data)
    out = {
        "data": str(args.data), "people": data.people, "recordings": len(data), "seeds": seeds,
        "title": title, "protocol": "leave one person out; every setting chosen on these people",
        "machine": f"{platform.machine()}, {platform.python_version()}",
        "seconds": round(time.perf_counter() - start, 1), "rows": rows,
    }
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "real_people.json"
    path.write_text(json.dumps(out, indent=1))
    figure = args.figure or args.out / "real_people.png"
    plot(rows, figure, title)
    print(f"wrote {path} and {figure}")


if __name__ == "__main__":
    main()
