"""Do real people pause inside a gesture where one person did not? The one-go rule, checked on others.

Since v14 the live recognizer treats a gesture whose demonstrations do not rest inside (the
median, over its takes, of the longest rest between two movement units is below ``confirm``) as
performed in one go: a candidate for it may rest at most ``min_pause`` inside. This script asks
the real recordings of ``machete_vive`` (six people, two controllers, 11 whole-body gestures × 5)
how often another person pauses longer: for every controller, gesture and person whose takes
are performed in one go, every performance of the same gesture by the other five people is
checked against ``min_pause``.

Usage::

    python benchmarks/real_pauses.py [--data ../shared/data/machete_vive] [--json out.json]
"""

from __future__ import annotations

import json

import numpy as np

from framefree.benchmark.take_geometry import by_name, other_peoples, people_data_args, take_rests
from framefree.online import RecognizerConfig


def refused(rests: dict, one_go_below: float, allowed: float) -> dict:
    """How many of the other people's performances pause longer than ``allowed`` [s] inside a
    gesture that a person performed in one go (median longest rest below ``one_go_below``)."""
    sets = checked = over = 0
    by_gesture: dict[str, int] = {}
    for key, own in rests.items():
        if len(own) < 2 or float(np.median(own)) >= one_go_below:
            continue
        sets += 1
        others = other_peoples(rests, key)
        checked += len(others)
        n = sum(r > allowed for r in others)
        over += n
        by_gesture[key[2]] = by_gesture.get(key[2], 0) + n
    return {"one_go_below": one_go_below, "allowed": allowed, "one_go_sets": sets,
            "sets": len(rests), "checked": checked, "refused": over,
            "fraction": over / max(checked, 1), "by_gesture": by_gesture}


def main() -> None:
    args = people_data_args(__doc__)
    config = RecognizerConfig()
    rests = take_rests(args.data, config)
    every = np.concatenate([np.asarray(v) for v in rests.values()])
    print(f"{every.size} takes; longest rest at a corner, quantiles 50/75/90/99 %: "
          + ", ".join(f"{q:.2f}" for q in np.quantile(every, [0.5, 0.75, 0.9, 0.99])) + " s")
    rows = [refused(rests, config.confirm, allowed)
            for allowed in (config.constants.min_pause, 0.75, 1.0)]
    for r in rows:
        print(f"one go below {r['one_go_below']:.2f} s, {r['allowed']:.2f} s allowed: "
              f"{r['one_go_sets']} of {r['sets']} (controller, person, gesture) sets in one go; "
              f"{r['refused']} of {r['checked']} other people's performances pause longer "
              f"({100 * r['fraction']:.1f} %) {r['by_gesture']}")
    if args.json:
        args.json.write_text(json.dumps({"confirm": config.confirm, "min_pause": config.constants.min_pause,
                                         "rows": rows, "rests": by_name(rests)}, indent=1))


if __name__ == "__main__":
    main()
