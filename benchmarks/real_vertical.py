"""How vertically do real people move? A verticality range set from one person's takes, checked on
the others.

With a known vertical (``RecognizerConfig.up``), the live recognizer refuses a candidate whose
verticality (the fraction of the hand's path along the vertical, :mod:`framefree.online.vertical`)
lies more than a margin outside the range of its gesture's demonstrations. This script asks the
real recordings of ``machete_vive`` (six people, two controllers, 11 whole-body gestures × 5) how
far another person's performance lies outside one person's range: for every controller, gesture
and person, every performance of the same gesture by the other five people. The margin the
recognizer uses (:data:`~framefree.online.vertical.VERTICAL_MARGIN`) is the 99th percentile of
these distances; the script also says how many performances each margin would refuse.

Usage::

    python benchmarks/real_vertical.py [--data ../shared/data/machete_vive] [--json out.json]
"""

from __future__ import annotations

import json

import numpy as np

from framefree.benchmark.take_geometry import (
    by_name,
    other_peoples,
    people_data_args,
    take_verticality,
)
from framefree.online.vertical import VERTICAL_MARGIN

MARGINS = (0.1, 0.2, 0.3, 0.4, VERTICAL_MARGIN, 0.5)


def outside(vertical: dict) -> dict[str, list[float]]:
    """{gesture: how far [fraction of path] each other person's performance lies outside one
    person's range of takes (0 inside)}, over every (controller, person, gesture) set."""
    out: dict[str, list[float]] = {}
    for key, own in vertical.items():
        lo, hi = min(own), max(own)
        out.setdefault(key[2], []).extend(max(lo - v, v - hi, 0.0)
                                          for v in other_peoples(vertical, key))
    return out


def summary(distances: dict[str, list[float]]) -> dict:
    """Percentiles of the distances and the fraction each margin of :data:`MARGINS` refuses."""
    every = np.concatenate([np.asarray(d) for d in distances.values()])
    return {
        "checked": int(every.size),
        "percentiles": {q: float(np.quantile(every, q / 100)) for q in (50, 90, 95, 99, 100)},
        "refused": {str(m): float(np.mean(every > m)) for m in MARGINS},
        "largest_by_gesture": {g: float(max(d)) for g, d in sorted(distances.items())},
    }


def main() -> None:
    args = people_data_args(__doc__)
    vertical = take_verticality(args.data)
    s = summary(outside(vertical))
    p = s["percentiles"]
    print(f"{s['checked']} other people's performances against one person's range: outside by "
          f"median {p[50]:.3f}, 90 % {p[90]:.3f}, 95 % {p[95]:.3f}, 99 % {p[99]:.3f}, "
          f"largest {p[100]:.3f}")
    for m, f in s["refused"].items():
        print(f"  margin {float(m):.2f}: {100 * f:.1f} % refused")
    if args.json:
        args.json.write_text(json.dumps({"margin": VERTICAL_MARGIN, "result": s,
                                         "vertical": by_name(vertical)}, indent=1))


if __name__ == "__main__":
    main()
