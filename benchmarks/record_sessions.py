"""Does ``framefree record`` cut one recording of five performances into exactly those five takes?

Each simulated person (:mod:`framefree.replica.people`) records every gesture five times in one
go, as ``framefree record`` asks (:func:`framefree.replica.people_streams.take_session`: rest,
perform, rest, move back to the start, rest, perform, ...). The recording is pushed sample by
sample through :class:`framefree.library.TakeRecorder`; a session is *cut right* when it returns
exactly five takes and each holds more than half of one labelled performance (the
smallest such share is reported too: a take may leave out a slow start), and none reaches more
than ``RUN_ON`` seconds beyond either end of its performance (as a take that holds the way back
after it, or a move before it, does). People who pause at the
turning point of a gesture for longer than the recorder's shortest rest used to lose it to two
halves; ``--pause-ratio 0`` turns joining off to show that.

Usage::

    python benchmarks/record_sessions.py --people-group dev --people 20 [--rest 1.2,2.0]
        [--pause-ratio 0.6] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from tqdm.auto import tqdm

from framefree.datasets import GESTURES
from framefree.library import TakeRecorder
from framefree.replica import (
    DEV_PEOPLE,
    DEV_SHAPES,
    FRESH_SHAPES,
    HELDOUT_PEOPLE,
    HELDOUT_SHAPES,
    person,
)
from framefree.replica.people_streams import take_session

N_TAKES = 5
#: Farthest a take may reach beyond either end of its performance [s] and still be cut right:
#: more than a performance that ends slowly runs on (up to 0.8 s on the replica's development
#: people), less than a take holding its way back (2.4 s or more).
RUN_ON = 1.0


def cut_right(gesture: str, person_seed: int, rest: tuple[float, float], pause_ratio: float
              ) -> tuple[bool, dict[str, Any]]:
    """Record one session; whether it was cut into its five performances, and what was found."""
    session = take_session(gesture, person(person_seed), N_TAKES, seed=person_seed, rest=rest)
    rec = TakeRecorder(pause_ratio=pause_ratio)
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        rec.push(t, p, q)
    takes = [span for span, _ in rec.finish()]
    covered, shares, run_on = [], [], []
    for span in takes:
        share = [(min(span.end, seg.end_t) - max(span.onset, seg.start_t)) / (seg.end_t - seg.start_t)
                 for seg in session.segments]
        best = max(range(len(share)), key=share.__getitem__)
        covered.append(best if share[best] > 0.5 else None)
        shares.append(share[best])
        seg = session.segments[best]
        run_on.append(max(span.end - seg.end_t, seg.start_t - span.onset))
    ok = covered == list(range(N_TAKES)) and max(run_on, default=0.0) <= RUN_ON
    return ok, {"gesture": gesture, "person": person_seed, "takes": covered, "smallest_share":
                min(shares, default=0.0), "left_out": [why for _, why in rec.left_out],
                "joined": len(rec.joined), "longest_run_on": max(run_on, default=0.0)}


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--people-group", choices=["dev", "heldout"], default="dev")
    ap.add_argument("--people", type=int, default=20)
    ap.add_argument("--rest", default="1.2,2.0", help="range of each rest [s] (take_session)")
    ap.add_argument("--pause-ratio", type=float, default=0.6, help="TakeRecorder.pause_ratio (0: no joining)")
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    people = list(DEV_PEOPLE if args.people_group == "dev" else HELDOUT_PEOPLE)[: args.people]
    shapes = DEV_SHAPES if args.people_group == "dev" else HELDOUT_SHAPES + FRESH_SHAPES
    rest = tuple(float(x) for x in args.rest.split(","))
    per_gesture: dict[str, int] = {}
    wrong, smallest = [], []
    jobs = [(g, p) for g in (*shapes, *GESTURES) for p in people]
    for g, p in tqdm(jobs, desc="sessions"):
        ok, found = cut_right(g, p, rest, args.pause_ratio)
        per_gesture[g] = per_gesture.get(g, 0) + ok
        if ok:
            smallest.append(found["smallest_share"])
        else:
            wrong.append(found)
    total = sum(per_gesture.values())
    for g, n in per_gesture.items():
        print(f"{g:14s} {n:3d} / {len(people)} cut right")
    print(f"all            {total:3d} / {len(jobs)} cut right (pause ratio {args.pause_ratio}, "
          f"rests {rest} s); the smallest share of a performance in its take: {min(smallest):.2f}")
    out = {"people_group": args.people_group, "people": people, "rest": rest,
           "pause_ratio": args.pause_ratio, "cut_right": per_gesture, "sessions": len(jobs),
           "total": total, "smallest_share": min(smallest), "wrong": wrong}
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
