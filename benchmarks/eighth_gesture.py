"""An eighth gesture taught from a few demonstrations: per-gesture F1 on held-out simulated people.

The path a user takes with ``framefree record / enroll``, in Python:

1. the replica's person (who recorded the HPM seven) performs the new gesture ``--takes`` times in
   one recording, resting between performances; :func:`framefree.library.split_takes` cuts it;
2. the HPM seven (replica, *original_1*) plus these takes are enrolled once
   (:func:`framefree.library.enroll`), saved and loaded back (no recalibration);
3. held-out simulated people (:data:`framefree.replica.HELDOUT_PEOPLE`, never used to tune
   anything) perform sessions that include the new gesture; every stream is run through the
   loaded recognizer (:func:`framefree.online.evaluation.run_stream`);
4. per-gesture precision, recall and F1 are printed and written as JSON, with the same for the
   seven-gesture library on the same streams (``--no-baseline`` skips it), to see whether the
   seven keep their F1.

Run::

    python benchmarks/eighth_gesture.py --gesture figure_eight --people 3 --json out.json
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from framefree.core.trajectory import Trajectory
from framefree.datasets import GESTURES
from framefree.library import (
    TakeSet,
    enroll,
    join_recordings,
    load_recognizer,
    read_takes,
    split_takes,
)
from framefree.online.evaluation import match_events, run_stream
from framefree.replica import (
    DEV_PEOPLE,
    FRESH_PEOPLE,
    HELDOUT_PEOPLE,
    make_person_streams,
    replica_path,
    synthesize_gesture,
)


def demonstration(gesture: str, takes: int, seed: int) -> Trajectory:
    """One recording of ``takes`` performances (with the replica person's rests between them)."""
    rng = np.random.default_rng([seed, 8])
    return join_recordings([synthesize_gesture(gesture, rng) for _ in range(takes)],
                           source=f"{gesture} demonstration")


def per_gesture(results: Sequence[Any], labels: Sequence[str],
                ignore: Sequence[Sequence[tuple[float, float]]] | None = None,
                ) -> dict[str, dict[str, float]]:
    """Precision, recall and F1 per label from matched events (see ``match_events``); a false
    positive whose time lies in one of ``ignore[k]`` (spans [s] of stream ``k``) is not counted."""
    ignore = ignore or [()] * len(results)

    def counted(d: dict, spans: Sequence[tuple[float, float]]) -> bool:
        return d["verdict"] == "tp" or not any(a <= d["time"] <= b for a, b in spans)

    out = {}
    for g in labels:
        tp = sum(1 for r in results for d in r.details if d["label"] == g and d["verdict"] == "tp")
        fp = sum(1 for r, spans in zip(results, ignore, strict=True) for d in r.details
                 if d["label"] == g and d["verdict"] != "tp" and counted(d, spans))
        fn = sum(1 for r in results for m in r.missed if m["label"] == g)
        p = tp / (tp + fp) if tp + fp else 1.0
        rc = tp / (tp + fn) if tp + fn else 1.0
        out[g] = {"tp": tp, "fp": fp, "fn": fn, "precision": p, "recall": rc,
                  "f1": 2 * p * rc / (p + rc) if p + rc else 0.0}
    return out


def evaluate(library: Path, streams: Sequence[Any], labels: Sequence[str],
             new_gesture: str | None = None) -> dict[str, Any]:
    """Run every stream through the library's recognizer; per-gesture and pooled metrics.

    With ``new_gesture`` (a library without it), also ``per_gesture_without_new``: the metrics when
    the new gesture's performances are not counted (neither its misses nor the events during
    them), which is what the seven would score on sessions without it.
    """
    rec = load_recognizer(library)
    rec.warmup()
    results = []
    for s in streams:
        events, _ = run_stream(rec, s.traj)
        results.append(match_events(events, s.segments, s.traj.duration))
    pooled = per_gesture(results, labels)
    extra = {}
    if new_gesture is not None:
        spans = [[(g.start_t, g.end_t + 0.5) for g in s.segments if g.label == new_gesture]
                 for s in streams]
        extra["per_gesture_without_new"] = per_gesture(results, labels, spans)
    tp = sum(v["tp"] for v in pooled.values())
    fp = sum(r.fp for r in results)
    fn = sum(v["fn"] for v in pooled.values())
    p, r = tp / max(tp + fp, 1), tp / max(tp + fn, 1)
    return {"per_gesture": pooled, **extra,
            "total": {"tp": tp, "fp": fp, "fn": fn, "precision": p, "recall": r,
                      "f1": 2 * p * r / (p + r) if p + r else 0.0}}


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gesture", default="figure_eight", help="the new gesture (figure_eight, push_twist)")
    ap.add_argument("--takes", type=int, default=5, help="demonstrations of the new gesture")
    ap.add_argument("--demo-seed", type=int, default=0, help="seed of the demonstration recording")
    ap.add_argument("--people", type=int, default=3, help="number of held-out people")
    ap.add_argument("--first-person", type=int, default=0, help="index of the first one in the group")
    ap.add_argument("--people-group", choices=["heldout", "fresh", "dev"], default="heldout",
                    help="HELDOUT_PEOPLE or FRESH_PEOPLE (report), DEV_PEOPLE (to choose settings)")
    ap.add_argument("--set", action="append", default=[], help="recognizer setting KEY=VALUE (JSON value)")
    ap.add_argument("--streams-per-person", type=int, default=2)
    ap.add_argument("--n-gestures", type=int, default=16, help="gestures per stream")
    ap.add_argument("--no-baseline", action="store_true", help="skip the seven-gesture library")
    ap.add_argument("--work", default="eighth_gesture_work", help="folder for the library files")
    ap.add_argument("--json", default=None, help="write the results here")
    args = ap.parse_args(argv)

    work = Path(args.work)
    t0 = time.perf_counter()
    takes = split_takes(demonstration(args.gesture, args.takes, args.demo_seed))
    if len(takes) != args.takes:
        print(f"warning: the demonstration was cut into {len(takes)} takes, not {args.takes}")
    hpm = read_takes(replica_path(), "original_1")
    new = TakeSet(tuple(takes), (args.gesture,) * len(takes),
                  tuple(f"{args.gesture}/own/trial_{k + 1}" for k in range(len(takes))))
    settings = {kv.split("=", 1)[0]: json.loads(kv.split("=", 1)[1]) for kv in args.set}
    lib8 = enroll(hpm + new, built_from=[str(replica_path()), f"{args.gesture} demonstration"],
                  **settings)
    path8 = lib8.save(work / "hpm_plus_one.npz")
    t_enroll = time.perf_counter() - t0

    group = {"heldout": HELDOUT_PEOPLE, "fresh": FRESH_PEOPLE, "dev": DEV_PEOPLE}[args.people_group]
    people = list(group)[args.first_person: args.first_person + args.people]
    labels = [*GESTURES, args.gesture]
    streams = make_person_streams(people, args.streams_per_person, n_gestures=args.n_gestures,
                                  gestures=labels, progress=True)
    out: dict[str, Any] = {
        "gesture": args.gesture, "takes": len(takes), "people": people,
        "people_group": args.people_group,
        "streams": [(s.person_seed, s.stream_seed) for s in streams],
        "enroll_s": t_enroll, "thresholds": lib8.gesture_thresholds,
        "with_new_gesture": evaluate(path8, streams, [*labels, "stop"]),
    }
    if not args.no_baseline:
        path7 = enroll(hpm, built_from=[str(replica_path())], **settings).save(work / "hpm.npz")
        out["seven_only"] = evaluate(path7, streams, [*labels, "stop"], new_gesture=args.gesture)
    _print(out)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    return out


def _print(out: dict[str, Any]) -> None:
    both = "seven_only" in out
    group = out.get("people_group", "heldout")
    print(f"{out['gesture']}: {out['takes']} takes; {group} people {out['people']}, "
          f"{len(out['streams'])} streams")
    print(f"{'gesture':<16}{'F1 (8 gestures)':>16}"
          + (f"{'F1 (HPM seven)':>16}{'(new not counted)':>19}" if both else ""))
    for g, m in out["with_new_gesture"]["per_gesture"].items():
        base = ""
        if both:
            alone = out["seven_only"]["per_gesture_without_new"][g]["f1"]
            base = f"{100 * out['seven_only']['per_gesture'][g]['f1']:15.1f}%{100 * alone:18.1f}%"
        print(f"{g:<16}{100 * m['f1']:15.1f}%{base}   (TP {m['tp']} FP {m['fp']} FN {m['fn']})")
    tot = out["with_new_gesture"]["total"]
    base = f"{100 * out['seven_only']['total']['f1']:15.1f}%" if both else ""
    print(f"{'all':<16}{100 * tot['f1']:15.1f}%{base}")


if __name__ == "__main__":
    main()
