"""The seven hand-palm gestures of the HPM dataset as a person holding a tracker makes them.

Geometry (the paper, Section III; docs/dataset.md, *Gesture geometry*), in the *user frame*
(x forward, y to the user's left, z up) for a right hand whose *hand frame* has x along the
fingers, y towards the thumb when the palm faces down, z out of the back of the hand:

==============  ===========================================================================
go_left         straight-line translation to the left (≈ 30 cm), pause, back
go_right        a full circle (radius ≈ 12 cm) in the frontal plane with a slight forearm roll
                (8–20°); no reverse
go_up           elbow flexion: rotation of ≈ 50° about a lateral axis through the elbow (≈ 33 cm
                behind the palm): the hand rises while the forearm rotates; pause, back
go_down         palm up → palm down: pronation of ≈ 165° about the forearm axis, which passes a few
                centimetres from the palm centre; pause, back
open_gripper    from palm down, move forward ≈ 20 cm while supinating ≈ 165° about the forearm axis:
                a positive-pitch screw; pause, back
close_gripper   from palm up, move forward while pronating: the same screw with negative pitch
go_home         pure translation along a circular arc of ≈ 150° (radius ≈ 14 cm) over the top;
                pause, back
==============  ===========================================================================

Pairs that differ only in shape: open/close gripper (sign of the pitch), go_left/go_home (line vs
arc), go_down/go_up (rotation about a near vs a far axis), go_down/close_gripper (with or without
the advance). Human variation per trial: size, speed, start pose, heading, slight asymmetry of the
speed profiles, mid-path deviations, pause length, and an imperfect return to the start. Variation
between people (:mod:`~framefree.replica.people`) enters through the ``person`` argument; two more
shapes that are no HPM gesture (*figure_eight*, *push_twist*) are in :data:`EXTRA_SHAPES`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from ..datasets.layout import GESTURES
from .motion import (
    Motion,
    Path,
    Piece,
    deviated,
    hesitant_stroke,
    hold,
    make_pose,
    overlapped,
    reversed_path,
    rot,
    screw_path,
    stroke,
    translation_path,
)
from .population import ANTHROPOMETRY, HESITATION
from .recording import measure, random_grip, sample_times
from .shapes import DRAWN_SHAPES, shape_strokes

if TYPE_CHECKING:
    from .people import Person

__all__ = [
    "EXTRA_SHAPES",
    "GESTURE_SHAPES",
    "PALM_DOWN",
    "PALM_LEFT",
    "PALM_UP",
    "SKEW_RANGE",
    "GesturePlan",
    "default_world",
    "gesture_motion",
    "plan_gesture",
    "synthesize_gesture",
]

#: Hand orientations in the user frame (written out, so that importing needs no compiled kernel).
PALM_DOWN = np.eye(3)
PALM_UP = np.diag([1.0, -1.0, -1.0])  # half a turn about x
# quarter turn about x: thumb up, palm facing left
PALM_LEFT = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])

#: Nominal sizes and stroke durations of the gestures (deliberate, comfortable gestures: peak hand
#: speeds 0.5–0.8 m/s and peak forearm rotation speeds below ≈ 4 rad/s, typical of unhurried
#: pointing and turning movements). ``size`` [m] is the path extent, ``duration`` [s] one stroke.
GESTURE_SHAPES = {
    "go_left": {"size": 0.30, "duration": 0.9},
    "go_right": {"size": 0.12, "duration": 2.0, "roll": (math.radians(8.0), math.radians(20.0))},
    "go_up": {"size": 0.30, "duration": 1.0},
    "go_down": {"size": 0.05, "duration": 1.4},
    "open_gripper": {"size": 0.20, "duration": 1.4},
    "close_gripper": {"size": 0.20, "duration": 1.4},
    "go_home": {"size": 0.14, "duration": 1.2, "arc": (math.radians(150.0), math.radians(12.0))},
}

@dataclass(frozen=True)
class GesturePlan:
    """One performance of a gesture, before recording.

    Attributes
    ----------
    gesture : str
    start : ndarray, shape (4, 4)
        Hand pose in the user frame where the gesture starts.
    strokes : list of Piece
        The movement (strokes and the pause at the reversal), starting at ``start``.
    """

    gesture: str
    start: np.ndarray
    strokes: list[Piece]

    @property
    def duration(self) -> float:
        """Duration of the movement [s] (no rest)."""
        return float(sum(p.duration for p in self.strokes))

    @property
    def end(self) -> np.ndarray:
        """Final hand pose (4, 4)."""
        return self.strokes[-1].end


def _clipped(rng: np.random.Generator, mean: float, std: float, k: float = 2.5) -> float:
    return float(mean + std * np.clip(rng.standard_normal(), -k, k))


def _small_rotation(rng: np.random.Generator, std: float) -> np.ndarray:
    """A random rotation whose rotation vector has independent N(0, std²) components."""
    phi = rng.normal(0.0, std, 3)
    return se3.rotation_from_vector(phi)


def _circle_path(start: np.ndarray, center: np.ndarray, axis: np.ndarray, angle: float, roll: float,
                 roll_axis: np.ndarray, phase: float) -> Path:
    """Translation around a circle plus a sinusoidal roll of the hand about ``roll_axis``."""
    R0 = start[:3, :3]
    p0 = start[:3, 3]

    def path(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=np.float64)
        Rc = se3.rotation_from_vector(s[:, None] * angle * axis)
        p = np.einsum("nij,j->ni", Rc, p0 - center) + center
        r = roll * (np.sin(2 * math.pi * s + phase) - math.sin(phase))
        Rr = se3.rotation_from_vector(r[:, None] * roll_axis)
        T = np.zeros((s.shape[0], 4, 4))
        T[:, :3, :3] = Rr @ R0
        T[:, :3, 3] = p
        T[:, 3, 3] = 1.0
        return T

    return path


def _arc_offset(r: float, angle: float, e1: np.ndarray, e2: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """Offsets (n, 3) along a circular arc over the top, from its right end towards its left end."""
    a0 = math.pi / 2 + angle / 2

    def offset(s: np.ndarray) -> np.ndarray:
        a = a0 - angle * np.asarray(s, dtype=np.float64)
        return r * ((np.cos(a) - math.cos(a0))[:, None] * e1 + (np.sin(a) - math.sin(a0))[:, None] * e2)

    return offset


#: Gestures beyond the HPM seven (not part of the replica), e.g. to teach a user's own gesture:
#: *figure_eight*: the hand traces a horizontal figure eight (lemniscate, ``size`` wide, ``height``
#: tall) in the frontal plane, starting and ending at its crossing, palm down; no reverse.
#: *push_twist*: from a handshake pose (palm left), push forward ``size`` metres while turning
#: the wrist ``twist`` radians about the forearm (supination); pause, back.
EXTRA_SHAPES = {
    "figure_eight": {"size": 0.30, "height": 0.12, "duration": 2.6},
    "push_twist": {"size": 0.22, "duration": 1.2, "twist": (math.radians(90.0), math.radians(8.0))},
}


def _lemniscate_offset(width: float, height: float, e1: np.ndarray, e2: np.ndarray
                       ) -> Callable[[np.ndarray], np.ndarray]:
    """Offsets (n, 3) along a figure eight (lemniscate of Gerono) through its crossing point: one
    lobe towards ``e1`` for ``s`` in [0, ½], the other for [½, 1]."""

    def offset(s: np.ndarray) -> np.ndarray:
        a = 2 * math.pi * np.asarray(s, dtype=np.float64)
        return (width / 2) * np.sin(a)[:, None] * e1 + (height / 2) * np.sin(2 * a)[:, None] * e2

    return offset


def _resolve(person: Person | None) -> Person:
    from .people import DEFAULT_PERSON  # people.py builds on this module's constants

    return DEFAULT_PERSON if person is None else person


class _Performance:
    """The random draws of one performance, in the order the replica has always made them."""

    def __init__(self, gesture: str, rng: np.random.Generator, speed: float, who: Person) -> None:
        V = who.variation()
        self.rng, self.who, self.V = rng, who, V
        self.shape = GESTURE_SHAPES.get(gesture) or EXTRA_SHAPES.get(gesture) or DRAWN_SHAPES[gesture]
        self.scale = who.size * math.exp(_clipped(rng, 0.0, V["size"]))
        self.tempo = math.exp(_clipped(rng, 0.0, V["speed"])) / speed / who.tempo
        # geometry frame of this performance: heading about the vertical, small tilt
        self.Rg = rot([0, 0, 1], who.heading + _clipped(rng, 0.0, V["heading"])) @ _small_rotation(
            rng, V["tilt"]
        )
        self.fwd, self.left, self.up = self.Rg[:, 0], self.Rg[:, 1], self.Rg[:, 2]
        std_p = ANTHROPOMETRY["hand_position"][1] * who.variability
        self.p0 = np.asarray(who.hand_position) + std_p * np.clip(rng.standard_normal(3), -2.5, 2.5)
        self.size = self.shape.get("size", 1.0) * self.scale

    def anatomy(self, name: str) -> float:
        """A body dimension or joint excursion of this trial: the person's value ± trial std."""
        return _clipped(self.rng, getattr(self.who, name), ANTHROPOMETRY[name][1] * self.who.variability)

    def duration(self) -> float:
        return self.shape["duration"] * self.tempo * math.exp(_clipped(self.rng, 0.0, self.V["stroke_speed"]))

    def skew(self) -> float:
        a = math.exp(self.who.skew + _clipped(self.rng, 0.0, self.V["skew"]))
        return min(max(a, SKEW_RANGE[0]), SKEW_RANGE[1])

    def bulge(self) -> tuple[np.ndarray, np.ndarray]:
        b = self.V["bulge_rel"] * self.size + self.V["bulge_abs"]
        return self.rng.normal(0.0, b, 3), self.rng.normal(0.0, self.V["bulge_rot"], 3)

    def hand(self, R_base: np.ndarray) -> np.ndarray:
        R = _small_rotation(self.rng, self.V["hand_tilt"]) @ self.Rg @ R_base
        if any(self.who.hand_tilt):
            R = R @ se3.rotation_from_vector(np.asarray(self.who.hand_tilt, dtype=np.float64))
        return make_pose(R, self.p0)

    def forearm_screw(self, start: np.ndarray, sign: float, advance: float, angle: float | None = None
                      ) -> Path:
        angle = sign * (self.anatomy("forearm_rotation") if angle is None else angle)
        angle = float(np.clip(angle, -math.radians(185), math.radians(185)))
        off_dir = np.cross(self.fwd, self.rng.standard_normal(3))
        off = off_dir / np.linalg.norm(off_dir) * max(0.01, self.anatomy("pronation_axis_offset"))
        return screw_path(start, self.fwd, start[:3, 3] + off, angle, advance)

    def stroke(self, path: Path) -> Piece:
        """One timed stroke along ``path``: this performance's duration and skew, and a
        hesitation on the way with the person's probability (no draw for people who never
        hesitate, so their performances are those drawn before hesitations were modelled)."""
        duration, skew = self.duration(), self.skew()
        who = self.who
        if who.hesitation <= 0 or self.rng.random() >= who.hesitation:
            return stroke(path, duration, skew)
        at = self.rng.uniform(*HESITATION["at"])
        pause = self.rng.uniform(*who.hesitation_pause)
        residual = self.rng.uniform(*HESITATION["residual"])
        return hesitant_stroke(path, duration, skew, at, pause, residual)

    def end_error(self) -> tuple[np.ndarray, np.ndarray]:
        return self.rng.normal(0.0, self.V["return_pos"], 3), self.rng.normal(0.0, self.V["return_rot"], 3)


#: Limits of the time-warp exponent of a stroke (peak speed at 0.35–0.65 of the stroke).
SKEW_RANGE = (0.67, 1.6)


def _outward(gesture: str, g: _Performance) -> tuple[np.ndarray, Path]:
    """Start pose and outward path of an out-and-back gesture."""
    rng = g.rng
    if gesture == "go_left":
        start = g.hand(PALM_LEFT)
        return start, translation_path(start, lambda s: s[:, None] * g.size * g.left)
    if gesture == "go_up":
        start = g.hand(PALM_DOWN)
        elbow = g.p0 - g.anatomy("elbow_to_palm") * g.fwd
        angle = g.anatomy("elbow_flexion") * math.sqrt(g.scale)
        return start, screw_path(start, g.left, elbow, -angle)
    if gesture == "go_down":
        start = g.hand(PALM_UP)
        return start, g.forearm_screw(start, -1.0, 0.0)
    if gesture == "open_gripper":
        start = g.hand(PALM_DOWN)
        return start, g.forearm_screw(start, +1.0, g.size)
    if gesture == "close_gripper":
        start = g.hand(PALM_UP)
        return start, g.forearm_screw(start, -1.0, g.size)
    if gesture == "push_twist":
        start = g.hand(PALM_LEFT)
        twist = _clipped(rng, g.shape["twist"][0], g.shape["twist"][1] * g.who.variability)
        return start, g.forearm_screw(start, +1.0, g.size, twist)
    # go_home
    start = g.hand(PALM_DOWN)
    arc = _clipped(rng, g.shape["arc"][0], g.shape["arc"][1] * g.who.variability)
    arc = float(np.clip(arc, math.radians(120), math.radians(180)))
    return start, translation_path(start, _arc_offset(g.size, arc, g.left, g.up))


def _once(gesture: str, g: _Performance) -> tuple[np.ndarray, Path]:
    """Start pose and path of a gesture made once, without a reverse (go_right, figure_eight)."""
    rng = g.rng
    start = g.hand(PALM_DOWN)
    if gesture == "figure_eight":
        height = g.shape["height"] * g.scale
        return start, translation_path(start, _lemniscate_offset(g.size, height, g.left, g.up))
    center = g.p0 + g.size * g.up
    roll = rng.uniform(*g.shape["roll"])
    return start, _circle_path(start, center, g.fwd, -2 * math.pi, roll, g.fwd, rng.uniform(0, 2 * math.pi))


def _drawn(gesture: str, g: _Performance) -> tuple[np.ndarray, list[Piece]]:
    """Start pose and strokes of a shape drawn in the air (:mod:`~framefree.replica.shapes`):
    one stroke per side, each with its own deviation, and a short hold at some corners; a person
    who draws fluently (``Person.coarticulation``) joins the sides without stopping instead
    (:func:`~framefree.replica.motion.overlapped`)."""
    rng = g.rng
    start = g.hand(PALM_DOWN)
    right = -g.left
    pieces: list[Piece] = []
    pose = start
    strokes = shape_strokes(gesture)
    for k, offset in enumerate(strokes):
        def planar(s: np.ndarray, f=offset) -> np.ndarray:
            xy = g.scale * (f(s) - f(np.zeros(1)))
            return xy[:, :1] * right + xy[:, 1:] * g.up

        bp, br = g.bulge()
        ends = g.end_error() if k == len(strokes) - 1 else (None, None)
        piece = g.stroke(deviated(translation_path(pose, planar), bp, br, *ends))
        pieces.append(piece)
        pose = piece.end
        if k < len(strokes) - 1 and not g.who.coarticulation and rng.random() < 0.5:
            pieces.append(hold(pose, rng.uniform(0.0, 0.08)))
    if g.who.coarticulation and len(pieces) > 1:
        pieces = [overlapped(pieces, g.who.coarticulation)]
    return start, pieces


#: Gestures made once, without a reverse stroke.
_ONCE = ("go_right", "figure_eight")


def plan_gesture(
    gesture: str, rng: np.random.Generator, speed: float = 1.0, person: Person | None = None
) -> GesturePlan:
    """Draw one human performance of ``gesture``: its start pose and its timed strokes.

    Parameters
    ----------
    gesture : str
        One of :data:`~framefree.datasets.GESTURES`, :data:`EXTRA_SHAPES` or
        :data:`~framefree.replica.shapes.DRAWN_SHAPES`.
    rng : numpy.random.Generator
    speed : float
        Extra speed factor (2 = twice as fast as this person would normally move).
    person : Person, optional
        Whose style (:mod:`~framefree.replica.people`); default: the replica's person (the
        draws and results are then exactly those of the replica).

    Returns
    -------
    GesturePlan
    """
    if gesture not in GESTURE_SHAPES and gesture not in EXTRA_SHAPES and gesture not in DRAWN_SHAPES:
        expected = ", ".join([*GESTURES, *EXTRA_SHAPES, *DRAWN_SHAPES])
        raise ValueError(f"unknown gesture {gesture!r}; expected one of {expected}")
    if not speed > 0:
        raise ValueError(f"speed must be positive, got {speed}")
    g = _Performance(gesture, rng, speed, _resolve(person))
    if gesture in DRAWN_SHAPES:
        return GesturePlan(gesture, *_drawn(gesture, g))
    if gesture in _ONCE:
        start, path = _once(gesture, g)
        bp, br = g.bulge()
        end_p, end_r = g.end_error()
        once = g.stroke(deviated(path, bp, br, end_p, end_r))
        return GesturePlan(gesture, start, [once])
    start, fwd_path = _outward(gesture, g)
    bp, br = g.bulge()
    there = deviated(fwd_path, bp, br)
    bp, br = g.bulge()
    back = deviated(reversed_path(there), bp, br, *g.end_error())
    first = g.stroke(there)
    pause = hold(first.end, rng.uniform(*g.V["pause"]))
    return GesturePlan(gesture, start, [first, pause, g.stroke(back)])


def gesture_motion(plan: GesturePlan, rng: np.random.Generator, person: Person | None = None) -> Motion:
    """The hand motion of a recorded trial: rest, the gesture, rest (rest ranges of ``person``)."""
    rest = _resolve(person).rest
    return Motion([hold(plan.start, rng.uniform(*rest)), *plan.strokes, hold(plan.end, rng.uniform(*rest))])


def default_world(rng: np.random.Generator) -> np.ndarray:
    """Pose (4, 4) of the user frame in the tracker world: SteamVR-style y-up world (the user's z
    axis maps to world y), random heading, standing within 1 m of the world origin."""
    R = rot([1, 0, 0], -math.pi / 2) @ rot([0, 0, 1], rng.uniform(-math.pi, math.pi))
    xy = rng.uniform(-1.0, 1.0, 2)
    return make_pose(R, np.array([xy[0], 0.0, xy[1]]))


def synthesize_gesture(
    gesture: str,
    rng: np.random.Generator,
    speed: float = 1.0,
    world: np.ndarray | None = None,
    grip: np.ndarray | None = None,
    source: str | None = None,
    person: Person | None = None,
) -> Trajectory:
    """One realistic recorded trial of ``gesture`` (the *Original 1* recording of the replica).

    Parameters
    ----------
    gesture : str
        One of :data:`~framefree.datasets.GESTURES` or of :data:`EXTRA_SHAPES`.
    rng : numpy.random.Generator
        All randomness comes from here.
    speed : float
        Extra speed factor (1: the person's natural pace).
    world : ndarray, shape (4, 4), optional
        User frame in the tracker world (default: :func:`default_world`).
    grip : ndarray, shape (4, 4), optional
        Tracker in the hand frame (default: :func:`~framefree.replica.recording.random_grip`, or
        the person's grip style, :func:`~framefree.replica.people.person_grip`).
    source : str, optional
        Label for the trajectory.
    person : Person, optional
        Who performs it (:mod:`~framefree.replica.people`): size, tempo, skew, pauses, rests,
        tremor, posture, body dimensions, grip style, consistency. Default: the replica's person
        (then the result is bit for bit the replica's).

    Returns
    -------
    Trajectory
        Rest, the gesture (and its return), rest, at 50 Hz (with jitter); about 3–5 s for the
        replica's person.
    """
    plan = plan_gesture(gesture, rng, speed, person)
    motion = gesture_motion(plan, rng, person)
    if world is None:
        world = default_world(rng)
    source = source or f"synthetic {gesture}"
    if person is None:
        if grip is None:
            grip = random_grip(rng)
        t = sample_times(motion.duration, rng)
        return measure(t, motion.at(t), grip, world, rng, source=source)
    from .people import person_grip, record

    if grip is None:
        grip = person_grip(person, rng)
    t = sample_times(motion.duration, rng)
    return record(t, motion.at(t), grip, world, rng, person, source=source)
