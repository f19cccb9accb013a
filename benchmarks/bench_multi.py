"""Speed of live recognition with two trackers: 120 Hz, a vocabulary of 11 gestures × 30 takes.

The models are the 330 recordings of the six Machete Vive people (11 whole-body gestures, five
takes each, a controller in each hand: 11 × 30). The stream is one person's session of all 55
takes at 120 Hz (``continuous_session``: the takes resampled, moves and rests between them; the
person is among the models, which changes what is recognized but not what it costs). Every pose
is pushed as fast as the machine goes and timed:

* inline: ``push`` classifies on the pose path; its slowest call is the slowest classification
  (every candidate of a movement unit against every model), and each unit's classification is
  timed on its own as well;
* background (``framefree live``'s default): ``push`` hands classification to the worker.

Prints a table and writes ``--out`` (JSON)::

    python benchmarks/bench_multi.py --out benchmarks/results/multi_speed.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from framefree.datasets.multi_sessions import continuous_session
from framefree.datasets.people_layout import load_people
from framefree.online.multi import MultiRecognizer

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data" / "machete_vive"


def timed_run(rec: MultiRecognizer, t: np.ndarray, P: np.ndarray, Q: np.ndarray,
              background: bool) -> tuple[np.ndarray, list[float], int]:
    """Per-pose ``push`` times [s] (N,), each unit's classification time [s], events."""
    rec.background = background
    rec.reset()
    units: list[float] = []
    original = rec.spotter.candidates

    def candidates(buffer):
        t0 = time.perf_counter()
        out = original(buffer)
        units.append(time.perf_counter() - t0)
        return out

    rec.spotter.candidates = candidates
    times = np.empty(t.size)
    events = 0
    try:
        for k in range(t.size):
            t0 = time.perf_counter()
            events += len(rec.push(t[k], P[k], Q[k]))
            times[k] = time.perf_counter() - t0
        events += len(rec.finish())
    finally:
        del rec.spotter.candidates
        rec.close()
    return times, units, events


def summary(times: np.ndarray) -> dict[str, float]:
    ms = 1e3 * times
    return {"mean_ms": float(ms.mean()), "p99_ms": float(np.percentile(ms, 99)),
            "max_ms": float(ms.max())}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=DATA)
    ap.add_argument("--person", default="Sub_U001", help="whose takes make the session")
    ap.add_argument("--rate", type=float, default=120.0, help="poses per second [Hz]")
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args()
    if not args.data.is_dir():
        print(f"--data {args.data}: not a folder of people <person>/<gesture>/<recording>",
              file=sys.stderr)
        raise SystemExit(2)
    people = load_people(args.data)
    samples = [r.sample for r in people]
    labels = [r.gesture for r in people]
    counts = {g: labels.count(g) for g in dict.fromkeys(labels)}
    t0 = time.perf_counter()
    rec = MultiRecognizer.from_samples(samples, labels)
    build = time.perf_counter() - t0
    rec.warmup()
    takes = people.of([args.person])
    order = np.random.default_rng(0).permutation(len(takes))
    session, _ = continuous_session([takes[k].sample for k in order],
                                    [takes[k].gesture for k in order], rate=args.rate)
    t = session.t
    P = np.stack([tr.p for tr in session.trackers], axis=1)
    Q = np.stack([tr.q for tr in session.trackers], axis=1)
    out = {"models": len(samples), "gestures": counts, "trackers": rec.n_trackers,
           "rate_hz": args.rate, "poses": int(t.size), "session_s": float(t[-1] - t[0]),
           "build_s": build, "machine": platform.processor() or platform.machine(),
           "cpus": os.cpu_count(), "load_average": os.getloadavg()}
    for mode in ("inline", "background"):
        times, units, events = timed_run(rec, t, P, Q, mode == "background")
        row = {**summary(times), "events": events}
        if mode == "inline":
            u = 1e3 * np.asarray(units)
            row.update(units=int(u.size), unit_mean_ms=float(u.mean()),
                       slowest_classification_ms=float(u.max()))
        out[mode] = row
    period = 1e3 / args.rate
    print(f"{len(samples)} models ({len(counts)} gestures × {len(samples) // len(counts)}), "
          f"{rec.n_trackers} trackers, {t.size} poses at {args.rate:g} Hz (period {period:.2f} ms); "
          f"built in {build:.1f} s")
    for mode in ("inline", "background"):
        r = out[mode]
        print(f"{mode:>10}: per pose mean {r['mean_ms']:.3f} ms, p99 {r['p99_ms']:.3f} ms, "
              f"slowest {r['max_ms']:.1f} ms; {r['events']} events")
    r = out["inline"]
    print(f"classification per movement unit ({r['units']}): mean {r['unit_mean_ms']:.1f} ms, "
          f"slowest {r['slowest_classification_ms']:.1f} ms")
    print(f"load average {out['load_average'][0]:.2f} (at the end)")
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(out, indent=1))
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
