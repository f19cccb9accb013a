"""How far a gesture moves, in the recognizer's distance, when another person makes it larger or smaller.

People's gestures differ in amplitude by about ±30 % (body size, habit) while their wrists turn
about as far. This script scales the hand path of every demonstration of a library about its start
(×1/``--size`` and ×``--size``, orientations kept, as ``framefree check`` does) and prints, per
gesture, with the distances of the recognizer's own classifier:

* ``tau``: the gesture's threshold;
* ``own``: the largest, over its scaled demonstrations, of the distance to the nearest *other*
  demonstration of the same gesture (above ``tau``: such a person's gesture is missed);
* ``rival``: the smallest distance from a scaled demonstration of *another* gesture to this
  gesture's demonstrations, and which gesture that was (below ``tau``: it may be taken for this
  one).

Models only, no streams: the HPM seven of the replica (*original_1*), optionally with an eighth
gesture demonstrated five times by the replica's person (``--gesture``).

    python benchmarks/size_sensitivity.py [--gesture push_twist] [--size 1.3] [--json out.json]
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from framefree.library import TakeSet, enroll, join_recordings, read_takes, split_takes
from framefree.replica import replica_path, synthesize_gesture


def vocabulary(gesture: str | None, seed: int = 0) -> TakeSet:
    """The HPM seven, plus five demonstrations of ``gesture`` cut from one recording."""
    takes = read_takes(replica_path(), "original_1")
    if gesture is None:
        return takes
    rng = np.random.default_rng([seed, 8])
    new = split_takes(join_recordings([synthesize_gesture(gesture, rng) for _ in range(5)]))
    return takes + TakeSet(tuple(new), (gesture,) * len(new),
                           tuple(f"{gesture}/own/trial_{k + 1}" for k in range(len(new))))


def size_sensitivity(takes: TakeSet, size: float) -> dict[str, dict[str, float | str]]:
    """Per gesture: ``tau``, ``own`` and ``rival`` distances (see the module docstring)."""
    rec = enroll(takes).recognizer()
    desc = rec.classifier.descriptor
    labels = np.array(takes.labels)
    factors = (1.0 / size, size)
    copies = [desc.compute(tr.path_scaled(f)) for tr in takes.takes for f in factors]
    owner = np.repeat(np.arange(len(takes)), len(factors))
    D = desc.distance_matrix(copies, rec.classifier.models)  # (copies, models)
    D[np.arange(owner.size), owner] = np.inf  # a copy is not compared with its own original
    out: dict[str, dict[str, float | str]] = {}
    for g in takes.gestures:
        own_models = labels == g
        mine = own_models[owner]
        others = D[np.ix_(~mine, own_models)].min(axis=1)
        out[g] = {
            "tau": float(rec.gesture_thresholds[g]),
            "own": float(D[np.ix_(mine, own_models)].min(axis=1).max()),
            "rival": float(others.min()),
            "rival_gesture": str(labels[owner[~mine]][int(np.argmin(others))]),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gesture", default=None, help="an eighth gesture (figure_eight, push_twist)")
    ap.add_argument("--size", type=float, default=1.3, help="size factor (copies at 1/size and size)")
    ap.add_argument("--json", default=None, help="write the results here")
    args = ap.parse_args()
    result = size_sensitivity(vocabulary(args.gesture), args.size)
    print(f"{'gesture':<16}{'tau':>8}{'own':>8}{'rival':>8}  nearest rival")
    for g, r in result.items():
        flag = "  own > tau" if r["own"] > r["tau"] else ""
        flag += "  rival < tau" if r["rival"] < r["tau"] else ""
        print(f"{g:<16}{r['tau']:8.4f}{r['own']:8.4f}{r['rival']:8.4f}  {r['rival_gesture']}{flag}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"gesture": args.gesture, "size": args.size, "gestures": result}, fh, indent=1)


if __name__ == "__main__":
    main()
