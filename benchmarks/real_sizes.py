"""How much larger or smaller do real people make a gesture than one person's takes?

The live recognizer accepts a candidate as a gesture only within size limits set from the
gesture's demonstrations: ``size_factor`` times smaller than the smallest, ``size_growth`` times
larger than the largest. This script asks the real recordings of ``machete_vive`` (six people, two
controllers, 11 whole-body gestures × 5) how often another person's performance falls outside
such a range: for every controller, gesture and person, the sizes of the five takes (screw-path
length of the whole gesture, measured as the recognizer measures its demonstrations) give a range,
and every performance of the same gesture by the other five people is checked against it, for
several factors.

Usage::

    python benchmarks/real_sizes.py [--data ../shared/data/machete_vive] [--json out.json]
"""

from __future__ import annotations

import json
from pathlib import Path

from framefree.benchmark.take_geometry import (
    by_name,
    other_peoples,
    people_data_args,
    take_geometry,
)
from framefree.online import RecognizerConfig

FACTORS = (1.25, 1.5, 2.0, 2.5, 3.0)


def sizes_of_every_recording(data: Path, config: RecognizerConfig) -> dict:
    """{(controller, person, gesture): [size [m] of each take]}
    (:func:`~framefree.benchmark.take_geometry.take_geometry`)."""
    return {key: [size for _, size, _, _ in takes]
            for key, takes in take_geometry(data, config).items()}


def outside(sizes: dict, factor: float) -> dict:
    """How many of the other people's performances lie more than ``factor`` above the largest
    or below the smallest of each person's takes."""
    checked = above = below = 0
    for key, own in sizes.items():
        lo, hi = min(own), max(own)
        others = other_peoples(sizes, key)
        checked += len(others)
        above += sum(s > hi * factor for s in others)
        below += sum(s < lo / factor for s in others)
    return {"factor": factor, "checked": checked, "above": above, "below": below,
            "above_fraction": above / max(checked, 1), "below_fraction": below / max(checked, 1)}


def main() -> None:
    args = people_data_args(__doc__)
    config = RecognizerConfig()
    sizes = sizes_of_every_recording(args.data, config)
    rows = [outside(sizes, f) for f in FACTORS]
    print(f"{len(sizes)} (controller, person, gesture) sets of takes")
    for r in rows:
        print(f"factor {r['factor']:4}: {r['above']:4d} of {r['checked']} other people's "
              f"performances larger ({100 * r['above_fraction']:.1f} %), {r['below']:4d} smaller "
              f"({100 * r['below_fraction']:.1f} %)")
    if args.json:
        args.json.write_text(json.dumps({"L": config.descriptor.L, "rows": rows, "sizes": by_name(sizes)},
                                        indent=1))


if __name__ == "__main__":
    main()
