"""How far can the live recognizer get on labelled real streams by its thresholds alone?

A diagnosis, not a tuning: nothing here is chosen. Two questions, on streams whose gestures are
labelled (default: SFINGE3D's 36 development sequences, the four swipes, the dictionary's
examples as models, as ``framefree evaluate-stream --gestures`` runs them):

*The ceiling of the distance.* Every labelled gesture is cut out at its labelled start and end
(with the spotter's margin) and classified as the spotter classifies a candidate: is its nearest
model of its own gesture, and within ``c`` × that gesture's calibrated threshold τ_g? This is
what a perfect spotter could find at each scale ``c``.

*The live recognizer at the same scales.* Every τ_g multiplied by ``c`` (``gesture_thresholds``),
the streams run live and scored as ``evaluate-stream`` scores them (true positives, false
positives, misses; ``c`` = 1 is the recognizer as it is).

Where the live count stays below the ceiling, the spotting loses gestures (where candidates
start and end, which one fires); where false positives grow faster than true ones, the distance
does not separate the gestures from free motion.

Cite Caputo et al., *SFINGE 3D*, Computers & Graphics 91, 2020, with any figure from its data.

Usage::

    python benchmarks/threshold_ceiling.py [--scales 0.8,0.9,1,1.1,1.2,1.3,1.5]
        [--models DIR] [--streams DIR] [--gestures G1,G2,...] [--out JSON] [--figure PNG]
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from tqdm import tqdm

from framefree.datasets.layout import resolve_models
from framefree.datasets.stream_files import load_stream
from framefree.online import Recognizer
from framefree.online.evaluation import combine, match_events, per_gesture, run_stream

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data"
SWIPES = "swipe_left,swipe_right,swipe_v,swipe_o"
SCALES = "0.8,0.9,1,1.1,1.2,1.3,1.5"


def labelled_ratios(rec: Recognizer, trajectory: Any, segments: Sequence[Any]
                    ) -> list[dict[str, Any]]:
    """Each labelled gesture of one stream cut at its labelled bounds and classified as a live
    candidate: its label, its nearest gesture and its distance to its own gesture's nearest
    model over that gesture's τ."""
    spotter = rec.spotter
    times, poses = trajectory.uniform_poses(rec.config.constants.dt)
    pad = spotter.margin * rec.config.constants.dt
    labels = np.asarray(rec.labels)
    rows = []
    for seg in segments:
        inside = (times >= seg.start_t - pad) & (times <= seg.end_t + pad)
        distances, _ = spotter.classifier.distances(times[inside], poses[inside])
        ratios = distances / spotter.model_thresholds
        nearest = int(np.argmin(ratios))
        rows.append({"label": seg.label, "nearest": str(labels[nearest]),
                     "own_ratio": float(np.min(ratios[labels == seg.label]))})
    return rows


def ceiling(rows: Sequence[dict[str, Any]], scale: float) -> dict[str, int]:
    """How many labelled gestures, in all and per gesture, are nearest their own gesture and
    within ``scale`` × its τ."""
    found: dict[str, int] = {}
    for r in rows:
        found.setdefault(r["label"], 0)
        found[r["label"]] += int(r["nearest"] == r["label"] and r["own_ratio"] < scale)
    return {"all": sum(found.values()), **found}


def live_counts(rec: Recognizer, streams: Sequence[tuple[Any, list]]) -> dict[str, Any]:
    """The streams run live and scored as ``evaluate-stream`` scores them: totals and per
    gesture."""
    rec.warmup()
    rec.background = False
    results = []
    for trajectory, segments in streams:
        rec.reset()
        events, _ = run_stream(rec, trajectory)
        results.append(match_events(events, segments, float(trajectory.t[-1] - trajectory.t[0])))
    total = combine(results).summary()
    return {**{k: total[k] for k in ("tp", "fp", "fn", "f1", "fp_per_minute")},
            "per_gesture": {g: {k: v[k] for k in ("tp", "fp", "fn")}
                            for g, v in per_gesture(results).items()}}


def gesture_models(models: Path, gestures: Sequence[str]) -> tuple[list[Any], list[str]]:
    """The takes of ``gestures`` in a models folder and their labels (as ``evaluate-stream
    --gestures`` keeps them)."""
    found = resolve_models(str(models), model_context="original_1", quat_order="wxyz", units="m")
    keep = [i for i, label in enumerate(found.labels) if label in gestures]
    return [found.trajectories[i] for i in keep], [found.labels[i] for i in keep]


def labelled_streams(streams_dir: Path, gestures: Sequence[str]
                     ) -> list[tuple[Path, Any, list[Any]]]:
    """Every stream of a folder with its labels of ``gestures`` (the others count as
    non-gesture motion)."""
    out = []
    for path in sorted(streams_dir.glob("*.csv")):
        if not path.name.endswith("_labels.csv"):
            trajectory, segments = load_stream(path)
            out.append((path, trajectory, [s for s in segments if s.label in gestures]))
    return out


def measure(models: Path, streams_dir: Path, gestures: list[str], scales: list[float]
            ) -> dict[str, Any]:
    """The ceiling and the live counts at every scale (see the module's docstring)."""
    takes, labels = gesture_models(models, gestures)
    rec = Recognizer.from_trajectories(takes, labels)
    tau = dict(rec.calibration.summary()["thresholds"])
    streams = [(trajectory, segments)
               for _, trajectory, segments in labelled_streams(streams_dir, gestures)]
    rows = [r for trajectory, segments in streams for r in labelled_ratios(rec, trajectory, segments)]
    out: dict[str, Any] = {"models": str(models), "streams": len(streams), "gestures": gestures,
                           "labelled": len(rows), "tau": tau,
                           "nearest_own": sum(r["nearest"] == r["label"] for r in rows),
                           "scales": {}}
    for scale in tqdm(scales, desc="scales"):
        scaled = rec if scale == 1 else Recognizer.from_trajectories(  # c = 1: rec itself
            takes, labels, gesture_thresholds={g: scale * t for g, t in tau.items()})
        out["scales"][f"{scale:g}"] = {"ceiling": ceiling(rows, scale),
                                       "live": live_counts(scaled, streams)}
    return out


def draw(result: dict[str, Any], path: Path) -> None:
    """Labelled gestures within c τ (the ceiling), and the live true and false positives."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scales = [float(s) for s in result["scales"]]
    rows = list(result["scales"].values())
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    ax.axhline(result["labelled"], color="0.6", lw=1, ls=":", label="labelled gestures")
    ax.plot(scales, [r["ceiling"]["all"] for r in rows], "o-", color="tab:green",
            label="cut at their labelled bounds: nearest their own gesture, within c τ")
    ax.plot(scales, [r["live"]["tp"] for r in rows], "s-", color="tab:blue",
            label="live: true positives")
    ax.plot(scales, [r["live"]["fp"] for r in rows], "^-", color="tab:red",
            label="live: false positives")
    ax.axvline(1.0, color="0.8", lw=1)
    ax.set_xlabel("every threshold τ_g multiplied by c")
    ax.set_ylabel("gestures")
    ax.set_title(f"{result['labelled']} labelled gestures in {result['streams']} streams",
                 fontsize=10)
    ax.set_ylim(0, result["labelled"] + 3)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _scales(text: str) -> list[float]:
    """The factors of ``--scales``; a usage error (one line, exit status 2) otherwise."""
    try:
        scales = [float(s) for s in text.split(",") if s.strip()]
    except ValueError:
        scales = []
    if not scales or any(not np.isfinite(s) or s <= 0 for s in scales):
        print(f"error: --scales must be positive numbers separated by commas, got {text!r}",
              file=sys.stderr)
        raise SystemExit(2)
    return scales


def main(argv: list[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", type=Path, default=DATA / "sfinge_dev" / "templates")
    ap.add_argument("--streams", type=Path, default=DATA / "sfinge_dev" / "streams")
    ap.add_argument("--gestures", default=SWIPES)
    ap.add_argument("--scales", default=SCALES, help="the factors c, separated by commas")
    ap.add_argument("--out", type=Path, default=REPO / "benchmarks" / "results"
                    / "threshold_ceiling_sfinge.json")
    ap.add_argument("--figure", type=Path, default=None, help="draw the counts against c here")
    args = ap.parse_args(argv)
    scales = _scales(args.scales)
    for folder in (args.models, args.streams):
        if not folder.is_dir():
            print(f"error: {folder}: no such folder", file=sys.stderr)
            raise SystemExit(2)
    gestures = [g.strip() for g in args.gestures.split(",") if g.strip()]
    result = measure(args.models, args.streams, gestures, scales)
    print(f"{result['labelled']} labelled gestures, {result['nearest_own']} nearest their own "
          "gesture when cut at their labelled bounds")
    print("   c   within c τ   live TP / FP / FN    F1     FP/min")
    for scale, row in result["scales"].items():
        live = row["live"]
        print(f"{float(scale):4.2f}   {row['ceiling']['all']:9d}   {live['tp']:7d} / {live['fp']:2d} / "
              f"{live['fn']:2d}   {100 * live['f1']:5.1f} %  {live['fp_per_minute']:5.2f}")
    args.out.write_text(json.dumps(result, indent=1))
    if args.figure:
        draw(result, args.figure)
    return result


if __name__ == "__main__":
    main()
