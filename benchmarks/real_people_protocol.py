"""Real people, chosen without flattery: nested leave-two-people-out over the multi-tracker comparisons.

Outer loop: every pair of the people is the query set, the others are the models. Inner loop, on
the model people only: each of them is classified against the rest (leave one person out), and
the candidate comparison with the best inner accuracy is chosen (ties: the earlier candidate in
:data:`CANDIDATES`, the simpler one). The outer accuracy of that choice, pooled and per fold, says
how well *choosing on some people* carries to others. No query person takes part in the choice
made for its fold.

Conditions (as ``framefree evaluate-people`` builds them, :func:`framefree.benchmark.people.reframe`):
``full`` on tilted frames, ``gravity`` as recorded and turned; random frames over ``--seeds``.

Candidates (all 1-NN by DTW; :class:`~framefree.descriptors.canonical.CanonicalPath`, see
docs/real-people.md). ``P``: canonical positions (the comparison of framefree <= 0.17). ``O``
added: each tracker's rotation since its start in the canonical frame, times 0.3 m (fixed
beforehand: a hand turning one radian moves a point at forearm length by 0.3 m). ``H`` added:
each hand's position in the other's frame. ``S`` added: the positions in the controllers' mean
starting orientation. ``P+B``: the canonical positions' DTW plus the paper's BILTS+ per
controller, each divided by its median over the model people's pairs (of the fold). ``--round 1``
is the first set (P, PO, PH, POH, P+B); round 2 (the default: P, POH, PS, POHS, P+B) was set
after round 1 had been seen on all six people.

Every distance is computed once for all recordings of a condition (a distance never depends on
the fold); the folds only pick rows and columns. Every candidate is exactly invariant in its
condition, so one seed gives the same figures as three. Writes
``real_people_protocol_round<N>.json`` to ``--out`` (default ``benchmarks/results/local/``).

Usage::

    NUMBA_NUM_THREADS=1 .venv/bin/python benchmarks/real_people_protocol.py \
        [--data DIR] [--seeds 0] [--round 2] [--out DIR]
"""

from __future__ import annotations

import argparse
import itertools
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from framefree import NearestNeighborClassifier
from framefree.benchmark.people import reframe
from framefree.datasets.people_layout import load_people
from framefree.descriptors.canonical import CanonicalPath

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "machete_vive"
DEFAULT_OUT = ROOT / "benchmarks" / "results" / "local"
#: orientation weight [m], fixed before any run (not tuned)
ORIENTATION_SCALE = 0.3
#: candidate comparisons of each round: name -> components, summed after median normalisation.
#: Round 2 was set after round 1's results on all six people had been seen (docs/real-people.md).
ROUNDS = {
    1: {"P": ("P",), "PO": ("PO",), "PH": ("PH",), "POH": ("POH",), "P+B": ("P", "B")},
    2: {"P": ("P",), "POH": ("POH",), "PS": ("PS",), "POHS": ("POHS",), "P+B": ("P", "B")},
}
CANDIDATES = dict(ROUNDS[2])
#: invariance, world frames
CONDITIONS = (("full", "tilted"), ("gravity", "recorded"), ("gravity", "turned"))


def _path(invariance: str, name: str) -> CanonicalPath:
    return CanonicalPath(invariance, orientation_scale=ORIENTATION_SCALE if "O" in name else None,
                         relative="H" in name, start_frame="S" in name)


def component_matrices(samples: list, labels: list[str], invariance: str) -> dict[str, np.ndarray]:
    """Distances (n, n) among all recordings for every component a candidate uses.

    Parameters
    ----------
    samples : list of MultiTrajectory, length n
        Every recording, in one condition's world frames.
    labels : list of str, length n
        Their gestures (the per-tracker classifiers need labels; distances do not depend on them).
    invariance : {"full", "gravity"}
        The canonical frame of the path components.
    """
    out = {}
    for name in sorted({c for parts in CANDIDATES.values() for c in parts}):
        if name == "B":
            total = np.zeros((len(samples), len(samples)))
            for k in range(samples[0].n_trackers):
                tracks = [s.trackers[k] for s in samples]
                total += NearestNeighborClassifier.paper().fit(tracks, labels).distance_matrix(tracks)
            out[name] = total
        else:
            path = _path(invariance, name)
            seqs = [path.compute(s) for s in samples]
            out[name] = path.distance_matrix(seqs, seqs)
    return out


def candidate_matrix(parts: tuple[str, ...], comps: dict[str, np.ndarray], models: np.ndarray) -> np.ndarray:
    """A candidate's distances (n, n): one component as is, or several each divided by its median
    over pairs of distinct ``models`` (indices)."""
    if len(parts) == 1:
        return comps[parts[0]]
    total = np.zeros_like(comps[parts[0]])
    sub = np.ix_(models, models)
    for name in parts:
        block = comps[name][sub]
        total += comps[name] / float(np.median(block[~np.eye(len(models), dtype=bool)]))
    return total


def accuracy(D: np.ndarray, gestures: np.ndarray, queries: np.ndarray, models: np.ndarray) -> float:
    """1-NN accuracy of ``queries`` against ``models`` (index arrays) under distances ``D``."""
    nearest = models[np.argmin(D[np.ix_(queries, models)], axis=1)]
    return float(np.mean(gestures[nearest] == gestures[queries]))


def choose(comps: dict[str, np.ndarray], gestures: np.ndarray, persons: np.ndarray,
           pool: list[str]) -> tuple[str, dict[str, float]]:
    """The candidate with the best leave-one-person-out accuracy among the people ``pool``."""
    inner = {}
    models_all = np.flatnonzero(np.isin(persons, pool))
    for name, parts in CANDIDATES.items():
        D = candidate_matrix(parts, comps, models_all)
        hits = []
        for p in pool:
            q = np.flatnonzero(persons == p)
            m = np.flatnonzero(np.isin(persons, [o for o in pool if o != p]))
            hits.append(accuracy(D, gestures, q, m) * len(q))
        inner[name] = float(np.sum(hits) / len(models_all))
    best = max(CANDIDATES, key=lambda n: (inner[n], -list(CANDIDATES).index(n)))
    return best, inner


def nested(comps: dict[str, np.ndarray], gestures: np.ndarray, persons: np.ndarray,
           people: list[str]) -> dict:
    """Outer leave-two-people-out, inner choice on the four (or other) model people."""
    folds = []
    for pair in itertools.combinations(people, 2):
        pool = [p for p in people if p not in pair]
        best, inner = choose(comps, gestures, persons, pool)
        q = np.flatnonzero(np.isin(persons, pair))
        m = np.flatnonzero(np.isin(persons, pool))
        outer = {n: accuracy(candidate_matrix(parts, comps, m), gestures, q, m)
                 for n, parts in CANDIDATES.items()}
        folds.append({"queries": list(pair), "chosen": best, "inner": inner, "outer": outer,
                      "outer_chosen": outer[best]})
    chosen = np.array([f["outer_chosen"] for f in folds])
    six_best, six_inner = choose(comps, gestures, persons, people)
    return {
        "folds": folds,
        "chosen_mean": float(chosen.mean()), "chosen_std": float(chosen.std(ddof=1)),
        "chosen_min": float(chosen.min()), "chosen_max": float(chosen.max()),
        "times_chosen": {n: sum(f["chosen"] == n for f in folds) for n in CANDIDATES},
        "fixed_mean": {n: float(np.mean([f["outer"][n] for f in folds])) for n in CANDIDATES},
        "fixed_min": {n: float(np.min([f["outer"][n] for f in folds])) for n in CANDIDATES},
        "folds_better_worse_than_P": {n: [sum(f["outer"][n] > f["outer"]["P"] for f in folds),
                                          sum(f["outer"][n] < f["outer"]["P"] for f in folds)]
                                      for n in CANDIDATES if n != "P"},
        "all_people_choice": six_best, "all_people_lopo": six_inner,
    }


def run_condition(data, invariance: str, frames: str, seed: int) -> dict:
    """The nested protocol in one condition and seed."""
    recs = list(data)
    samples = reframe([r.sample for r in recs], frames, seed)
    labels = [r.gesture for r in recs]
    comps = component_matrices(samples, labels, invariance)
    return nested(comps, np.asarray(labels), np.asarray([r.person for r in recs]), list(data.people))


def arguments() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=SHARED, help="people data set (default: %(default)s)")
    ap.add_argument("--seeds", default="0,1,2", help="seeds of the random world frames")
    ap.add_argument("--conditions", default=",".join(f"{i}:{f}" for i, f in CONDITIONS),
                    help="invariance:frames pairs (default: %(default)s)")
    ap.add_argument("--round", type=int, choices=sorted(ROUNDS), default=2,
                    help="candidate set (default: %(default)s)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="folder for real_people_protocol.json")
    args = ap.parse_args()
    if not args.data.is_dir():
        print(f"error: {args.data}: no such folder; pass --data DIR, a people data set "
              "(<person>/<gesture>/<recording>) of three or more people", file=sys.stderr)
        sys.exit(2)
    return args


def report(key: str, res: dict) -> None:
    """One condition's summary lines."""
    fixed = "  ".join(f"{n} {100 * a:.1f} (min {100 * res['fixed_min'][n]:.1f})"
                      for n, a in res["fixed_mean"].items())
    print(f"{key}: chosen {100 * res['chosen_mean']:.1f} ± {100 * res['chosen_std']:.1f} "
          f"(min {100 * res['chosen_min']:.1f}, max {100 * res['chosen_max']:.1f}) | "
          f"times chosen {res['times_chosen']} | folds better/worse than P "
          f"{res['folds_better_worse_than_P']} | fixed, mean over folds: {fixed} | "
          f"six people LOPO: {res['all_people_choice']} "
          + " ".join(f"{n} {100 * a:.1f}" for n, a in res["all_people_lopo"].items()), flush=True)


def main() -> None:
    args = arguments()
    seeds = [int(s) for s in args.seeds.split(",")]
    CANDIDATES.clear()
    CANDIDATES.update(ROUNDS[args.round])
    data = load_people(args.data)
    print(data.summary())
    if len(data.people) < 4:
        print(f"error: {args.data}: {len(data.people)} people; leave-two-people-out with a choice "
              "among the rest needs four or more", file=sys.stderr)
        sys.exit(2)
    conditions = [tuple(c.split(":")) for c in args.conditions.split(",")]
    jobs = [(i, f, s) for i, f in conditions for s in (seeds if f != "recorded" else seeds[:1])]
    start = time.perf_counter()
    results = {}
    for invariance, frames, seed in tqdm(jobs, desc="conditions"):
        key = f"{invariance}/{frames}/seed{seed}"
        results[key] = run_condition(data, invariance, frames, seed)
        report(key, results[key])
    out = {"data": str(args.data), "people": data.people, "round": args.round, "candidates": CANDIDATES,
           "orientation_scale_m": ORIENTATION_SCALE, "seeds": seeds,
           "protocol": "outer leave-two-people-out; inner leave-one-person-out on the model people",
           "machine": f"{platform.machine()}, {platform.python_version()}",
           "seconds": round(time.perf_counter() - start, 1), "results": results}
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / f"real_people_protocol_round{args.round}.json"
    path.write_text(json.dumps(out, indent=1))
    print(f"wrote {path} ({out['seconds']} s)")


if __name__ == "__main__":
    main()
