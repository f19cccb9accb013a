"""What ``thresholds="auto"`` keeps and what it rejects, side by side.

``NearestNeighborClassifier(thresholds="auto")`` (the default settings) is fitted on the HPM
replica's 35 *Original 1* models. Two numbers are measured with the same thresholds:

* **genuine gestures rejected**: the replica's held-out trials of the other 15 contexts (315 test
  and 210 training trials; never models), the fraction said ``no_gesture``;
* **everyday motion rejected**: the fraction said ``no_gesture`` of (a) nine recorded everyday
  motions of ``tests/data/real_motions`` (pouring with a kettle, pouring, scooping, free motion)
  and (b) 210 synthetic ones built from the models' start and end poses
  (:func:`framefree.online.negatives.non_gesture_motions`: unhurried via-point moves, re-grips,
  random drawn shapes). The synthetic ones are hard on purpose: a re-grip is a forearm rotation,
  as *go down* and the gripper gestures are, and a via-point move can be a straight translation.

The current rule is printed beside the former one (the geometric midpoint ``√(P·N)``) so that the
trade is visible. Prints a table, writes JSON.

Usage::

    python benchmarks/auto_thresholds.py [--json benchmarks/results/local/auto_thresholds.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from framefree import NearestNeighborClassifier, Trajectory
from framefree.benchmark.data import load_benchmark_data
from framefree.online.negatives import non_gesture_motions
from framefree.rejection import thresholds_from_models

HERE = Path(__file__).resolve().parent
REAL = HERE.parent / "tests" / "data" / "real_motions"
REAL_FILES = (*sorted(p.name for p in REAL.glob("kettle_pour_*.csv")),
              *(f"reference_set/ip_{n}.csv" for n in ("pouring_motion", "recorded_motion",
                                                       "scooping_motion")))
DEFAULT_JSON = HERE / "results" / "local" / "auto_thresholds.json"


def former_rule(D: np.ndarray, labels: np.ndarray) -> dict[str, float]:
    """The rule before issue 41: ``√(P·N)`` when ``P < N``, else ``N`` (for comparison only)."""
    D = np.array(D, dtype=np.float64)
    np.fill_diagonal(D, np.inf)
    out = {}
    for g in dict.fromkeys(labels.tolist()):
        own = labels == g
        p, n = float(D[np.ix_(own, own)].min(axis=1).max()), float(D[np.ix_(own, ~own)].min())
        out[g] = float(np.sqrt(p * n)) if p < n else n
    return out


def rejected(D: np.ndarray, labels: np.ndarray, thresholds: dict[str, float]) -> np.ndarray:
    """Per query: whether its nearest model lies beyond that model's gesture threshold."""
    j = D.argmin(axis=1)
    tau = np.array([thresholds[g] for g in labels[j]])
    return D[np.arange(len(D)), j] > tau


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json", type=Path, default=DEFAULT_JSON, help="JSON output file")
    args = parser.parse_args()
    data = load_benchmark_data()
    models = [Trajectory.from_array(r.data) for r in data.models]
    labels = np.array([r.gesture for r in data.models])
    clf = NearestNeighborClassifier(thresholds="auto").fit(models, list(labels))
    held = {"test": data.test, "training": data.train}
    synthetic = non_gesture_motions(models, list(labels), L=clf.descriptor_.L,
                                    kinds=("moves", "regrip", "drawn"), seed=0)
    sets = {f"genuine {k} trials": [Trajectory.from_array(r.data) for r in v] for k, v in held.items()}
    sets["everyday motion, recorded"] = [Trajectory.from_csv(REAL / f) for f in REAL_FILES]
    for kind in ("moves", "regrip", "drawn"):
        sets[f"everyday motion, synthetic {kind}"] = [t for k, t in synthetic if k == kind]
    D_models = clf.distance_matrix(models)
    rules = {"P + N (current)": thresholds_from_models(D_models, labels),
             "sqrt(P N) (former)": former_rule(D_models, labels)}
    assert rules["P + N (current)"] == clf.thresholds_
    out: dict = {"classifier": repr(clf), "models": len(models), "sets": {}}
    print(f"{'set':<36} {'n':>4}  " + "  ".join(f"{r:>20}" for r in rules))
    for name, trajs in sets.items():
        D = clf.distance_matrix(trajs)
        row = {r: float(rejected(D, labels, th).mean()) for r, th in rules.items()}
        out["sets"][name] = {"n": len(trajs), "rejected": row}
        print(f"{name:<36} {len(trajs):>4}  " + "  ".join(f"{100 * v:>19.1f}%" for v in row.values()))
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(out, indent=2))
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
