"""Re-measure the live recognizer's headline figures and compare them with the ones on record.

The README and docs/online.md report the live recognizer on four sets of streams. A change made
for one of them can move another, and a figure nobody re-measures stays in the docs: the
two-controller Machete sessions went from 98.5 to 95.7 % with v19 and the docs said 98.5 % until
after v23 (docs/multi-trackers.md). This script runs each row as a reader would, with the
command the docs give, and compares its counts (true positives, false positives, misses) with
``benchmarks/results/live_figures.json``. Everything is deterministic, so any difference is a
change of behaviour, not noise.

Rows:

``sfinge``
    SFINGE3D's 36 development sequences, the four swipes, the dictionary as models
    (``framefree evaluate-stream``; needs ``../shared/data/sfinge_dev``).
``sfinge_no_hand_frame``
    The same with ``--no-hand-frame`` (nothing depends on how the tracker sits in the hand: the
    defaults before v27).
``machete_one``
    The Machete sessions, right controller only, each of the six people against models of the
    five others (``benchmarks/one_controller_streams.py --people all``).
``machete_right_hand``
    The same, evaluating only the eight gestures the right hand performs; the others stay in the
    sessions as non-gesture motion (``... --people all --gestures right-hand``).
``machete_left_hand``
    The left controller and the eight gestures the left hand performs, a vocabulary no rule was
    chosen on (``... --people all --tracker 1 --gestures left-hand``).
``machete_two``
    The same sessions with both controllers (``benchmarks/multi_people_streams.py``).
``replica``
    The replica's 20 held-out people, one session each (``benchmarks/online_people.py --people
    heldout --per-person 1``).
``zigzag``, ``check_mark``
    A new gesture taught from five takes, among the seven, on 10 held-out people with
    pentagons, letter Ms and Cs (``benchmarks/eighth_gesture.py --gesture G --people 10
    --distractors fresh``): the new gesture's counts.

A row whose data is missing is skipped with one line. About forty minutes for all eight on a
2-core machine.

    python benchmarks/live_figures.py                  # measure, compare with the record
    python benchmarks/live_figures.py --only sfinge    # some rows
    python benchmarks/live_figures.py --write          # measure and record (after a change the docs report)

Exit status: 0 when every row measured matches the record, 1 when one has moved (or has no
record), 2 on a usage error or when a benchmark fails.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data"
RECORD = REPO / "benchmarks" / "results" / "live_figures.json"
SWIPES = "swipe_left,swipe_right,swipe_v,swipe_o"
#: what the record keeps of a row (``per_stream``: TP, FP, FN of each stream, where measured)
KEYS = ("tp", "fp", "fn", "precision", "recall", "f1", "fp_per_minute", "per_stream")


def _run(args: Sequence[str]) -> None:
    proc = subprocess.run([sys.executable, *args], capture_output=True, text=True, cwd=REPO)
    if proc.returncode != 0:
        tail = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise RuntimeError(f"{' '.join(args[:2])} failed: {tail}")


def _sfinge(*extra: str) -> Callable[[Path], dict[str, Any]]:
    def measure(out: Path) -> dict[str, Any]:
        streams = sorted(str(p) for p in (DATA / "sfinge_dev" / "streams").glob("seq_??.csv"))
        _run(["-c", "from framefree.cli import main; main()", "evaluate-stream",
              "--models", str(DATA / "sfinge_dev" / "templates"), "--gestures", SWIPES, *streams,
              *extra, "--json", str(out)])
        result = json.loads(out.read_text())
        per_stream = {Path(name).stem: [row["tp"], row["fp"], row["fn"]]
                      for name, row in result["streams"].items()}
        return {**result["total"], "per_stream": per_stream}
    return measure


def _machete_one(*extra: str) -> Callable[[Path], dict[str, Any]]:
    def measure(out: Path) -> dict[str, Any]:
        _run(["benchmarks/one_controller_streams.py", "--people", "all", *extra, "--out", str(out)])
        return json.loads(out.read_text())["all"]
    return measure


def _machete_two(out: Path) -> dict[str, Any]:
    _run(["benchmarks/multi_people_streams.py", "--out", str(out)])
    return json.loads(out.read_text())["held_out"]


def _replica(out: Path) -> dict[str, Any]:
    _run(["benchmarks/online_people.py", "--people", "heldout", "--per-person", "1",
          "--json", str(out)])
    return json.loads(out.read_text())["segments"]["pooled"]


def _new_gesture(gesture: str) -> Callable[[Path], dict[str, Any]]:
    def measure(out: Path) -> dict[str, Any]:
        _run(["benchmarks/eighth_gesture.py", "--gesture", gesture, "--people", "10",
              "--distractors", "fresh", "--no-baseline", "--json", str(out),
              "--work", str(out.parent / f"{gesture}_work")])
        return json.loads(out.read_text())["with_new_gesture"]["per_gesture"][gesture]
    return measure


#: row name: (what it measures, the data it needs, how to measure it)
ROWS: dict[str, tuple[str, Path | None, Callable[[Path], dict[str, Any]]]] = {
    "sfinge": ("SFINGE3D dev, 36 sequences, four swipes", DATA / "sfinge_dev", _sfinge()),
    "sfinge_no_hand_frame": ("the same with --no-hand-frame", DATA / "sfinge_dev",
                             _sfinge("--no-hand-frame")),
    "machete_one": ("Machete sessions, right controller, six people held out in turn",
                    DATA / "machete_streams", _machete_one()),
    "machete_right_hand": ("Machete sessions, right controller, the right hand's eight gestures",
                           DATA / "machete_streams", _machete_one("--gestures", "right-hand")),
    "machete_left_hand": ("Machete sessions, left controller, the left hand's eight gestures",
                          DATA / "machete_streams",
                          _machete_one("--tracker", "1", "--gestures", "left-hand")),
    "machete_two": ("Machete sessions, both controllers, six people held out in turn",
                    DATA / "machete_streams", _machete_two),
    "replica": ("replica, 20 held-out people, one session each", None, _replica),
    "zigzag": ("a zigzag taught from five takes, 10 held-out people", None, _new_gesture("zigzag")),
    "check_mark": ("a check mark taught from five takes, 10 held-out people", None,
                   _new_gesture("check_mark")),
}


def counts(row: dict[str, Any]) -> tuple[int, int, int]:
    """(true positives, false positives, misses) of a measured or recorded row."""
    return int(row["tp"]), int(row["fp"]), int(row["fn"])


def compare(measured: dict[str, dict[str, Any]], record: dict[str, dict[str, Any]]
            ) -> dict[str, str]:
    """Each measured row's verdict against the record: ``same`` (the totals, and each stream's
    counts where both have them), ``moved`` or ``no record``."""
    out = {}
    for name, row in measured.items():
        if name not in record:
            out[name] = "no record"
        else:
            streams = (row.get("per_stream"), record[name].get("per_stream"))
            same = (counts(row) == counts(record[name])
                    and (None in streams or streams[0] == streams[1]))
            out[name] = "same" if same else "moved"
    return out


def _line(row: dict[str, Any] | None) -> str:
    if row is None:
        return "-"
    tp, fp, fn = counts(row)
    rate = f", {row['fp_per_minute']:.2f} FP/min" if "fp_per_minute" in row else ""
    return f"{tp} / {fp} / {fn}, F1 {100 * row['f1']:.1f} %{rate}"


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", default=",".join(ROWS),
                    help=f"comma-separated rows among {', '.join(ROWS)}")
    ap.add_argument("--record", type=Path, default=RECORD, help="the figures on record (JSON)")
    ap.add_argument("--write", action="store_true", help="record the measured rows")
    args = ap.parse_args(argv)
    names = [n.strip() for n in args.only.split(",") if n.strip()]
    unknown = [n for n in names if n not in ROWS]
    if unknown:
        print(f"--only: unknown row {unknown[0]!r} (rows: {', '.join(ROWS)})", file=sys.stderr)
        return 2
    record = json.loads(args.record.read_text()) if args.record.is_file() else {}
    measured: dict[str, dict[str, Any]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            title, needs, measure = ROWS[name]
            if needs is not None and not needs.is_dir():
                print(f"{name}: skipped, {needs} is missing")
                continue
            print(f"{name}: {title} ...", flush=True)
            try:
                row = measure(Path(tmp) / f"{name}.json")
            except RuntimeError as err:
                print(f"{name}: {err}", file=sys.stderr)
                return 2
            measured[name] = {k: row[k] for k in KEYS if k in row}
    verdicts = compare(measured, record)
    for name, row in measured.items():
        print(f"{name:<{max(map(len, ROWS))}} now {_line(row):<44} record {_line(record.get(name))}"
              f"  {verdicts[name]}")
    if args.write:
        args.record.parent.mkdir(parents=True, exist_ok=True)
        args.record.write_text(json.dumps({**record, **measured}, indent=2) + "\n")
        print(f"wrote {args.record}")
        return 0
    return 0 if all(v == "same" for v in verdicts.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
