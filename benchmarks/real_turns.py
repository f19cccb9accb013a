"""Do real people turn the same way? A turn limit set from one person's takes, checked on the others.

The live recognizer refuses a candidate as a gesture when two of its corners turn in a way the
gesture's demonstrations never do (:func:`framefree.online.limits.forbidden_turns`): every
pair of corners the same way (a triangle, a square) or every pair back (a Z). This script asks the
real recordings of ``machete_vive`` (six people, two controllers, 11 whole-body gestures × 5)
how often another person's performance would be refused by such a limit: for every controller,
gesture and person whose takes all turn one way only, every performance of the same gesture by
the other five people is counted against it.

Usage::

    python benchmarks/real_turns.py [--data ../shared/data/machete_vive] [--json out.json]
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
from framefree.online.limits import forbidden_turns


def turns_of_every_recording(data: Path, config: RecognizerConfig) -> dict:
    """{(controller, person, gesture): [turn kinds of each take]}
    (:func:`~framefree.benchmark.take_geometry.take_geometry`)."""
    return {key: [kinds for *_, kinds in takes] for key, takes in take_geometry(data, config).items()}


def refused(turns: dict) -> dict:
    """How many of the other people's performances show a turn each agreeing person never made."""
    limits = checked = over = 0
    by_gesture: dict[str, int] = {}
    kinds_of_limits: dict[int, int] = {}
    for key, kinds in turns.items():
        never = forbidden_turns(kinds)
        if not never:
            continue
        limits += 1
        kinds_of_limits[never] = kinds_of_limits.get(never, 0) + 1
        others = other_peoples(turns, key)
        checked += len(others)
        n = sum(bool(k & never) for k in others)
        over += n
        by_gesture[key[2]] = by_gesture.get(key[2], 0) + n
    return {"limits": limits, "sets": len(turns), "forbidden": kinds_of_limits, "checked": checked,
            "refused": over, "fraction": over / max(checked, 1), "by_gesture": by_gesture}


def main() -> None:
    args = people_data_args(__doc__)
    config = RecognizerConfig()
    turns = turns_of_every_recording(args.data, config)
    r = refused(turns)
    print(f"limits for {r['limits']} of {r['sets']} (controller, person, gesture) sets of takes "
          f"(forbidden kinds: {r['forbidden']}); {r['refused']} of {r['checked']} other people's "
          f"performances show a forbidden turn ({100 * r['fraction']:.1f} %); by gesture "
          f"{r['by_gesture']}")
    if args.json:
        args.json.write_text(json.dumps({"corner_angle": config.constants.corner_angle,
                                         "L": config.descriptor.L,
                                         "result": r, "turns": by_name(turns)}, indent=1))


if __name__ == "__main__":
    main()
