"""What a person does between gestures in a continuous session, and the session's clock.

A :class:`Session` holds three time-aligned motions (the hand in the user frame, the tracker in the
hand, the user frame in the tracker world) and a log of :class:`Activity` entries. The activities:

* the replica's repertoire (:data:`ACTIVITIES`, used without a person): holding still,
  repositioning, via-point distractors, walking, re-gripping;
* a person's repertoire (:data:`PERSON_ACTIVITIES`, used with a
  :class:`~framefree.replica.people.Person`) adds reach-and-stay, walk-and-turn and
  scratching-like loops, and times the deliberate moves with the person's tempo and skew;
* stop signals (:func:`stop_signal`), in both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import se3
from .gestures import SKEW_RANGE
from .motion import Motion, Piece, hold, make_pose, minimum_jerk, rot, sclerp_path, stroke
from .people import Person, person_grip
from .population import ANTHROPOMETRY
from .recording import random_grip

__all__ = [
    "ACTIVITIES",
    "PERSON_ACTIVITIES",
    "REACH",
    "SCRATCH",
    "STOP_SIGNAL",
    "WALK",
    "WALK_TURN",
    "Activity",
    "Session",
    "interlude",
    "stop_signal",
]

#: Stop signal: wrist rotation amplitude [rad] and stroke duration [s] ranges (uniform); three
#: strokes (+A, −2A, +A). Minimum peak speed 1.875 · 50° / 0.3 s ≈ 5.5 rad/s.
STOP_SIGNAL = {"amplitude": (math.radians(50), math.radians(80)), "stroke": (0.2, 0.3)}

#: Interlude activities of the replica's person and their probabilities.
ACTIVITIES = {"hold": 0.3, "reposition": 0.25, "distractor": 0.2, "walk": 0.15, "regrip": 0.1}

#: Interlude activities of a simulated person (:mod:`~framefree.replica.people`).
PERSON_ACTIVITIES = {
    "hold": 0.17,
    "reposition": 0.15,
    "reach_stay": 0.13,
    "distractor": 0.11,
    "scratch": 0.13,
    "walk": 0.1,
    "walk_turn": 0.1,
    "regrip": 0.11,
}

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

#: Walking and turning (a person): the body turns 45–180° (either way) while walking 0–1.5 m at
#: the person's speed; turning rate of the body ≈ 120°/s; the hand, held in front, is carried
#: along an arc. A plain walk of a person turns at most ± 45°.
WALK_TURN = {"turn": (math.radians(45.0), math.pi), "distance": (0.0, 1.5), "rate": math.radians(120.0),
             "plain_turn": math.radians(45.0)}

#: Reach and stay: reach forward 10–25 cm beyond the usual hand position, ± 30 cm sideways,
#: −20…+35 cm up, hold 1–3 s; come back right away with probability ½ (else stay).
REACH = {"forward": (0.10, 0.25), "side": 0.30, "up": (-0.20, 0.35), "hold": (1.0, 3.0), "back": 0.5}

#: Scratching-like loops: 2–5 cycles at 2–4 Hz, 1–4 cm across, loops (ellipses) or to-and-fro,
#: with a wrist wobble of 3–12°.
SCRATCH = {"cycles": (2, 5), "hz": (2.0, 4.0), "extent": (0.01, 0.04), "wobble": (math.radians(3.0),
                                                                                  math.radians(12.0))}


@dataclass(frozen=True)
class Activity:
    """One logged stretch of a session.

    Attributes
    ----------
    kind : str
        An interlude activity (a key of :data:`PERSON_ACTIVITIES` or :data:`ACTIVITIES`), or
        ``"idle"`` (start and end of the session), ``"approach"`` (move to a gesture's start pose),
        ``"settle"`` / ``"rest"`` (still before / after a gesture), ``"gesture"``, ``"stop"``.
    start_t, end_t : float
        Span [s] in the session clock.
    label : str
        The gesture's name for ``kind == "gesture"``, else empty.
    """

    kind: str
    start_t: float
    end_t: float
    label: str = ""


class Session:
    """The three time-aligned motions of a session (hand in the user frame, grip, world placement)
    and the log of activities.

    Parameters
    ----------
    hand, grip, world : ndarray, shape (4, 4)
        Initial poses.
    person : Person, optional
        Who performs (``None``: the replica's person and repertoire).
    """

    def __init__(self, hand: np.ndarray, grip: np.ndarray, world: np.ndarray,
                 person: Person | None = None) -> None:
        self.hand = Motion()
        self.grip = Motion()
        self.world = Motion()
        self._h, self._g, self._w = hand, grip, world
        self.time = 0.0
        self.person = person
        self.activities: list[Activity] = []

    def add(
        self,
        hand: Piece | None = None,
        grip: Piece | None = None,
        world: Piece | None = None,
        duration: float | None = None,
    ) -> None:
        """Append one piece to every motion (``None``: hold the current pose)."""
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

    def log(self, kind: str, start_t: float, label: str = "") -> None:
        """Record that ``kind`` went on from ``start_t`` until now."""
        if self.time > start_t:
            self.activities.append(Activity(kind, float(start_t), float(self.time), label))

    def fork(self) -> Session:
        """An empty session starting where this one is now (same person)."""
        return Session(self._h, self._g, self._w, self.person)

    def extend(self, other: Session) -> None:
        """Append everything ``other`` (a :meth:`fork` of this session) holds."""
        offset = self.time
        for h, g, w in zip(other.hand.pieces, other.grip.pieces, other.world.pieces, strict=True):
            self.add(hand=h, grip=g, world=w)
        self.activities += [Activity(a.kind, a.start_t + offset, a.end_t + offset, a.label)
                            for a in other.activities]

    @property
    def hand_pose(self) -> np.ndarray:
        """Current hand pose (4, 4) in the user frame."""
        return self._h

    @property
    def grip_pose(self) -> np.ndarray:
        """Current tracker pose (4, 4) in the hand frame."""
        return self._g

    @property
    def world_pose(self) -> np.ndarray:
        """Current user frame (4, 4) in the tracker world."""
        return self._w

    @property
    def home(self) -> np.ndarray:
        """The performer's usual hand position (3,) [m] in the user frame."""
        if self.person is None:
            return np.asarray(ANTHROPOMETRY["hand_position"][0])
        return np.asarray(self.person.hand_position)

    def move_duration(self, A: np.ndarray, B: np.ndarray) -> float:
        """Time [s] for a deliberate move between hand poses ``A`` and ``B`` (4, 4): grows with
        distance and turn; divided by the person's tempo."""
        dist = float(np.linalg.norm(B[:3, 3] - A[:3, 3]))
        ang = float(np.linalg.norm(se3.vector_from_rotation(A[:3, :3].T @ B[:3, :3])))
        d = float(np.clip(0.5 + dist / 0.35 + ang / 2.5, _MIN_APPROACH, 2.5))
        if self.person is None:
            return d
        return max(d / self.person.tempo, _MIN_MOVE)

    def move_skew(self, rng: np.random.Generator) -> float:
        """Time-warp exponent of a deliberate move (the person's skew plus trial scatter)."""
        if self.person is None:
            return math.exp(rng.normal(0, 0.1))
        a = math.exp(self.person.skew + rng.normal(0, 0.1))
        return min(max(a, SKEW_RANGE[0]), SKEW_RANGE[1])


_MIN_APPROACH = 0.6  # shortest move to a gesture's start pose [s] (replica's person)
_MIN_MOVE = 0.35  # shortest deliberate move of a quick person [s]


def _random_hand_pose(rng: np.random.Generator, around: np.ndarray, home: np.ndarray) -> np.ndarray:
    """A comfortable hand pose near the usual working position ``home`` (3,)."""
    p = home + rng.uniform([-0.15, -0.2, -0.25], [0.15, 0.2, 0.15])
    R = rot(rng.standard_normal(3), rng.uniform(0, math.radians(70))) @ around[:3, :3]
    return make_pose(R, p)


def reposition(
    s: Session,
    rng: np.random.Generator,
    target: np.ndarray | None = None,
    duration: float | None = None,
) -> None:
    """A deliberate move of the hand to ``target`` (default: a random comfortable pose)."""
    target = _random_hand_pose(rng, s.hand_pose, s.home) if target is None else target
    d = s.move_duration(s.hand_pose, target) if duration is None else duration
    s.add(hand=stroke(sclerp_path(s.hand_pose, target), d, s.move_skew(rng)))


def _distractor(s: Session, rng: np.random.Generator) -> None:
    """A few via-point movements that are no gesture (pointing, looking at the tracker)."""
    for _ in range(rng.integers(2, 5)):
        mean_p = s.home
        target = s.hand_pose.copy()
        lo, hi = mean_p - np.array([0.2, 0.3, 0.4]), mean_p + np.array([0.2, 0.3, 0.3])
        target[:3, 3] = np.clip(target[:3, 3] + rng.normal(0, 0.12, 3), lo, hi)
        target[:3, :3] = (
            rot(rng.standard_normal(3), rng.uniform(0, math.radians(70))) @ target[:3, :3]
        )
        d = s.move_duration(s.hand_pose, target) * rng.uniform(0.8, 1.2)
        s.add(hand=stroke(sclerp_path(s.hand_pose, target), d, s.move_skew(rng)))
        if rng.random() < 0.5:
            s.add(duration=rng.uniform(0.05, 0.3))


def _gait(W0: np.ndarray, W1: np.ndarray, d: float, f: float) -> Piece:
    """The user frame walking from ``W0`` to ``W1`` (4, 4) in ``d`` seconds at ``f`` steps/s, with
    gait bob and sway."""
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

    return Piece(d, world)


def _walk(s: Session, rng: np.random.Generator) -> None:
    """Walk to another spot: the user frame moves and turns in the world, with gait bob and sway."""
    W0 = s.world_pose
    heading = rng.uniform(-math.pi, math.pi)
    dist = rng.uniform(*WALK["distance"])
    direction = np.array([math.cos(heading), math.sin(heading), 0.0])
    step = make_pose(rot([0, 0, 1], rng.uniform(*WALK["turn"])), dist * direction)
    d = 1.0 + dist / 1.0  # ≈ 1 m/s plus starting and stopping
    f = rng.uniform(*WALK["step_hz"])
    s.add(world=_gait(W0, W0 @ step, d, f))


def _person_walk(s: Session, rng: np.random.Generator, turning: bool) -> None:
    """A person's walk at their own speed; ``turning``: the body turns 45–180° on the way, so the
    hand held in front is carried along an arc."""
    assert s.person is not None
    W = WALK_TURN
    heading = rng.uniform(-math.pi, math.pi)
    if turning:
        dist = rng.uniform(*W["distance"])
        turn = rng.choice([-1.0, 1.0]) * rng.uniform(*W["turn"])
    else:
        dist = rng.uniform(*WALK["distance"])
        turn = rng.uniform(-W["plain_turn"], W["plain_turn"])
    direction = np.array([math.cos(heading), math.sin(heading), 0.0])
    step = make_pose(rot([0, 0, 1], turn), dist * direction)
    d = 1.0 + dist / s.person.walk_speed + abs(turn) / W["rate"]
    f = rng.uniform(*WALK["step_hz"])
    s.add(world=_gait(s.world_pose, s.world_pose @ step, d, f))


def _regrip(s: Session, rng: np.random.Generator) -> None:
    """Re-grip the tracker: it turns and shifts in the hand while the hand stays roughly still. A
    person with a habitual grip turns it away (30–90°) and puts it back their usual way."""
    G0 = s.grip_pose
    if s.person is None:
        G1 = random_grip(rng)
    else:
        G1 = person_grip(s.person, rng)
        if s.person.grip == "habitual":
            Gm = G0.copy()
            away = rot(rng.standard_normal(3), rng.uniform(math.radians(30), math.radians(90)))
            Gm[:3, :3] = away @ G0[:3, :3]
            _grip_move(s, G0, Gm, rng)
            G0 = Gm
    _grip_move(s, G0, G1, rng)


def _grip_move(s: Session, G0: np.ndarray, G1: np.ndarray, rng: np.random.Generator) -> None:
    turn = float(np.linalg.norm(se3.vector_from_rotation(G0[:3, :3].T @ G1[:3, :3])))
    # a deliberate handling movement: peak tracker rotation speed at most ≈ 3 rad/s
    d = max(rng.uniform(1.0, 2.0), 1.875 * turn / 3.0)
    s.add(grip=stroke(sclerp_path(G0, G1), d))


def _reach_stay(s: Session, rng: np.random.Generator) -> None:
    """Reach out to a point (arm nearly extended), stay there 1–3 s, perhaps come back."""
    R = REACH
    before = s.hand_pose
    target = before.copy()
    target[:3, 3] = s.home + np.array([rng.uniform(*R["forward"]), rng.uniform(-R["side"], R["side"]),
                                       rng.uniform(*R["up"])])
    target[:3, :3] = rot(rng.standard_normal(3), rng.uniform(0, math.radians(45))) @ before[:3, :3]
    reposition(s, rng, target)
    s.add(duration=rng.uniform(*R["hold"]))
    if rng.random() < R["back"]:
        reposition(s, rng, before)


def _scratch(s: Session, rng: np.random.Generator) -> None:
    """Small fast loops or to-and-fro of the hand (2–5 cycles, 1–4 cm, 2–4 Hz), e.g. scratching,
    fidgeting, wiping; sometimes after moving the hand somewhere else first."""
    if rng.random() < 0.5:
        reposition(s, rng)
    C = SCRATCH
    cycles = int(rng.integers(C["cycles"][0], C["cycles"][1] + 1))
    f = rng.uniform(*C["hz"])
    a = rng.uniform(*C["extent"]) / 2
    ratio = rng.uniform(0.3, 1.0) if rng.random() < 0.6 else 0.0  # ellipse or to-and-fro
    wobble = rng.uniform(*C["wobble"])
    e = np.linalg.qr(rng.standard_normal((3, 3)))[0]  # random orthonormal directions
    d = cycles / f
    ramp = 0.5 / f
    H = s.hand_pose.copy()

    def hand(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=np.float64)
        env = minimum_jerk(t / ramp) * minimum_jerk((d - t) / ramp)
        w = 2 * math.pi * f * t
        off = a * env[:, None] * (np.sin(w)[:, None] * e[:, 0] + ratio * (1 - np.cos(w))[:, None] * e[:, 1])
        T = np.broadcast_to(H, (t.shape[0], 4, 4)).copy()
        T[:, :3, 3] += off
        T[:, :3, :3] = se3.rotation_from_vector((wobble * env * np.sin(w))[:, None] * e[:, 2]) @ H[:3, :3]
        return T

    s.add(hand=Piece(d, hand))


def _legacy_activity(s: Session, rng: np.random.Generator, act: str) -> None:
    if act == "hold":
        s.add(duration=rng.uniform(1.0, 3.0))
    elif act == "reposition":
        reposition(s, rng)
    elif act == "distractor":
        _distractor(s, rng)
    elif act == "walk":
        _walk(s, rng)
    else:
        _regrip(s, rng)


_PERSON_ACTIONS = {
    "reach_stay": _reach_stay,
    "scratch": _scratch,
    "walk": lambda s, rng: _person_walk(s, rng, turning=False),
    "walk_turn": lambda s, rng: _person_walk(s, rng, turning=True),
}


def interlude(s: Session, rng: np.random.Generator) -> None:
    """One to three random activities (the person's repertoire if the session has a person)."""
    table = ACTIVITIES if s.person is None else PERSON_ACTIVITIES
    names = list(table)
    probs = np.array([table[n] for n in names])
    for _ in range(rng.integers(1, 4)):
        act = names[rng.choice(len(names), p=probs / probs.sum())]
        start = s.time
        if s.person is not None and act in _PERSON_ACTIONS:
            _PERSON_ACTIONS[act](s, rng)
        else:
            _legacy_activity(s, rng, act)
        s.log(act, start)


def stop_signal(s: Session, rng: np.random.Generator) -> tuple[float, float]:
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
    s.log("stop", start)
    return start, s.time
