"""Does a gesture's cone of hand directions hold another person? Cones from five people, checked on the sixth.

With ``RecognizerConfig.hand_frame`` (the default since v27), a gesture whose takes move the same
way in the tracker's frame counts a candidate that moves outside a cone around that way 1.5 times
farther from it
(:mod:`framefree.online.hand_direction`: a von Mises–Fisher distribution fitted to the takes,
the cone holding ``coverage`` of it). This script asks the real recordings of ``machete_vive``
(six people, two controllers, 11 whole-body gestures × 5) how many of a person's takes lie inside
the cone learned from the other five people's takes of the same gesture and controller, for
several coverages; the recognizer's is marked. It was not chosen on this table: 0.99 is the
share of real people the other limits are meant to hold (docs/online-history.md, v26). Cite
Machete's README with any figure from its data.

Usage::

    python benchmarks/real_directions.py [--data ../shared/data/machete_vive] [--json out.json]
        [--figure docs/images/real_directions.png]
"""

from __future__ import annotations

import json
from pathlib import Path

from framefree.benchmark.take_geometry import (
    by_name,
    cone_coverage,
    people_data_args,
    take_directions,
)
from framefree.online.hand_direction import COVERAGE

COVERAGES = (0.9, 0.95, 0.99, 0.999)


def draw(pairs: list[tuple[float, float]], path: Path) -> None:
    """Each left-out take's angle from its cone's axis over the cone's half-angle, as a
    histogram: a take beyond 1 lies outside the cone."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ratios = [a / c if c > 0 else float("inf") for a, c in pairs]
    fig, ax = plt.subplots(figsize=(6.4, 3.4), layout="constrained")
    ax.hist([min(r, 2.5) for r in ratios], bins=50, range=(0.0, 2.5), color="0.45")
    ax.axvline(1.0, color="tab:red", lw=1.2)
    outside = sum(r > 1.0 for r in ratios)
    ax.set_xlabel("angle from the cone's axis / the cone's half-angle (2.5: 2.5 or more)")
    ax.set_ylabel("takes")
    ax.set_title(f"A sixth person's takes against the cone of five people's ({outside} of "
                 f"{len(ratios)} outside)\nMachete Vive, both controllers, coverage {COVERAGE}",
                 fontsize=9)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    args = people_data_args(__doc__, figure=True)
    ways = take_directions(args.data)
    rows = [{"coverage": c, **cone_coverage(ways, c)} for c in COVERAGES]
    if args.figure:
        draw(next(r for r in rows if r["coverage"] == COVERAGE)["angles"], args.figure)
    for r in rows:
        mark = "  (the recognizer's)" if r["coverage"] == COVERAGE else ""
        print(f"coverage {r['coverage']}: cones for {r['cones']} (controller, gesture, person) "
              f"sets of takes; {r['inside']} of {r['checked']} of the left-out person's takes "
              f"inside ({100 * r['inside'] / max(r['checked'], 1):.1f} %){mark}")
    if args.json:
        args.json.write_text(json.dumps({
            "rows": [{k: v for k, v in r.items() if k != "angles"} for r in rows],
            "angles": next(r for r in rows if r["coverage"] == COVERAGE)["angles"],
            "directions": {k: [v.tolist() for v in vs]
                                         for k, vs in by_name(ways).items()}}, indent=1))


if __name__ == "__main__":
    main()
