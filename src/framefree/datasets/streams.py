"""Continuous labelled sessions for the online recognizer.

A session is a few minutes of tracker data in which gestures are performed one after the other,
separated by everything a person does in between: holding still, repositioning the hand, walking
to another spot (the user frame moves in the tracker world), re-gripping the tracker (the tracker
moves in the hand) and distractor motions that are no gesture; plus stop signals (a fast
back-and-forth wrist rotation, peak angular speed above 5 rad/s).

Labels (``<name>_labels.csv``, header ``label,start_t,end_t``) span the gesture's movement, from
the onset of its first stroke to the end of its last stroke (the rest before and after is not
included). The label of a stop signal is ``stop``.
"""

from __future__ import annotations

import csv
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import se3
from ..errors import DatasetError
from ..trajectory import Trajectory
from .gestures import ANTHROPOMETRY, EXTRA_SHAPES, GESTURE_SHAPES, default_world, plan_gesture
from .motion import Motion, Piece, hold, make_pose, minimum_jerk, rot, sclerp_path, stroke
from .recording import (
    measure,
    measurement_noise,
    random_grip,
    sample_times,
    tracker_poses,
    write_recording,
)

__all__ = [
    "STOP",
    "STOP_SIGNAL",
    "LivePerson",
    "Segment",
    "StreamItem",
    "labels_path",
    "load_stream",
    "make_stream",
    "save_stream",
]

#: Label of a stop signal.
STOP = "stop"

#: Stop signal: wrist rotation amplitude [rad] and stroke duration [s] ranges (uniform); three
#: strokes (+A, −2A, +A). Minimum peak speed 1.875 · 50° / 0.3 s ≈ 5.5 rad/s.
STOP_SIGNAL = {"amplitude": (math.radians(50), math.radians(80)), "stroke": (0.2, 0.3)}

#: Interlude activities and their probabilities when no timing is imposed.
ACTIVITIES = {"hold": 0.3, "reposition": 0.25, "distractor": 0.2, "walk": 0.15, "regrip": 0.1}

#: Walking: step frequency [Hz] (about 1.8–2 steps/s at normal speed), vertical bob and lateral sway
#: amplitude [m] of a hand carried in front of the body (centre-of-mass excursion of walking is
#: ≈ 2–3 cm each way), distance [m] and turn [rad] ranges.
WALK = {
    "step_hz": (1.7, 2.1),
    "bob": 0.02,
    "sway": 0.015,
    "distance": (0.5, 2.0),
    "turn": (-math.pi / 2, math.pi / 2),
}

_MIN_APPROACH = 0.6  # shortest move to a gesture's start pose [s]
_MIN_SETTLE = 0.2  # shortest rest before a gesture [s]
_FILL_MARGIN = 3.0  # time kept free before a scripted onset for the approach and the settling [s]


@dataclass(frozen=True)
class Segment:
    """A labelled stretch of a stream.

    Attributes
    ----------
    label : str
        Gesture name or ``"stop"``.
    start_t, end_t : float
        Movement onset and end [s], in the stream's clock.
    """

    label: str
    start_t: float
    end_t: float


@dataclass(frozen=True)
class StreamItem:
    """One scripted entry of :func:`make_stream`.

    Attributes
    ----------
    label : str
        Gesture name or ``"stop"``.
    start_t : float, optional
        Requested movement onset [s]. If the previous item and the approach need longer, the item
        starts as early as possible and a warning is issued.
    gap : float, optional
        Requested time [s] from the end of the previous item to this onset (ignored with
        ``start_t``). Default: a random interlude.
    speed : float
        Speed factor of the performance (e.g. 2 for a hurried gesture).
    """

    label: str
    start_t: float | None = None
    gap: float | None = None
    speed: float = 1.0


class _Session:
    """The three time-aligned motions of a session: hand (user frame), grip, world placement."""

    def __init__(self, hand: np.ndarray, grip: np.ndarray, world: np.ndarray) -> None:
        self.hand = Motion()
        self.grip = Motion()
        self.world = Motion()
        self._h, self._g, self._w = hand, grip, world
        self.time = 0.0

    def add(
        self,
        hand: Piece | None = None,
        grip: Piece | None = None,
        world: Piece | None = None,
        duration: float | None = None,
    ) -> None:
        d = (
            next(p.duration for p in (hand, grip, world) if p is not None)
            if duration is None
            else duration
        )
        for attr, piece in (("hand", hand), ("grip", grip), ("world", world)):
            current = getattr(self, "_" + attr[0])
            piece = piece if piece is not None else hold(current, d)
            getattr(self, attr).append(piece)
            setattr(self, "_" + attr[0], piece.end)
        self.time += d

    @property
    def hand_pose(self) -> np.ndarray:
        return self._h


def _move_duration(A: np.ndarray, B: np.ndarray) -> float:
    """Time [s] for an unhurried move between hand poses (grows with distance and turn)."""
    dist = float(np.linalg.norm(B[:3, 3] - A[:3, 3]))
    ang = float(np.linalg.norm(_rotvec(A[:3, :3].T @ B[:3, :3])))
    return float(np.clip(0.5 + dist / 0.35 + ang / 2.5, _MIN_APPROACH, 2.5))


def _rotvec(R: np.ndarray) -> np.ndarray:
    return se3.vector_from_rotation(R)


def _random_hand_pose(rng: np.random.Generator, around: np.ndarray) -> np.ndarray:
    """A comfortable hand pose near the usual working position."""
    mean_p, _ = ANTHROPOMETRY["hand_position"]
    p = np.asarray(mean_p) + rng.uniform([-0.15, -0.2, -0.25], [0.15, 0.2, 0.15])
    R = rot(rng.standard_normal(3), rng.uniform(0, math.radians(70))) @ around[:3, :3]
    return make_pose(R, p)


def _reposition(
    s: _Session,
    rng: np.random.Generator,
    target: np.ndarray | None = None,
    duration: float | None = None,
) -> None:
    target = _random_hand_pose(rng, s.hand_pose) if target is None else target
    d = _move_duration(s.hand_pose, target) if duration is None else duration
    s.add(hand=stroke(sclerp_path(s.hand_pose, target), d, math.exp(rng.normal(0, 0.1))))


def _distractor(s: _Session, rng: np.random.Generator) -> None:
    """A few via-point movements that are no gesture (scratching, pointing, looking at the tracker)."""
    for _ in range(rng.integers(2, 5)):
        mean_p = np.asarray(ANTHROPOMETRY["hand_position"][0])
        target = s.hand_pose.copy()
        lo, hi = mean_p - np.array([0.2, 0.3, 0.4]), mean_p + np.array([0.2, 0.3, 0.3])
        target[:3, 3] = np.clip(target[:3, 3] + rng.normal(0, 0.12, 3), lo, hi)
        target[:3, :3] = (
            rot(rng.standard_normal(3), rng.uniform(0, math.radians(70))) @ target[:3, :3]
        )
        d = _move_duration(s.hand_pose, target) * rng.uniform(0.8, 1.2)
        s.add(hand=stroke(sclerp_path(s.hand_pose, target), d, math.exp(rng.normal(0, 0.1))))
        if rng.random() < 0.5:
            s.add(duration=rng.uniform(0.05, 0.3))


def _walk(s: _Session, rng: np.random.Generator) -> None:
    """Walk to another spot: the user frame moves and turns in the world, with gait bob and sway."""
    W0 = s._w
    heading = rng.uniform(-math.pi, math.pi)
    dist = rng.uniform(*WALK["distance"])
    direction = np.array([math.cos(heading), math.sin(heading), 0.0])
    step = make_pose(rot([0, 0, 1], rng.uniform(*WALK["turn"])), dist * direction)
    W1 = W0 @ step
    d = 1.0 + dist / 1.0  # ≈ 1 m/s plus starting and stopping
    f = rng.uniform(*WALK["step_hz"])
    base = sclerp_path(W0, W1)

    def world(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=np.float64)
        T = base(minimum_jerk(t / d))
        env = np.sin(np.pi * t / d) ** 2
        bob = np.zeros((t.shape[0], 4, 4))
        bob[:] = np.eye(4)
        bob[:, 2, 3] = WALK["bob"] * env * np.sin(2 * math.pi * f * t)
        bob[:, 1, 3] = WALK["sway"] * env * np.sin(math.pi * f * t)
        return T @ bob

    s.add(world=Piece(d, world))


def _regrip(s: _Session, rng: np.random.Generator) -> None:
    """Re-grip the tracker: it turns and shifts in the hand while the hand stays roughly still."""
    G0 = s._g
    G1 = random_grip(rng)
    turn = float(np.linalg.norm(_rotvec(G0[:3, :3].T @ G1[:3, :3])))
    # a deliberate handling movement: peak tracker rotation speed at most ≈ 3 rad/s
    d = max(rng.uniform(1.0, 2.0), 1.875 * turn / 3.0)
    s.add(grip=stroke(sclerp_path(G0, G1), d))


def _stop(s: _Session, rng: np.random.Generator) -> tuple[float, float]:
    """A fast back-and-forth rotation of the wrist about the forearm axis; returns (start, end)."""
    a = rng.uniform(*STOP_SIGNAL["amplitude"])
    start = s.time
    for k, frac in enumerate((1.0, -2.0, 1.0)):
        H = s.hand_pose
        axis = H[:3, 0]
        target = H.copy()
        target[:3, :3] = rot(axis, frac * a) @ H[:3, :3]
        dur = rng.uniform(*STOP_SIGNAL["stroke"]) * (1.6 if k == 1 else 1.0)
        s.add(hand=stroke(sclerp_path(H, target), dur))
    return start, s.time


def _interlude(s: _Session, rng: np.random.Generator) -> None:
    names = list(ACTIVITIES)
    probs = np.array([ACTIVITIES[n] for n in names])
    for _ in range(rng.integers(1, 4)):
        act = names[rng.choice(len(names), p=probs / probs.sum())]
        if act == "hold":
            s.add(duration=rng.uniform(1.0, 3.0))
        elif act == "reposition":
            _reposition(s, rng)
        elif act == "distractor":
            _distractor(s, rng)
        elif act == "walk":
            _walk(s, rng)
        else:
            _regrip(s, rng)


def _fill(s: _Session, rng: np.random.Generator, until: float) -> None:
    """Random interlude activities as long as they end before time ``until`` [s]."""
    for _ in range(100):
        if until - s.time < 1.0:
            return
        trial = _Session(s.hand_pose, s._g, s._w)
        _interlude(trial, rng)
        if s.time + trial.time > until:
            return
        for h, g, w in zip(trial.hand.pieces, trial.grip.pieces, trial.world.pieces, strict=True):
            s.add(hand=h, grip=g, world=w)


def _approach(s: _Session, target: np.ndarray | None) -> float:
    return 0.0 if target is None else _move_duration(s.hand_pose, target)


def _items(
    sequence: Sequence[str | StreamItem] | None,
    n_gestures: int,
    n_stops: int | None,
    rng: np.random.Generator,
) -> list[StreamItem]:
    if sequence is not None:
        items = [x if isinstance(x, StreamItem) else StreamItem(str(x)) for x in sequence]
        for it in items:
            if it.label != STOP and it.label not in GESTURE_SHAPES and it.label not in EXTRA_SHAPES:
                raise ValueError(
                    f"unknown stream label {it.label!r}; expected a gesture name or {STOP!r}"
                )
        return items
    names = list(GESTURE_SHAPES)
    order: list[str] = []
    while len(order) < n_gestures:
        order += [str(x) for x in rng.permutation(names)]
    order = order[:n_gestures]
    k = int(rng.integers(1, 3)) if n_stops is None else n_stops
    for pos in sorted(
        rng.choice(np.arange(1, len(order) + 1), size=k, replace=k > len(order)), reverse=True
    ):
        order.insert(int(pos), STOP)
    return [StreamItem(x) for x in order]


def make_stream(
    seed: int,
    sequence: Sequence[str | StreamItem] | None = None,
    n_gestures: int = 20,
    n_stops: int | None = None,
    world: np.ndarray | None = None,
) -> tuple[Trajectory, list[Segment]]:
    """Generate a continuous labelled session.

    Parameters
    ----------
    seed : int
        Everything is deterministic given the seed.
    sequence : sequence of str or StreamItem, optional
        Script to perform: gesture names and ``"stop"``, or :class:`StreamItem` entries with
        requested onsets / gaps / speeds. Default: ``n_gestures`` gestures in random order (each
        gesture equally often) with ``n_stops`` stop signals at random positions.
    n_gestures : int
        Number of gestures without a script.
    n_stops : int, optional
        Number of stop signals without a script (default: 1 or 2 at random).
    world : ndarray, shape (4, 4), optional
        Initial user frame in the tracker world (default: random, y-up).

    Returns
    -------
    traj : Trajectory
        The tracker poses, ≈ 50 Hz with jitter, time starting at 0.
    segments : list of Segment
        The performed gestures and stop signals, in time order.
    """
    rng = np.random.default_rng([int(seed), 0x5EA])
    items = _items(sequence, n_gestures, n_stops, rng)
    s = _start_session(seed, world, rng)
    segments = [_perform(s, it, rng) for it in items]
    s.add(duration=rng.uniform(1.0, 2.0))
    t = sample_times(s.time, rng)
    traj = measure(
        t, s.hand.at(t), s.grip.at(t), s.world.at(t), rng, source=f"synthetic stream {seed}"
    )
    return traj, segments


def _start_session(seed: int, world: np.ndarray | None, rng: np.random.Generator) -> _Session:
    """A session resting at the first gesture's usual start pose, in a (random) user frame."""
    W0 = default_world(rng) if world is None else np.asarray(world, dtype=np.float64)
    plan0 = plan_gesture("go_left", np.random.default_rng([int(seed), 1]))
    s = _Session(plan0.start, random_grip(rng), W0)
    s.add(duration=rng.uniform(1.0, 2.0))
    return s


def _perform(s: _Session, it: StreamItem, rng: np.random.Generator) -> Segment:
    """Add one scripted item to the session: what comes before it (free activities or a scripted
    onset), the approach to its start pose, a short rest, and the gesture or stop signal itself."""
    plan = None if it.label == STOP else plan_gesture(it.label, rng, it.speed)
    target = None if plan is None else plan.start
    if it.start_t is not None or it.gap is not None:
        onset = float(it.start_t) if it.start_t is not None else s.time + float(it.gap)
        need = _approach(s, target) + _MIN_SETTLE
        if onset < s.time + need - 1e-9:
            if it.gap != 0.0:
                warnings.warn(
                    f"{it.label} requested at {onset:.2f} s cannot start before "
                    f"{s.time + need:.2f} s; starting as early as possible",
                    stacklevel=3,
                )
            onset = s.time + need
        _fill(s, rng, until=onset - _FILL_MARGIN)
        approach = _approach(s, target)
        settle = onset - s.time - approach
    else:
        _interlude(s, rng)
        approach = _approach(s, target)
        settle = rng.uniform(0.4, 1.0)
    if target is not None:
        _reposition(s, rng, target, approach)
    if settle > 1e-9:
        s.add(duration=settle)
    if plan is None:
        a, b = _stop(s, rng)
    else:
        a = s.time
        for piece in plan.strokes:
            s.add(hand=piece)
        b = s.time
    return Segment(it.label, a, b)


class LivePerson:
    """A simulated person who performs gestures on request while the stream is being consumed.

    The same person model as :func:`make_stream` (interlude activities, walking, re-gripping,
    approach, rest, the gesture, tremor, tracker error, 50 Hz time stamps with jitter), but the
    script is decided as the session goes on, so a closed loop can react to what it observes: for
    instance repeat a gesture the robot did not obey, as the paper's user did. Tremor and tracker
    error are one continuous realization over the whole session.

    Parameters
    ----------
    seed : int
        Everything is deterministic given the seed and the sequence of requests.
    world : ndarray, shape (4, 4), optional
        Initial user frame in the tracker world (default: random, y-up).
    max_duration : float
        Longest session [s] (the noise processes are drawn for this span up front).

    Examples
    --------
    >>> person = LivePerson(0)
    >>> seg = person.perform("go_left", start_t=5.0)
    >>> person.hold(2.0)                      # watch the robot for two seconds
    >>> t, p, q = person.samples_until()      # everything performed so far, not yet emitted
    """

    def __init__(self, seed: int, world: np.ndarray | None = None, max_duration: float = 1200.0):
        rng = np.random.default_rng([int(seed), 0x11FE])
        self._rng = rng
        self._session = _start_session(seed, world, rng)
        self._times = sample_times(float(max_duration), rng)
        self._noise = measurement_noise(self._times, rng)
        self._emitted = 0
        self._last_q: np.ndarray | None = None
        self.segments: list[Segment] = []

    @property
    def time(self) -> float:
        """End of what the person has performed so far [s]."""
        return self._session.time

    def perform(
        self, label: str, start_t: float | None = None, gap: float | None = None, speed: float = 1.0
    ) -> Segment:
        """Perform a gesture (or ``"stop"``).

        Parameters
        ----------
        label : str
            Gesture name or ``"stop"``.
        start_t : float, optional
            Requested onset [s] (free activities fill the time before it; moved later, with a
            warning, if it cannot be met).
        gap : float, optional
            Onset this long after the current end; 0 means as soon as possible (no warning).
            Without ``start_t`` and ``gap``: after one to three random activities.
        speed : float
            Speed factor of the performance.

        Returns
        -------
        Segment
            The labelled span of the gesture (also appended to :attr:`segments`).
        """
        seg = _perform(self._session, StreamItem(label, start_t, gap, speed), self._rng)
        if seg.end_t > self._times[-1]:
            raise DatasetError(f"the session exceeds its max_duration of {self._times[-1]:.0f} s")
        self.segments.append(seg)
        return seg

    def hold(self, duration: float) -> None:
        """Keep the hand still (e.g. while watching the robot) for ``duration`` seconds."""
        self._session.add(duration=float(duration))

    def samples_until(self, t: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The not yet emitted tracker samples up to time ``t`` (default: all performed so far).

        Returns
        -------
        t : ndarray, shape (n,)
            Time stamps [s] (session clock, starting at 0).
        p : ndarray, shape (n, 3)
            Positions [m].
        q : ndarray, shape (n, 4)
            Quaternions (w, x, y, z), sign-continuous across calls.
        """
        end = self.time if t is None else min(float(t), self.time)
        stop = int(np.searchsorted(self._times, end, side="right"))
        window = slice(self._emitted, stop)
        self._emitted = max(stop, self._emitted)
        tt = self._times[window]
        if tt.size == 0:
            return tt, np.empty((0, 3)), np.empty((0, 4))
        s = self._session
        T = tracker_poses(s.hand.at(tt), s.grip.at(tt), s.world.at(tt), self._noise[window])
        p, q = se3.pq_from_poses(T)
        if self._last_q is not None:
            q = q * se3.quaternion_sign(q[0], self._last_q)
        self._last_q = q[-1].copy()
        return tt, p, q


def labels_path(path: str | Path) -> Path:
    """``<dir>/<name>_labels.csv`` beside the stream file ``<dir>/<name>.csv``."""
    path = Path(path)
    return path.with_name(f"{path.stem}_labels.csv")


def save_stream(
    path: str | Path,
    traj: Trajectory,
    segments: Sequence[Segment],
    rng: np.random.Generator | None = None,
) -> Path:
    """Write the stream CSV and its ``<name>_labels.csv``; with ``rng``, quaternions are stored
    with SDK-like sign flips. Returns the stream path."""
    path = write_recording(path, traj, rng)
    with labels_path(path).open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["label", "start_t", "end_t"])
        for seg in segments:
            w.writerow([seg.label, repr(float(seg.start_t)), repr(float(seg.end_t))])
    return path


def load_stream(path: str | Path, quat_order: str = "wxyz") -> tuple[Trajectory, list[Segment]]:
    """Read a stream CSV and its ``<name>_labels.csv``.

    Raises
    ------
    DatasetError
        If the labels file is missing or malformed (naming the file and row).
    """
    path = Path(path)
    traj = Trajectory.from_csv(path, quat_order=quat_order)
    lp = labels_path(path)
    if not lp.is_file():
        raise DatasetError(f"{lp}: labels file missing for stream {path}")
    segments = []
    with lp.open(newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows or [c.strip() for c in rows[0]] != ["label", "start_t", "end_t"]:
        raise DatasetError(f"{lp}, row 1: expected the header 'label,start_t,end_t'")
    for i, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != 3:
            raise DatasetError(f"{lp}, row {i}: expected 3 columns, found {len(row)}")
        try:
            a, b = float(row[1]), float(row[2])
        except ValueError:
            raise DatasetError(f"{lp}, row {i}: start_t and end_t must be numbers") from None
        if not (math.isfinite(a) and math.isfinite(b)) or b < a:
            raise DatasetError(f"{lp}, row {i}: need finite start_t <= end_t, got {a}, {b}")
        segments.append(Segment(row[0].strip(), a, b))
    return traj, segments
