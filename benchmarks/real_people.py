"""Real people, real trackers: every method, one person left out at a time, in three world frames.

Data: the HTC Vive recordings of ``../shared/data/machete_vive`` (six people, a controller in each
hand, 11 gestures × 5). Each query person is classified against the other five; every recording
is seen from its own world frame — as recorded, turned about the vertical by a random angle, or
tilted at random (seeded; the stated vertical stays +z, as a tilted tracking system would claim).

Methods (framefree.benchmark.people): framefree with ``--invariance gravity`` and ``full`` (canonical
paths of both controllers), the paper's BILTS+ per controller and framefree's recommended
single-tracker recognizer per controller (distance matrices summed), and two practitioner's
baselines (start-relative positions, 32 points, Euclidean 1-NN; and the same heading-normalised).

Writes ``benchmarks/results/real_people.json`` and prints the table of docs/real-people.md.

    .venv/bin/python benchmarks/real_people.py [--data DIR] [--seeds 0,1,2]
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np

from framefree.benchmark.people import FRAMES, evaluate_people
from framefree.datasets.people_layout import load_people

ROOT = Path(__file__).resolve().parents[1]
ROWS = [
    ("the paper's BILTS+ (per controller, summed)", "paper", "full"),
    ("framefree recommended (per controller, summed)", "recommended", "full"),
    ("baseline: start-relative positions, 1-NN", "baseline", "full"),
    ("baseline, heading-normalised", "baseline-heading", "full"),
    ("framefree, invariance full", "framefree", "full"),
    ("framefree, invariance gravity", "framefree", "gravity"),
]


def plot(rows: list[dict], path: Path) -> None:
    """Grouped bars: accuracy of every method in every world-frame condition."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.5, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    width = 0.8 / len(FRAMES)
    colours = ("#4c72b0", "#dd8452", "#c44e52")
    x = np.arange(len(rows))
    for k, frames in enumerate(FRAMES):
        acc = [100 * r["frames"][frames]["accuracy"] for r in rows]
        ax.bar(x + (k - 1) * width, acc, width, label=frames, color=colours[k])
    short = {"paper": "paper's BILTS+\nper controller", "recommended": "recommended\nper controller",
             "baseline": "baseline\n(positions)", "baseline-heading": "baseline\nheading-normalised"}
    ax.set_xticks(x, [short.get(r["method"], f"framefree\ninvariance {r['invariance']}") for r in rows],
                  fontsize=8)
    ax.set_ylabel("recognized, one person left out [%]")
    ax.set_ylim(50, 100)
    for level in (97, 99):
        ax.axhline(level, color="0.5", lw=0.8, ls=":")
        ax.text(len(rows) - 0.5, level, f"{level} %", fontsize=7, va="bottom", ha="right", color="0.4")
    ax.set_title("Six real people, two Vive controllers, 11 gestures: accuracy by world frame")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, title="world frame of each recording",
              title_fontsize=8)
    fig.savefig(path, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(ROOT.parent / "shared" / "data" / "machete_vive"))
    ap.add_argument("--seeds", default="0,1,2", help="seeds of the random world frames (averaged)")
    ap.add_argument("--json", default=str(ROOT / "benchmarks" / "results" / "real_people.json"))
    args = ap.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    data = load_people(args.data)
    print(data.summary())
    rows = []
    start = time.perf_counter()
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
    out = {
        "data": str(args.data), "people": data.people, "recordings": len(data), "seeds": seeds,
        "protocol": "leave one person out; every setting chosen on these six people",
        "machine": f"{platform.machine()}, {platform.python_version()}",
        "seconds": round(time.perf_counter() - start, 1), "rows": rows,
    }
    Path(args.json).write_text(json.dumps(out, indent=1))
    figure = ROOT / "docs" / "images" / "real_people.png"
    plot(rows, figure)
    print(f"wrote {args.json} and {figure}")


if __name__ == "__main__":
    main()
