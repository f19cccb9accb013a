"""An eighth gesture taught from a few demonstrations: per-gesture F1 on held-out simulated people.

The path a user takes with ``framefree record / enroll``, in Python:

1. the replica's person (who recorded the HPM seven) performs the new gesture ``--takes`` times in
   one recording, resting between performances and moving the hand back to the start
   (:func:`framefree.replica.people_streams.take_session`); :class:`framefree.library.TakeRecorder`
   cuts it as ``framefree record`` does, leaving out the ways back (``--keep-all`` keeps them);
2. the HPM seven (replica, *original_1*) plus these takes are enrolled once
   (:func:`framefree.library.enroll`), saved and loaded back (no recalibration);
3. held-out simulated people (:data:`framefree.replica.HELDOUT_PEOPLE`, never used to tune
   anything) perform sessions that include the new gesture and shapes nobody enrolled
   (``--distractors``: by default the development shapes, :data:`framefree.replica.DEV_SHAPES`;
   ``--distractors heldout`` and ``fresh`` the shapes kept out of every choice); those are not
   labelled, so any event during them is a false positive; every stream is run through the loaded recognizer
   (:func:`framefree.online.evaluation.run_stream`);
4. per-gesture precision, recall and F1 are printed and written as JSON, with the same for the
   seven-gesture library on the same streams (``--no-baseline`` skips it), to see whether the
   seven keep their F1.

Run::

    python benchmarks/eighth_gesture.py --gesture figure_eight --people 3 --json out.json
    python benchmarks/eighth_gesture.py --gesture zigzag --people 2 --streams-per-person 4 \
        --people-group dev
    python benchmarks/eighth_gesture.py --gesture check_mark --people 10 --demo-seed 0-4  # 5 demonstrators
"""

from __future__ import annotations

import argparse
import json
import re
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from framefree.core.trajectory import Trajectory
from framefree.datasets import GESTURES
from framefree.library import TakeRecorder, TakeSet, enroll, load_recognizer, read_takes
from framefree.library.inside import fired_inside
from framefree.online.diagnosis import explain, logging_candidates
from framefree.online.evaluation import match_events, run_stream
from framefree.replica import (
    DEFAULT_PERSON,
    DEV_PEOPLE,
    DEV_SHAPES,
    FRESH_PEOPLE,
    FRESH_SHAPES,
    HELDOUT_PEOPLE,
    HELDOUT_SHAPES,
    make_person_streams,
    replica_path,
)
from framefree.replica.people_streams import take_session


def recorded_takes(gesture: str, takes: int, seed: int, keep_all: bool = False) -> list[Trajectory]:
    """The replica's person records ``takes`` performances in one go; the takes ``record`` keeps."""
    session = take_session(gesture, DEFAULT_PERSON, takes, seed=seed)
    recorder = TakeRecorder(keep_all=keep_all)
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        recorder.push(t, p, q)
    return [take for _, take in recorder.finish()]


def _distractors(name: str, gesture: str) -> list[str]:
    families = {"dev": DEV_SHAPES, "heldout": HELDOUT_SHAPES, "fresh": FRESH_SHAPES}
    if name in families:
        return [s for s in families[name] if s != gesture]
    return [s for s in name.split(",") if s and s != gesture]


def _unlabelled(streams: Sequence[Any], shapes: Sequence[str]) -> list[Any]:
    """The streams with the distractor shapes' segments dropped: events during them count as
    false positives (:func:`_during` says which)."""
    return [s._replace(segments=[g for g in s.segments if g.label not in shapes]) for s in streams]


def _during(streams: Sequence[Any], results: Sequence[Any], shapes: Sequence[str]) -> dict[str, int]:
    """False positives per distractor shape they fired during (0.5 s tolerance after it)."""
    out: dict[str, int] = {}
    for s, r in zip(streams, results, strict=True):
        spans = [(g.label, g.start_t, g.end_t + 0.5) for g in s.segments if g.label in shapes]
        for d in r.details:
            if d["verdict"] != "tp":
                hit = [lab for lab, a, b in spans if a <= d["time"] <= b]
                key = f"{d['label']} during {hit[0]}" if hit else f"{d['label']} elsewhere"
                out[key] = out.get(key, 0) + 1
    return out


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
             new_gesture: str | None = None, distractors: Sequence[str] = ()) -> dict[str, Any]:
    """Run every stream through the library's recognizer; per-gesture and pooled metrics.

    With ``new_gesture`` (a library without it), also ``per_gesture_without_new``: the metrics when
    the new gesture's performances are not counted (neither its misses nor the events during
    them), which is what the seven would score on sessions without it.
    """
    rec = load_recognizer(library)
    rec.warmup()
    results = []
    reasons: dict[str, dict[str, int]] = {}  # why each gesture was missed (diagnosis.explain)
    for s in _unlabelled(streams, distractors):
        with logging_candidates(rec) as log:
            events, _ = run_stream(rec, s.traj)
        results.append(match_events(events, s.segments, s.traj.duration))
        for miss in explain(results[-1], s.segments, log, rec.labels, rec.spotter)["missed"]:
            by = reasons.setdefault(miss["label"], {})
            by[miss["reason"]] = by.get(miss["reason"], 0) + 1
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
    extra["false_positives_during"] = _during(streams, results, distractors)
    extra["miss_reasons"] = reasons
    return {"per_gesture": pooled, **extra,
            "total": {"tp": tp, "fp": fp, "fn": fn, "precision": p, "recall": r,
                      "f1": 2 * p * r / (p + r) if p + r else 0.0}}


def main(argv: Sequence[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gesture", default="figure_eight", help="the new gesture (figure_eight, push_twist)")
    ap.add_argument("--takes", type=int, default=5, help="demonstrations of the new gesture")
    ap.add_argument("--keep-all", action="store_true",
                    help="enroll every move the recorder cut, the ways back included")
    ap.add_argument("--distractors", default="dev",
                    help="shapes performed but not enrolled: dev (DEV_SHAPES), heldout (HELDOUT_SHAPES), "
                    "fresh (FRESH_SHAPES), a comma-separated list, or '' for none")
    ap.add_argument("--demo-seed", default="0",
                    help="seed of the demonstration recording; several ('0-4' or '0,2,5'): one "
                    "demonstration after the other on the same streams, and a table of them")
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
    seeds = demo_seeds(args.demo_seed)
    if len(seeds) == 1:
        return run(args, seeds[0], Path(args.work))
    runs = {seed: run(args, seed, Path(args.work) / f"demo_{seed}", write=False) for seed in seeds}
    _print_demonstrations(args.gesture, runs)
    out = {"gesture": args.gesture, "by_demo_seed": runs}
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    return out


def demo_seeds(text: str) -> list[int]:
    """``'3'`` → [3], ``'0-4'`` → [0, 1, 2, 3, 4], ``'0,2,5'`` → [0, 2, 5]."""
    seeds: list[int] = []
    for part in text.split(","):
        match = re.fullmatch(r"\s*(\d+)(?:-(\d+))?\s*", part)
        if match is None or int(match[2] or match[1]) < int(match[1]):
            raise SystemExit(f"--demo-seed: {part.strip()!r} is not a seed or a range (0-4)")
        seeds.extend(range(int(match[1]), int(match[2] or match[1]) + 1))
    return seeds


def run(args: argparse.Namespace, demo_seed: int, work: Path, write: bool = True) -> dict[str, Any]:
    """One demonstration (``demo_seed``) enrolled and evaluated on the people's streams."""
    t0 = time.perf_counter()
    takes = recorded_takes(args.gesture, args.takes, demo_seed, args.keep_all)
    if len(takes) != args.takes:
        print(f"note: the recording was cut into {len(takes)} takes for {args.takes} performances")
    shapes = _distractors(args.distractors, args.gesture)
    hpm = read_takes(replica_path(), "original_1")
    new = TakeSet(tuple(takes), (args.gesture,) * len(takes),
                  tuple(f"{args.gesture}/own/trial_{k + 1}" for k in range(len(takes))))
    settings = {kv.split("=", 1)[0]: json.loads(kv.split("=", 1)[1]) for kv in args.set}
    lib8 = enroll(hpm + new, built_from=[str(replica_path()), f"{args.gesture} demonstration"],
                  **settings)
    path8 = lib8.save(work / "hpm_plus_one.npz")
    t_enroll = time.perf_counter() - t0
    inside = fired_inside(load_recognizer(path8), hpm + new)  # what ``framefree check`` replays

    group = {"heldout": HELDOUT_PEOPLE, "fresh": FRESH_PEOPLE, "dev": DEV_PEOPLE}[args.people_group]
    people = list(group)[args.first_person: args.first_person + args.people]
    labels = [*GESTURES, args.gesture]
    streams = make_person_streams(people, args.streams_per_person, n_gestures=args.n_gestures,
                                  gestures=[*labels, *shapes], progress=True)
    out: dict[str, Any] = {
        "gesture": args.gesture, "demo_seed": demo_seed, "takes": len(takes), "people": people,
        "people_group": args.people_group,
        "streams": [(s.person_seed, s.stream_seed) for s in streams],
        "enroll_s": t_enroll, "thresholds": lib8.gesture_thresholds, "fired_inside": inside,
        "distractors": shapes,
        "with_new_gesture": evaluate(path8, streams, [*labels, "stop"], distractors=shapes),
    }
    if not args.no_baseline:
        path7 = enroll(hpm, built_from=[str(replica_path())], **settings).save(work / "hpm.npz")
        out["seven_only"] = evaluate(path7, streams, [*labels, "stop"], new_gesture=args.gesture,
                                     distractors=shapes)
    _print(out)
    if args.json and write:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(out, indent=1, default=float))
    return out


def _print_demonstrations(gesture: str, runs: dict[int, dict[str, Any]]) -> None:
    """One row per demonstration: the new gesture's counts, the seven's and every gesture's F1."""
    print(f"\n{gesture}, one row per demonstration (the same people's streams)")
    print(f"{'demo seed':<10}{'new: TP / FP / FN':>20}{'F1':>8}{'the seven: TP / FP / FN':>26}"
          f"{'all F1':>9}  takes that fire another gesture (framefree check)")
    for seed, out in runs.items():
        per = out["with_new_gesture"]["per_gesture"]
        new = per[gesture]
        seven = [sum(m[k] for g, m in per.items() if g not in (gesture, "stop"))
                 for k in ("tp", "fp", "fn")]
        print(f"{seed:<10}{new['tp']:>8} / {new['fp']:>3} / {new['fn']:>3}{100 * new['f1']:7.1f}%"
              f"{seven[0]:>14} / {seven[1]:>3} / {seven[2]:>3}"
              f"{100 * out['with_new_gesture']['total']['f1']:8.1f}%  "
              + (", ".join(f"{len(names)} {g} fire {other}"
                           for g, by in out.get("fired_inside", {}).items()
                           for other, names in by.items()) or "none"))


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
    print("false positives:", out["with_new_gesture"]["false_positives_during"])
    print("misses by reason:", out["with_new_gesture"]["miss_reasons"])


if __name__ == "__main__":
    main()
