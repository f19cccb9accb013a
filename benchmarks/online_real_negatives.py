"""Live recognition on real motion that is no gesture: every event is a false positive.

Streams every recording of ``real_motions`` (pouring, scooping and free motions of hand-held
objects, two tracker mountings, and their frame-changed copies) through the recognizer built
from the replica's ``original_1`` models, and counts the events it fires. The folder's synthetic
motions (``syn_*``: a helix, and a pure rotation, a straight line and a circle, which the data's
README keeps for "nothing crashes" tests) are streamed too but counted apart: they are no real
motion, and a circle drawn in the air is the shape of *go right*.

    .venv/bin/python benchmarks/online_real_negatives.py
    .venv/bin/python benchmarks/online_real_negatives.py --set move_factor=2 --set size_reach=1
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from online_people import _parse_set

from framefree.core.trajectory import Trajectory
from framefree.datasets.layout import load_model_recordings
from framefree.online import Recognizer
from framefree.online.evaluation import run_stream
from framefree.replica import replica_path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from real_data import REAL_MOTIONS  # noqa: E402  (the full set next to the checkout, else the shipped one)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=REAL_MOTIONS, help="folder of 8-column CSV recordings")
    ap.add_argument("--set", action="append", default=[], help="recognizer setting KEY=VALUE")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    files = sorted(args.data.rglob("*.csv"))
    rec = Recognizer.from_trajectories(*load_model_recordings(replica_path(0), "original_1"),
                                       **_parse_set(args.set))
    rec.warmup()
    minutes, fired = 0.0, {}
    for path in files:
        traj = Trajectory.from_csv(path)
        rec.reset()
        events, _ = run_stream(rec, traj)
        if not path.name.startswith("syn_"):
            minutes += traj.duration / 60.0
        fired[str(path.relative_to(args.data))] = [e.label for e in events]
    real = {k: v for k, v in fired.items() if not Path(k).name.startswith("syn_")}
    synthetic = {k: v for k, v in fired.items() if k not in real}
    n = sum(len(v) for v in real.values())
    print(f"{len(real)} real recordings, {minutes:.1f} min of non-gesture motion: {n} events "
          f"({n / max(minutes, 1e-9):.2f} per minute)")
    for name, labels in fired.items():
        if labels:
            print(f"   {name}{' (synthetic)' if name in synthetic else ''}: {labels}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"settings": _parse_set(args.set), "recordings": len(real),
                                         "minutes": minutes, "events": n, "fired": real,
                                         "synthetic_fired": synthetic}, indent=1))


if __name__ == "__main__":
    main()
