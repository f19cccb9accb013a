"""Do real people's corners agree? A corner limit set from one person's takes, checked on the others.

The live recognizer accepts a candidate as a gesture only with no more corners (turns of the
hand's heading of more than ``corner_angle`` between two movement units) than the gesture's
demonstrations agree on, plus ``corner_slack``. This script asks the real recordings of
``machete_vive`` (six people, two controllers, 11 whole-body gestures × 5) how often another
person exceeds such a limit: for every controller, gesture and person whose five takes agree on
their number of corners, every performance of the same gesture by the other five people is
counted against it, for slacks 0, 1 and 2, and with v15's rule (the slack only for gestures
whose takes agree on at most ``slack_corners`` corners); then, with no slack, by the number of
corners the person's takes agree on.

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


def exceeded(corners: dict, slack: int, smooth: int | None = None) -> dict:
    """How many of the other people's performances exceed each agreeing person's limit."""
    limits = checked = over = 0
    by_gesture: dict[str, int] = {}
    for key, counts in corners.items():
        limit = corner_limit(counts, slack, smooth)
        if limit is None:
            continue
        limits += 1
        others = other_peoples(corners, key)
        checked += len(others)
        n = sum(c > limit for c in others)
        over += n
        by_gesture[key[2]] = by_gesture.get(key[2], 0) + n
    return {"slack": slack, "smooth": smooth, "limits": limits, "sets": len(corners), "checked": checked,
            "exceeded": over, "fraction": over / max(checked, 1), "by_gesture": by_gesture}


def main() -> None:
    args = people_data_args(__doc__)
    config = RecognizerConfig()
    corners = corners_of_every_recording(args.data, config)
    rows = [exceeded(corners, slack) for slack in (0, 1, 2)]
    rows.append(exceeded(corners, config.constants.corner_slack, config.constants.slack_corners))
    for r in rows:
        rule = "" if r["smooth"] is None else f" up to {r['smooth']} corner(s), none above"
        print(f"slack {r['slack']}{rule}: limits for {r['limits']} of {r['sets']} (controller, gesture, "
              f"person) sets of takes; {r['exceeded']} of {r['checked']} other people's "
              f"performances exceed them ({100 * r['fraction']:.1f} %)")
    by_count = {}
    for key, own in corners.items():
        if corner_limit(own, 0) is not None:
            others = other_peoples(corners, key)
            n, over = by_count.get(own[0], (0, 0))
            by_count[own[0]] = (n + len(others), over + sum(c > own[0] for c in others))
    for k, (n, over) in sorted(by_count.items()):
        print(f"takes agreeing on {k} corner(s): {over} of {n} other people's performances have more")
    if args.json:
        args.json.write_text(json.dumps({"corner_angle": config.constants.corner_angle,
                                         "L": config.descriptor.L,
                                         "rows": rows, "by_agreed_count": by_count,
                                         "corners": by_name(corners)}, indent=1))


if __name__ == "__main__":
    main()
