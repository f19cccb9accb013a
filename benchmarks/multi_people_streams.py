"""Two-controller sessions of people the models never saw: ``framefree evaluate-stream`` per person.

For each person of ``--people`` (default: the six of ``../shared/data/machete_vive``), the models
are the other people's recordings (a temporary folder of symbolic links to their folders, so the
queried person's recordings are never among the models) and the streams are that person's
sessions in ``--streams``. The command is exactly what a user runs::

    framefree evaluate-stream --models <the other people> <person>_s1.csv <person>_s2.csv --json ...

Every fold's JSON is kept; the pooled counts, F1, precision, recall, FP/min, per gesture and per
person, are printed and written to ``--out``. ``--all-models`` adds one run with every person as
models (the queried people among them: not held out, said so in the output).

    python benchmarks/multi_people_streams.py --out benchmarks/results/multi_people_streams.json
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data"


def evaluate(models: Path, streams: list[Path], out: Path, extra: list[str]) -> dict:
    """Run ``framefree evaluate-stream`` in a child process; return its JSON."""
    cmd = [sys.executable, "-c", "from framefree.cli import main; main()", "evaluate-stream",
           "--models", str(models), *map(str, streams), "--json", str(out), *extra]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    sys.stderr.write(proc.stderr)
    return json.loads(out.read_text())


def pooled(totals: list[dict]) -> dict:
    """Sum the counts of several runs; F1, precision, recall, FP/min from the sums."""
    tp, fp, fn = (sum(t[k] for t in totals) for k in ("tp", "fp", "fn"))
    minutes = sum(t["nongesture_minutes"] for t in totals)
    p = tp / (tp + fp) if tp + fp else 0.0
    r = tp / (tp + fn) if tp + fn else 0.0
    out = {"tp": tp, "fp": fp, "fn": fn, "precision": p, "recall": r,
           "f1": 2 * p * r / (p + r) if p + r else 0.0,
           "fp_per_minute": fp / minutes if minutes else 0.0, "nongesture_minutes": minutes}
    gestures: dict[str, dict] = {}
    for t in totals:
        for g, row in t["gestures"].items():
            acc = gestures.setdefault(g, {"tp": 0, "fp": 0, "fn": 0})
            for k in ("tp", "fp", "fn"):
                acc[k] += row[k]
    for row in gestures.values():
        d = 2 * row["tp"] + row["fp"] + row["fn"]
        row["f1"] = 2 * row["tp"] / d if d else 0.0
    out["gestures"] = gestures
    return out


def report(name: str, result: dict) -> None:
    print(f"{name}: TP {result['tp']} FP {result['fp']} FN {result['fn']}  "
          f"F1 {result['f1']:.3f}  precision {result['precision']:.3f}  "
          f"recall {result['recall']:.3f}  FP/min {result['fp_per_minute']:.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=DATA / "machete_vive", help="people folder")
    ap.add_argument("--streams", type=Path, default=DATA / "machete_streams",
                    help="folder of <person>_s<k>.csv sessions with their labels")
    ap.add_argument("--people", default=None, help="comma-separated (default: every person)")
    ap.add_argument("--all-models", action="store_true",
                    help="also run with every person as models (not held out)")
    ap.add_argument("--out", type=Path, default=None, help="JSON file of every result")
    ap.add_argument("extra", nargs="*", help="further evaluate-stream options (after --)")
    args = ap.parse_args()
    if not args.data.is_dir():
        print(f"--data {args.data}: not a folder of people <person>/<gesture>/<recording>",
              file=sys.stderr)
        raise SystemExit(2)
    everyone = sorted(p.name for p in args.data.iterdir() if p.is_dir())
    people = args.people.split(",") if args.people else everyone
    folds, totals = {}, []
    with tempfile.TemporaryDirectory() as tmp:
        for person in people:
            models = Path(tmp) / f"without_{person}"
            models.mkdir()
            for other in everyone:
                if other != person:
                    (models / other).symlink_to((args.data / other).resolve())
            streams = sorted(args.streams.glob(f"{person}_s*.csv"))
            streams = [s for s in streams if not s.stem.endswith("_labels")]
            res = evaluate(models, streams, Path(tmp) / f"{person}.json", args.extra)
            folds[person] = res["total"]
            totals.append(res["total"])
            report(person, pooled([res["total"]]))
        held_out = pooled(totals)
        out = {"held_out": held_out, "per_person": folds, "people": people, "options": args.extra}
        report("all people, each held out", held_out)
        for g, row in sorted(held_out["gestures"].items()):
            print(f"  {g:>24}: TP {row['tp']:3d} FP {row['fp']:3d} FN {row['fn']:3d}  F1 {row['f1']:.3f}")
        if args.all_models:
            streams = sorted(s for s in args.streams.glob("*_s*.csv")
                             if not s.stem.endswith("_labels") and s.stem.rsplit("_s", 1)[0] in people)
            res = evaluate(args.data, streams, Path(tmp) / "all.json", args.extra)
            out["all_models_not_held_out"] = pooled([res["total"]])
            report("every person as models (NOT held out)", out["all_models_not_held_out"])
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(out, indent=1, default=float))
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
