"""Do real people's corners agree? A corner limit set from one person's takes, checked on the others.

The live recognizer accepts a candidate as a gesture only with no more corners (turns of the
hand's heading of more than ``corner_angle`` between two movement units) than the gesture's
demonstrations agree on, plus ``corner_slack``. This script asks the real recordings of
``machete_vive`` (six people, two controllers, 11 whole-body gestures × 5) how often another
person exceeds such a limit: for every controller, gesture and person whose five takes agree on
their number of corners, every performance of the same gesture by the other five people is
counted against it, for slacks 0, 1 and 2.

Usage::

    python benchmarks/real_corners.py [--data ../shared/data/machete_vive] [--json out.json]
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
from framefree.online.limits import corner_limit


def corners_of_every_recording(data: Path, config: RecognizerConfig) -> dict:
    """{(controller, person, gesture): [corners of each take]}
    (:func:`~framefree.benchmark.take_geometry.take_geometry`)."""
    return {key: [n for _, _, n, _ in takes] for key, takes in take_geometry(data, config).items()}


def exceeded(corners: dict, slack: int) -> dict:
    """How many of the other people's performances exceed each agreeing person's limit."""
    limits = checked = over = 0
    by_gesture: dict[str, int] = {}
    for key, counts in corners.items():
        limit = corner_limit(counts, slack)
        if limit is None:
            continue
        limits += 1
        others = other_peoples(corners, key)
        checked += len(others)
        n = sum(c > limit for c in others)
        over += n
        by_gesture[key[2]] = by_gesture.get(key[2], 0) + n
    return {"slack": slack, "limits": limits, "sets": len(corners), "checked": checked,
            "exceeded": over, "fraction": over / max(checked, 1), "by_gesture": by_gesture}


def main() -> None:
    args = people_data_args(__doc__)
    config = RecognizerConfig()
    corners = corners_of_every_recording(args.data, config)
    rows = [exceeded(corners, slack) for slack in (0, 1, 2)]
    for r in rows:
        print(f"slack {r['slack']}: limits for {r['limits']} of {r['sets']} (controller, gesture, "
              f"person) sets of takes; {r['exceeded']} of {r['checked']} other people's "
              f"performances exceed them ({100 * r['fraction']:.1f} %)")
    if args.json:
        args.json.write_text(json.dumps({"corner_angle": config.corner_angle, "L": config.L,
                                         "rows": rows, "corners": by_name(corners)}, indent=1))


if __name__ == "__main__":
    main()
