"""Live recognition on streams of simulated people: tune on some, report on others.

Models: the replica's ``original_1`` recordings (one person, the replica's). Streams: sessions of
people drawn from the population of :mod:`framefree.replica.people` — ``--people dev`` (seeds
0-19, the only ones used to choose parameters), ``--people heldout`` (seeds 1000-1019) or
``--people fresh`` (seeds 2000-2019, a second held-out group; both only for reporting once the
parameters are frozen). The methods can run side by side on the same streams:
``segments`` (framefree's recognizer), ``paper`` (the paper's) and ``window`` (a practitioner's
sliding-window 1-NN baseline); ``both`` runs the first two, ``all`` the three.

Prints per-person and pooled precision / recall / F1, false positives per minute of non-gesture
motion, the detection latency after the gesture's end, misses per gesture, and which activity each
false positive came from; ``--json`` writes it all.

    .venv/bin/python benchmarks/online_people.py --people dev --per-person 1 --method both
    .venv/bin/python benchmarks/online_people.py --people heldout --per-person 2 --json out.json
    .venv/bin/python benchmarks/online_people.py --people heldout --per-person 1 --method all
    .venv/bin/python benchmarks/online_people.py --people dev --set confirm=0.3
    .venv/bin/python benchmarks/online_people.py --people dev --style hesitant
    .venv/bin/python benchmarks/online_people.py --people dev --style hesitant --hesitation 1 \
        --hesitation-pause 0.4,0.7     # every stroke nearly stops for 0.4-0.7 s
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import time
from dataclasses import replace
from pathlib import Path

from joblib import Parallel, delayed

from framefree.datasets.layout import load_model_recordings
from framefree.online import Recognizer
from framefree.online.evaluation import combine, match_events, run_stream
from framefree.online.learned import split_settings
from framefree.online.paper import PaperRecognizer
from framefree.online.window_baseline import WindowSpotter
from framefree.replica import replica_path
from framefree.replica.people import (
    DEV_PEOPLE,
    FRESH_PEOPLE,
    HELDOUT_PEOPLE,
    STYLES,
    person,
    styled,
)
from framefree.replica.people_streams import make_person_streams, person_stream

_RECOGNIZERS: dict = {}


def _recognizer(method: str, overrides: dict):
    key = (method, json.dumps(overrides, sort_keys=True))
    if key not in _RECOGNIZERS:
        trajs, labels = load_model_recordings(replica_path(0), "original_1")
        cls = {"segments": Recognizer, "paper": PaperRecognizer, "window": WindowSpotter}[method]
        rec = cls.from_trajectories(trajs, labels, **overrides)
        rec.warmup()
        _RECOGNIZERS[key] = rec
    return _RECOGNIZERS[key]


def _activity_at(activities, t: float) -> str:
    """What the person was doing shortly before an event fired (the motion it was spotted in)."""
    kinds = [a.kind if a.kind != "gesture" else f"gesture:{a.label}" for a in activities
             if a.start_t <= t - 0.2 <= a.end_t]
    return kinds[-1] if kinds else "?"


def _evaluate(method: str, overrides: dict, item) -> dict:
    rec = _recognizer(method, overrides)
    events, _ = run_stream(rec, item.traj)
    res = match_events(events, item.segments, item.traj.duration)
    fps = [{"time": d["time"], "label": d["label"], "verdict": d["verdict"],
            "during": _activity_at(item.activities, d["time"])}
           for d in res.details if d["verdict"] != "tp"]
    return {"person": item.person_seed, "stream": item.stream_seed, "result": res,
            "false_positives": fps, "missed": res.missed}


def _parse_set(values: list[str]) -> dict:
    """``--set NAME=JSON`` values as recognizer settings; a malformed item, an unknown name or a
    value out of its range is one line on stderr and exit status 2."""
    out = {}
    for kv in values:
        k, sep, v = kv.partition("=")
        if not sep:
            _usage_error(f"--set: {kv!r}: expected NAME=JSON")
        try:
            out[k.strip()] = json.loads(v)
        except json.JSONDecodeError:
            out[k.strip()] = v
    try:
        split_settings(dict(out))
    except (TypeError, ValueError) as exc:
        _usage_error(f"--set: {exc}")
    return out


def _usage_error(message: str) -> None:
    print(f"error: {message}", file=sys.stderr)
    raise SystemExit(2)


def _report(method: str, rows: list[dict]) -> dict:
    pooled = combine([r["result"] for r in rows])
    per_person = collections.defaultdict(list)
    for r in rows:
        per_person[r["person"]].append(r["result"])
    misses = collections.Counter(m["label"] for r in rows for m in r["missed"])
    fp_kinds = collections.Counter(f"{f['label']} during {f['during']}" for r in rows
                                   for f in r["false_positives"])
    s = pooled.summary()
    print(f"\n== {method}: TP {s['tp']} FP {s['fp']} FN {s['fn']}  P {s['precision']:.3f} "
          f"R {s['recall']:.3f} F1 {s['f1']:.3f}  FP/min {s['fp_per_minute']:.3f}  "
          f"latency median {s['latency_median_s']}")
    for p, res in per_person.items():
        c = combine(res).summary()
        print(f"   person {p}: TP {c['tp']} FP {c['fp']} FN {c['fn']} F1 {c['f1']:.3f}")
    print("   misses:", dict(misses))
    print("   false positives:", dict(fp_kinds))
    return {"pooled": s, "per_person": {str(p): combine(v).summary() for p, v in per_person.items()},
            "misses": dict(misses), "false_positives": dict(fp_kinds),
            "streams": [{"person": r["person"], "stream": r["stream"], **r["result"].summary(),
                         "false_positive_details": r["false_positives"], "missed": r["missed"]}
                        for r in rows]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--people", default="dev", help="dev, heldout, fresh, or comma-separated seeds")
    ap.add_argument("--per-person", type=int, default=1, help="streams per person")
    ap.add_argument("--method", default="segments",
                    choices=["segments", "paper", "window", "both", "all"])
    ap.add_argument("--set", action="append", default=[], help="recognizer setting KEY=VALUE")
    ap.add_argument("--style", choices=list(STYLES), help="every person performs in this style "
                    "(framefree.replica.people.STYLES): hesitant (small, slow, trembling, near-stops) "
                    "or sloppy (large, fast, inconsistent)")
    ap.add_argument("--hesitation", type=float, default=None,
                    help="with --style: probability that a stroke nearly stops (hesitant: 0.25)")
    ap.add_argument("--hesitation-pause", default=None,
                    help="with --style: LO,HI range [s] of each near-stop (hesitant: 0.2,0.4)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    seeds = {"dev": DEV_PEOPLE, "heldout": HELDOUT_PEOPLE, "fresh": FRESH_PEOPLE}.get(args.people)
    if seeds is None:
        seeds = [int(s) for s in args.people.split(",")]
    overrides = _parse_set(args.set)
    t0 = time.perf_counter()
    if args.style is None:
        items = make_person_streams(seeds, n_streams_per_person=args.per_person, progress=True)
    else:  # the sessions of make_person_streams, performed in the style
        changes = {}
        if args.hesitation is not None:
            changes["hesitation"] = args.hesitation
        if args.hesitation_pause is not None:
            changes["hesitation_pause"] = tuple(float(x) for x in args.hesitation_pause.split(","))
        items = [person_stream(1000 * p + k, replace(styled(person(p), args.style), **changes))
                 for p in seeds for k in range(args.per_person)]
    print(f"{len(items)} streams, {sum(len(i.segments) for i in items)} labelled items, "
          f"{sum(i.traj.duration for i in items) / 60:.1f} min ({time.perf_counter() - t0:.0f} s)")
    methods = {"both": ["segments", "paper"], "all": ["segments", "paper", "window"]}.get(
        args.method, [args.method])
    out = {"people": args.people, "per_person": args.per_person, "style": args.style,
           "hesitation": args.hesitation, "hesitation_pause": args.hesitation_pause,
           "settings": overrides}
    for method in methods:
        rows = Parallel(n_jobs=args.jobs)(
            delayed(_evaluate)(method, overrides if method == "segments" else {}, it) for it in items)
        out[method] = _report(method, rows)
    print(f"\nwall {time.perf_counter() - t0:.0f} s")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
