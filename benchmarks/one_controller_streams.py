"""One controller of the real Machete sessions, with models of the other people: the single-tracker
recognizer on real continuous motion.

For each person of ``--people``, the models are one controller's recordings (``--tracker``: 0 the
right, 1 the left) of the other people of ``../shared/data/machete_vive``, and the streams are the
same controller in that person's sessions of ``../shared/data/machete_streams``. A gesture the
other hand performs is labelled in the sessions as well, so a controller cannot find all of them
(docs/online-history.md, v19: the right controller's misses by gesture).

``--trim F`` cuts every model recording to where its hand first and last moves faster than ``F``
times its peak speed: models cut as a benchmark's segmented examples are, without the rests
before and after the gesture that ``framefree record`` keeps (docs/online-history.md, *Models
cut without rests*).

    python benchmarks/one_controller_streams.py --out benchmarks/results/one_controller_streams.json
    python benchmarks/one_controller_streams.py --trim 0.05

``--gestures right-hand`` evaluates only the eight gestures the right hand performs (alone or
with the left); the others' performances stay in the sessions as non-gesture motion, as
``evaluate-stream --gestures`` counts them. It is the nearest these recordings come to a set whose
one sensor performs every gesture it is taught (docs/online.md, *On real continuous motion*).
A comma-separated list of gestures works the same way.

    python benchmarks/one_controller_streams.py --people all --gestures right-hand

``--tracker 1 --gestures left-hand`` does the same for the left controller and the eight gestures
the left hand performs: a vocabulary on which no rule of the recognizer was chosen.

    python benchmarks/one_controller_streams.py --people all --tracker 1 --gestures left-hand

``--no-orientation`` replaces every quaternion, of the models and of the streams, by the identity:
a sensor that tracks positions only, as skeleton trackers do (docs/online-history.md, *A sensor
without orientation*). ``--set NAME=JSON`` passes a recognizer setting by name (e.g.
``--set seen_fraction=0`` for the recognizer before v20). ``--explain`` prints why each gesture
was missed and what each false positive was (``framefree evaluate-stream --explain``'s diagnosis),
counted by gesture over the people.

``--rate HZ`` and ``--noise M`` give the models and the sessions as another sensor would: resampled
at HZ and with white noise of M metres per axis on every position. With ``--no-orientation``,
``--rate 30 --noise 0.01`` stands for a skeleton tracker's wrist joint (docs/online-history.md,
*A sensor without orientation*, v32). ``--turn-noise DEG`` turns every orientation by white noise
of DEG degrees per axis: a sensor whose orientation jitters (v32).

``--turned AXIS:DEG`` (e.g. ``x:90``) turns the controller in the hand in every stream, by DEG
degrees about its own AXIS, and leaves the models as recorded: a tracker held another way than
when the takes were recorded. Frame-free recognition does not see it; the cones of hand
directions (``hand_frame``) weigh the turned performances as moving another way
(docs/online-history.md, v27). With ``--no-orientation`` it stands for a sensor of positions only
moved since the takes, whose cones then refuse what moves outside them (v33).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np
from online_people import _parse_set
from tqdm import tqdm

from framefree.core import se3
from framefree.core.se3 import quaternion_multiply
from framefree.core.trajectory import Trajectory
from framefree.datasets.people_layout import load_people
from framefree.datasets.stream_files import load_stream
from framefree.online import Recognizer
from framefree.online.diagnosis import explain_stream
from framefree.online.evaluation import StreamResult, combine
from framefree.online.noisy_orientation import constant_orientation

REPO = Path(__file__).resolve().parent.parent
DATA = REPO.parent / "shared" / "data"


def trimmed(traj: Trajectory, fraction: float) -> Trajectory:
    """``traj`` from where its position speed first exceeds ``fraction`` × its peak to where it
    last does (``fraction`` 0: unchanged)."""
    if fraction <= 0:
        return traj
    speed = np.linalg.norm(np.gradient(traj.p, traj.t, axis=0), axis=1)
    fast = np.flatnonzero(speed > fraction * speed.max())
    a, b = int(fast[0]), int(fast[-1]) + 1
    return Trajectory(traj.t[a:b], traj.p[a:b], traj.q[a:b], source=traj.source)


def without_orientation(traj: Trajectory) -> Trajectory:
    """``traj`` with every quaternion replaced by the identity (positions only), as the
    recognizer takes an orientation too noisy to use (:func:`constant_orientation`)."""
    return constant_orientation(traj)


def as_sensor(traj: Trajectory, rate: float | None, noise: float,
              turn_noise: float = 0.0) -> Trajectory:
    """``traj`` as another sensor would give it: resampled at ``rate`` [Hz] (``None``: as
    recorded), with white noise of ``noise`` [m] per axis on the positions and of
    ``turn_noise`` [deg] per axis on the orientations (each pose turned in its own frame by a
    random rotation vector), seeded by the recording, so every run is the same."""
    if rate is not None:
        traj = traj.resampled(1.0 / rate)
    rng = np.random.default_rng([len(traj), round(1e3 * float(traj.t[0])) % 2**32])
    if noise > 0.0:
        traj = Trajectory(traj.t, traj.p + noise * rng.standard_normal(traj.p.shape), traj.q,
                          source=traj.source)
    if turn_noise > 0.0:
        T = traj.poses()
        jitter = np.radians(turn_noise) * rng.standard_normal((len(traj), 3))
        T[:, :3, :3] = T[:, :3, :3] @ se3.rotation_from_vector(jitter)
        traj = Trajectory.from_poses(traj.t, T, source=traj.source)
    return traj


def turned_in_hand(traj: Trajectory, turn: np.ndarray | None) -> Trajectory:
    """``traj`` with the tracker turned by the unit quaternion ``turn`` (4,) (w, x, y, z) in the
    hand: each pose ``T`` becomes ``T G``, ``G`` the turn about the tracker's own origin
    (``None``: unchanged)."""
    if turn is None:
        return traj
    q = quaternion_multiply(traj.q, np.broadcast_to(turn, traj.q.shape))
    return Trajectory(traj.t, traj.p, q, source=traj.source)


def turn_quaternion(text: str) -> np.ndarray:
    """The unit quaternion of ``AXIS:DEG`` (``x:90``: 90° about the x axis)."""
    axis, _, degrees = text.partition(":")
    if axis not in ("x", "y", "z"):
        raise ValueError(f"{text!r}: expected AXIS:DEG with AXIS x, y or z")
    half = np.radians(float(degrees)) / 2.0
    q = np.zeros(4)
    q[0], q["xyz".index(axis) + 1] = np.cos(half), np.sin(half)
    return q


def person_fold(person: str, recordings: list, streams: Path, tracker: int, trim: float,
                positions_only: bool = False, settings: dict | None = None,
                gestures: set[str] | None = None, turn: np.ndarray | None = None,
                rate: float | None = None, noise: float = 0.0, turn_noise: float = 0.0
                ) -> tuple[StreamResult, float, list[str], dict[str, list]]:
    """Counts for one held-out person (models from everyone else, that person's sessions), the
    rest level [m/s] learned from those models, the gestures the tracker does not follow, and
    why each gesture was missed and what each false positive was
    (:func:`~framefree.online.diagnosis.explain_stream`, over all the sessions).

    ``gestures``: the vocabulary (``None``: all); the other gestures' models are left out and
    their performances in the sessions count as non-gesture motion, as ``evaluate-stream
    --gestures`` counts them. ``turn``: the streams' tracker turned in the hand
    (:func:`turned_in_hand`), the models as recorded. ``rate``, ``noise``: models and streams
    as another sensor gives them (:func:`as_sensor`), ``turn_noise`` as well."""
    others = [r for r in recordings
              if r.person != person and (gestures is None or r.gesture in gestures)]
    def sensor(traj: Trajectory) -> Trajectory:
        return as_sensor(without_orientation(traj) if positions_only else traj, rate, noise,
                         turn_noise)

    rec = Recognizer.from_trajectories([sensor(trimmed(r.sample.trackers[tracker], trim))
                                        for r in others],
                                       [r.gesture for r in others], **(settings or {}))
    rec.warmup()
    rec.background = False
    results, why = [], {"missed": [], "false_positives": []}
    for path in sorted(streams.glob(f"{person}_s*.csv")):
        if path.name.endswith("_labels.csv"):
            continue
        multi, segments = load_stream(path)
        if gestures is not None:
            segments = [s for s in segments if s.label in gestures]
        traj = turned_in_hand(sensor(multi.trackers[tracker]), turn)
        rec.reset()
        res, explained = explain_stream(rec, traj, segments)
        results.append(res)
        for key in why:
            why[key] += explained[key]
    return combine(results), rec.learned_.rest_speed, list(rec.learned_.unseen or []), why


#: The Machete gestures the right hand performs, alone or with the left: the vocabulary of a
#: sensor that performs every gesture it is taught, as a single-sensor set is recorded. In their
#: takes the right controller's path is 0.97-1.00 times the left's (the median take; *hook right*,
#: *uppercut right* about 6.4, the *right-left-right combo* 1.67); in the others' at most 0.63
#: (the *left-right-left combo*, whose one right hook is, to the right hand, a *hook right*).
RIGHT_HAND = ("backflip", "cartwheel_left", "cartwheel_right", "fly_eagle", "golf_swing",
              "hook_right", "right_left_right_combo", "uppercut_right")
#: The same for the left hand (``--tracker 1``): in the takes of its three own gestures the left
#: controller's path is 6.4-6.6 times the right's (*hook left*, *uppercut left*) and 1.6 times (the
#: *left-right-left combo*); in those of the five both hands perform, 1.00-1.03 times.
LEFT_HAND = ("backflip", "cartwheel_left", "cartwheel_right", "fly_eagle", "golf_swing",
             "hook_left", "left_right_left_combo", "uppercut_left")
HANDS = {"right-hand": RIGHT_HAND, "left-hand": LEFT_HAND}


def vocabulary(text: str | None, known: set[str]) -> set[str] | None:
    """The gestures ``--gestures`` names (``None``: all; ``right-hand``: :data:`RIGHT_HAND`,
    ``left-hand``: :data:`LEFT_HAND`); a name the recordings do not hold raises ``ValueError``."""
    if text is None:
        return None
    names = (set(HANDS[text]) if text in HANDS
             else {g.strip() for g in text.split(",") if g.strip()})
    unknown = sorted(names - known)
    if unknown or not names:
        raise ValueError(f"unknown gesture(s) {', '.join(unknown) or '(none given)'}; "
                         f"the recordings hold {', '.join(sorted(known))}")
    return names


def print_reasons(why: dict[str, list]) -> None:
    """Misses by reason and gesture, and false positives by gesture and what they overlap."""
    missed = Counter((m["label"], m["reason"]) for m in why["missed"])
    print("misses by reason:", dict(Counter(m["reason"] for m in why["missed"]).most_common()))
    for (label, reason), n in sorted(missed.items()):
        print(f"  {label:<24} {reason:<22} {n}")
    fps = Counter((f["label"], ", ".join(f.get("overlaps") or []) or "-")
                  for f in why["false_positives"])
    for (label, during), n in sorted(fps.items()):
        print(f"  false {label:<18} during {during:<24} {n}")


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--models", type=Path, default=DATA / "machete_vive")
    ap.add_argument("--streams", type=Path, default=DATA / "machete_streams")
    ap.add_argument("--people", default="Sub_U001,Sub_U002,Sub_U004",
                    help="comma-separated people held out one at a time ('all': every person)")
    ap.add_argument("--tracker", type=int, default=0, help="0: right controller, 1: left")
    ap.add_argument("--trim", type=float, default=0.0,
                    help="cut each model recording where its speed stays below this share of its peak")
    ap.add_argument("--no-orientation", action="store_true",
                    help="replace every quaternion by the identity (a position-only sensor)")
    ap.add_argument("--rate", type=float, default=None, metavar="HZ",
                    help="resample models and streams at this rate (another sensor's)")
    ap.add_argument("--noise", type=float, default=0.0, metavar="M",
                    help="add white noise of this standard deviation [m] per axis to every "
                         "position, of models and streams")
    ap.add_argument("--turn-noise", type=float, default=0.0, metavar="DEG",
                    help="turn every orientation, of models and streams, by white noise of this "
                         "standard deviation [deg] per axis")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=JSON",
                    help="a recognizer setting by name (repeatable)")
    ap.add_argument("--gestures", default=None, metavar="G1,G2,...",
                    help="evaluate these gestures only; the others' performances count as "
                         "non-gesture motion ('right-hand', 'left-hand': those that hand performs, "
                         "alone or with the other)")
    ap.add_argument("--explain", action="store_true",
                    help="print why each gesture was missed and what each false positive was")
    ap.add_argument("--turned", default=None, metavar="AXIS:DEG",
                    help="turn the tracker in the hand in every stream (e.g. x:90), not in the "
                         "models (with --no-orientation: the sensor moved since the takes)")
    ap.add_argument("--out", type=Path, default=None, help="write the results as JSON here")
    args = ap.parse_args(argv)
    settings = _parse_set(args.sets)
    if args.no_orientation and args.turn_noise > 0:
        print("error: --turn-noise jitters an orientation that --no-orientation removes; give "
              "one of the two", file=sys.stderr)
        raise SystemExit(2)
    try:
        turn = None if args.turned is None else turn_quaternion(args.turned)
    except ValueError as err:
        print(f"error: --turned: {err}", file=sys.stderr)
        raise SystemExit(2) from None

    recordings = load_people(args.models)
    people = (sorted({r.person for r in recordings}) if args.people == "all"
              else args.people.split(","))
    try:
        gestures = vocabulary(args.gestures, {r.gesture for r in recordings})
    except ValueError as err:
        print(f"error: --gestures: {err}", file=sys.stderr)
        raise SystemExit(2) from None
    folds = {p: person_fold(p, recordings, args.streams, args.tracker, args.trim,
                            args.no_orientation, settings, gestures, turn, args.rate, args.noise,
                            args.turn_noise)
             for p in tqdm(people, desc="people")}
    rows = {p: {**res.summary(), "rest_speed": rest, "unseen": unseen}
            for p, (res, rest, unseen, _) in folds.items()}
    rows["all"] = combine([res for res, *_ in folds.values()]).summary()
    why = {key: [x for *_, w in folds.values() for x in w[key]]
           for key in ("missed", "false_positives")}
    for p, f in rows.items():
        level = f"  rest level {f['rest_speed']:.3f} m/s" if "rest_speed" in f else ""
        unseen = f"  not followed: {', '.join(f['unseen'])}" if f.get("unseen") else ""
        print(f"{p}: TP {f['tp']} FP {f['fp']} FN {f['fn']}  F1 {f['f1']:.3f}  "
              f"FP/min {f['fp_per_minute']:.2f}{level}{unseen}")
    if args.explain:
        print_reasons(why)
    out = {"tracker": args.tracker, "trim": args.trim, "positions_only": args.no_orientation,
           "turned": args.turned, "rate": args.rate, "noise": args.noise,
           "turn_noise": args.turn_noise,
           "settings": settings, "gestures": None if gestures is None else sorted(gestures),
           "misses_by_reason": dict(Counter(m["reason"] for m in why["missed"])),
           "false_positives": dict(Counter(f["label"] for f in why["false_positives"])),
           "people": {p: f for p, f in rows.items() if p != "all"}, "all": rows["all"]}
    if args.out:
        args.out.write_text(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
