"""Does a gesture's cone of hand directions hold another person? Cones from five people, checked on the sixth.

With ``RecognizerConfig.hand_frame`` (the tracker's frame sits on every hand the same way, as a
Vive controller held by its handle does), a gesture whose takes move the same way in the
tracker's frame refuses a candidate that moves outside a cone around that way
(:mod:`framefree.online.hand_direction`: a von Mises–Fisher distribution fitted to the takes,
the cone holding ``coverage`` of it). This script asks the real recordings of ``machete_vive``
(six people, two controllers, 11 whole-body gestures × 5) how many of a person's takes lie inside
the cone learned from the other five people's takes of the same gesture and controller, for
several coverages; the recognizer's is marked. It was not chosen on this table: 0.99 is the
share of real people the other limits are meant to hold (docs/online-history.md, v26). Cite
Machete's README with any figure from its data.

Usage::

    python benchmarks/real_directions.py [--data ../shared/data/machete_vive] [--json out.json]
"""

from __future__ import annotations

import json

from framefree.benchmark.take_geometry import (
    by_name,
    cone_coverage,
    people_data_args,
    take_directions,
)
from framefree.online.hand_direction import COVERAGE

COVERAGES = (0.9, 0.95, 0.99, 0.999)


def main() -> None:
    args = people_data_args(__doc__)
    ways = take_directions(args.data)
    rows = [{"coverage": c, **cone_coverage(ways, c)} for c in COVERAGES]
    for r in rows:
        mark = "  (the recognizer's)" if r["coverage"] == COVERAGE else ""
        print(f"coverage {r['coverage']}: cones for {r['cones']} (controller, gesture, person) "
              f"sets of takes; {r['inside']} of {r['checked']} of the left-out person's takes "
              f"inside ({100 * r['inside'] / max(r['checked'], 1):.1f} %){mark}")
    if args.json:
        args.json.write_text(json.dumps({
            "rows": rows, "directions": {k: [v.tolist() for v in vs]
                                         for k, vs in by_name(ways).items()}}, indent=1))


if __name__ == "__main__":
    main()
