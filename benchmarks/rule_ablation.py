"""Each rule of the live recognizer switched off alone, on the real streams and on the replica.

Issue 38 asks that every rule the recognizer keeps show its worth on the real streams as well
as on the replica. This script measures it for the recognizer as it is: the recognizer is built
once as shipped and once per rule with that rule switched off (by its setting, or by giving its
learned value as empty), and each is run on

* SFINGE3D's 36 development sequences, the four swipes, the dictionary as models (as
  ``framefree evaluate-stream --gestures`` runs them), reported for sequences 1-18 and 19-36;
* the Machete sessions, right controller only, each person against models of the five others
  (``benchmarks/one_controller_streams.py``), reported for the development people (Sub_U001,
  Sub_U002, Sub_U004) and the others (Sub_U005, Sub_U007, Sub_U008);
* the replica's development people, one session each (``benchmarks/online_people.py --people
  dev``).

Nothing is chosen here: the table says what each rule does on each set today. Counts are
deterministic. With v29 the six Machete folds alone took 13-18 minutes per rule on one core
of a shared machine (``--jobs 2`` runs two rules at a time; all of them take hours). Cite Caputo
et al., *SFINGE 3D*, Computers & Graphics 91, 2020, and Machete's README with any figure from
their data.

Usage::

    python benchmarks/rule_ablation.py [--rules none,travel,...] [--jobs 2]
        [--out benchmarks/results/rule_ablation.json]
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from joblib import Parallel, delayed
from one_controller_streams import person_fold
from online_people import _evaluate
from threshold_ceiling import gesture_models, labelled_streams, live_counts

from framefree.datasets.people_layout import load_people
from framefree.online import Recognizer
from framefree.online.evaluation import combine
from framefree.replica import DEV_PEOPLE
from framefree.replica.people_streams import make_person_streams

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data"
SWIPES = ("swipe_left", "swipe_right", "swipe_v", "swipe_o")
MACHETE_DEV = ("Sub_U001", "Sub_U002", "Sub_U004")
MACHETE_OTHERS = ("Sub_U005", "Sub_U007", "Sub_U008")

#: Each rule: what it does, and the settings that switch it off.
RULES: dict[str, tuple[str, dict[str, Any]]] = {
    "none": ("the recognizer as shipped", {}),
    "rest_before": ("a candidate starts after a rest (or a brief dip), not at any unit boundary",
                    {"rest_before": 0.0}),
    "confirm": ("a pending gesture fires when the hand rests, not as soon as it is accepted",
                {"fire_on_motion": True}),
    "brief_starts": ("candidates also after a brief dip below the rest level (with the tail rule)",
                     {"brief_starts": False}),
    "settle": ("a stroke that stays below half its peak for 0.3 s has ended (v28)",
               {"settle": float("inf")}),
    "valley_starts": ("candidates also start at a speed minimum between two strokes, without "
                      "a rest (v29)", {"valley_starts": False}),
    "returns": ("the way back after a gesture is not that gesture again", {"returns": False}),
    "one_go": ("a gesture drawn in one go does not rest at a corner", {"gesture_pauses": False}),
    "closure": ("closure and opening limits", {"closure": False}),
    "size": ("size limits (and the travel limit, which uses them)", {"size": False}),
    "travel": ("the travel limit alone", {"travel_limits": {}}),
    "corners": ("no more corners than the takes agree on", {"corners": False}),
    "proportions": ("a one-corner gesture keeps the ratio of its two strokes (v25)",
                    {"proportion_limits": {}}),
    "turns_back": ("a gesture whose takes always turn back refuses corners turning the same way "
                   "(v25)", {"forbidden_turns": {}}),
    "directions": ("a candidate moving outside a gesture's cone of directions in the hand counts "
                   "1.5 times farther (v26, v27)", {"direction_limits": {}}),
    "axes": ("a candidate turning the hand about an axis outside a gesture's cone of axes counts "
             "1.5 times farther (v29)", {"rotation_limits": {}}),
    "unseen": ("a gesture the tracker does not follow never fires", {"unseen": []}),
    "drawn": ("shapes drawn in the air among the calibration's negatives",
              {"drawn_negatives": False}),
    "rivals": ("the other gestures' takes bound the negatives", {"rival_negatives": False}),
    "gated": ("negatives gated by the gesture's limits", {"gated_negatives": False}),
    "unseparated": ("no lean where there is no gap (else the lean of separated gestures)",
                    {"unseparated_position": 0.7}),
}


def _counts(results: Sequence[Any]) -> dict[str, Any]:
    s = combine(results).summary()
    return {k: s[k] for k in ("tp", "fp", "fn", "f1", "fp_per_minute")}


def sfinge(settings: dict[str, Any]) -> dict[str, Any]:
    """SFINGE3D sequences 1-18 and 19-36 with ``settings``."""
    takes, labels = gesture_models(DATA / "sfinge_dev" / "templates", SWIPES)
    rec = Recognizer.from_trajectories(takes, labels, **settings)
    streams = labelled_streams(DATA / "sfinge_dev" / "streams", SWIPES)
    out = {}
    for name, half in (("sfinge_1_18", range(1, 19)), ("sfinge_19_36", range(19, 37))):
        counts = live_counts(rec, [(tr, seg) for path, tr, seg in streams
                                   if int(path.stem[4:]) in half])
        out[name] = {k: v for k, v in counts.items() if k != "per_gesture"}
    return out


def machete(settings: dict[str, Any]) -> dict[str, Any]:
    """The Machete right controller, each person against the five others, with ``settings``."""
    recordings = load_people(DATA / "machete_vive")
    streams = DATA / "machete_streams"
    folds = {p: person_fold(p, recordings, streams, 0, 0.0, settings=settings)[0]
             for p in (*MACHETE_DEV, *MACHETE_OTHERS)}
    return {"machete_dev": _counts([folds[p] for p in MACHETE_DEV]),
            "machete_others": _counts([folds[p] for p in MACHETE_OTHERS])}


def replica(settings: dict[str, Any]) -> dict[str, Any]:
    """The replica's development people, one session each, with ``settings``."""
    items = make_person_streams(DEV_PEOPLE, n_streams_per_person=1)
    return {"replica_dev": _counts([_evaluate("segments", settings, it)["result"]
                                    for it in items])}


def ablate(rule: str) -> dict[str, Any]:
    """Every set with ``rule`` switched off."""
    settings = RULES[rule][1]
    return {**sfinge(settings), **machete(settings), **replica(settings)}


def _row(rule: str, result: dict[str, Any]) -> str:
    cells = [f"{r['tp']}/{r['fp']}/{r['fn']}" for r in result.values()]
    return f"{rule:<13}" + "".join(f"{c:>15}" for c in cells)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rules", default=",".join(RULES), help="rules to switch off, by name")
    ap.add_argument("--jobs", type=int, default=1, help="rules measured at the same time")
    ap.add_argument("--out", type=Path, default=REPO / "benchmarks" / "results" / "rule_ablation.json")
    args = ap.parse_args(argv)
    rules = [r.strip() for r in args.rules.split(",") if r.strip()]
    if args.jobs < 1:
        print(f"error: --jobs must be at least 1, got {args.jobs}", file=sys.stderr)
        raise SystemExit(2)
    unknown = [r for r in rules if r not in RULES]
    if unknown or not rules:
        print(f"error: --rules: unknown rule {', '.join(unknown) or '(none given)'}; "
              f"known: {', '.join(RULES)}", file=sys.stderr)
        raise SystemExit(2)
    for folder in ("sfinge_dev", "machete_vive", "machete_streams"):
        if not (DATA / folder).is_dir():
            print(f"error: {DATA / folder}: no such folder", file=sys.stderr)
            raise SystemExit(2)
    results = Parallel(n_jobs=args.jobs)(delayed(ablate)(r) for r in rules)
    out = {r: {"rule": RULES[r][0], "settings": RULES[r][1], **res}
           for r, res in zip(rules, results, strict=True)}
    sets = list(results[0])
    print("TP/FP/FN, one rule switched off at a time")
    print(f"{'switched off':<13}" + "".join(f"{s:>15}" for s in sets))
    for r, res in zip(rules, results, strict=True):
        print(_row(r, res))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
