"""Do real people keep a gesture's proportions? Limits set from one person's takes, checked on the others.

Where a gesture's takes agree on one corner (``proportion_corners``), the live recognizer accepts
a candidate with one corner only if its first stroke's length against the second lies within the
takes' range widened by ``proportion_factor`` (:mod:`framefree.online.proportions`). This script
asks the real recordings of ``machete_vive`` (six people, two controllers, 11 whole-body
gestures × 5) how often another person lies outside such a limit: for every controller, gesture
and person whose five takes agree on their corners, every performance of the same gesture by
the other five people with as many corners is checked against the limits, for several factors
and by the number of corners (any number, to show why only one). The recognizer's factor is
marked; it was chosen with this table and the replica's check mark (docs/online-history.md,
*Session 31*). Cite
Machete's README with any figure from its data.

Usage::

    python benchmarks/real_proportions.py [--data ../shared/data/machete_vive] [--json out.json]
"""

from __future__ import annotations

import json

import numpy as np

from framefree.benchmark.take_geometry import (
    by_name,
    other_peoples,
    people_data_args,
    take_proportions,
)
from framefree.online import RecognizerConfig
from framefree.online.proportions import proportion_limits

FACTORS = (1.25, 1.5, 2.0, 2.5, 3.0)


def outside(shares: dict, factor: float) -> dict:
    """How many of the other people's performances with as many corners lie outside each
    agreeing person's limits, in all and by the number of corners the takes agree on."""
    by_corners: dict[int, dict[str, int]] = {}
    for key, own in shares.items():
        bounds = proportion_limits(own, factor, most_corners=1_000)
        if bounds is None:
            continue
        lo, hi = np.log(np.array(bounds)).T
        others = [v for v in other_peoples(shares, key) if len(v) == len(bounds)]
        row = by_corners.setdefault(len(bounds), {"limits": 0, "checked": 0, "outside": 0})
        row["limits"] += 1
        row["checked"] += len(others)
        row["outside"] += sum(bool(((v < lo) | (v > hi)).any()) for v in others)
    total = {k: sum(r[k] for r in by_corners.values()) for k in ("limits", "checked", "outside")}
    return {"factor": factor, "sets": len(shares), **total,
            "by_corners": dict(sorted(by_corners.items()))}


def main() -> None:
    args = people_data_args(__doc__)
    config = RecognizerConfig()
    shares = take_proportions(args.data, config)
    rows = [outside(shares, f) for f in FACTORS]
    for r in rows:
        mark = "  (the recognizer's)" if r["factor"] == config.constants.proportion_factor else ""
        print(f"factor {r['factor']}: limits for {r['limits']} of {r['sets']} (controller, "
              f"gesture, person) sets of takes; {r['outside']} of {r['checked']} other people's "
              f"performances lie outside{mark}")
        for n, c in r["by_corners"].items():
            print(f"    takes agreeing on {n} corner(s): {c['outside']} of {c['checked']} "
                  f"({100 * c['outside'] / max(c['checked'], 1):.1f} %)")
    if args.json:
        args.json.write_text(json.dumps({
            "corner_angle": config.constants.corner_angle, "L": config.descriptor.L,
            "rows": rows,
            "proportions": {k: [v.tolist() for v in vs] for k, vs in by_name(shares).items()},
        }, indent=1))


if __name__ == "__main__":
    main()
