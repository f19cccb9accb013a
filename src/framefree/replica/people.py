"""Simulated people: how one person's gestures and habits differ from another's.

A :class:`Person` is one performer's *style*: how big and how fast they gesture, how skewed their
speed profiles are, how long they pause and rest, how much they tremble, how they hold their hand
and the tracker, their body dimensions and how consistent they are from one trial to the next.
:func:`draw_person` draws a person from a documented population (every range and its source is in
``docs/dataset.md``, section *People*); :func:`person` does so deterministically from a seed.

People are split into two disjoint groups so that numbers are never reported on people used for
tuning: :data:`DEV_PEOPLE` (seeds 0–19, for tuning and development) and :data:`HELDOUT_PEOPLE`
(seeds 1000–1019, for reporting only). :data:`DEFAULT_PERSON` is the single person of the HPM replica;
passing it (or ``None``) anywhere reproduces the replica bit for bit.

>>> from framefree.replica.people import person, DEV_PEOPLE
>>> alice = person(DEV_PEOPLE[0])
>>> 0.6 <= alice.tempo <= 1.6
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from .population import ANTHROPOMETRY, VARIATION
from .recording import (
    GRIP_OFFSET_RANGE,
    MeasurementNoise,
    measurement_noise,
    random_rotation,
    tracker_poses,
)

__all__ = [
    "DEFAULT_PERSON",
    "DEV_PEOPLE",
    "FRESH_PEOPLE",
    "HABITUAL_GRIP_WOBBLE",
    "HELDOUT_PEOPLE",
    "NOMINAL_STATURE",
    "POPULATION",
    "STYLES",
    "Person",
    "draw_person",
    "person",
    "person_grip",
    "record",
    "scaled_noise",
    "styled",
]

#: Seeds of the people used for tuning and development.
DEV_PEOPLE = range(0, 20)
#: Seeds of the people used only to report results (never for tuning). Disjoint from DEV_PEOPLE.
HELDOUT_PEOPLE = range(1000, 1020)
#: A second held-out group, first run for the fourth version of the live recognizer (the first
#: group had by then been run once for each of three earlier versions). Disjoint from both.
FRESH_PEOPLE = range(2000, 2020)

#: Body height [m] of the replica's person (the dimensions of ``ANTHROPOMETRY`` correspond to it).
NOMINAL_STATURE = 1.70

#: The population :func:`draw_person` draws from (ranges are inclusive; see docs/dataset.md).
#: Normal laws are (mean, std) truncated at ± 2.5 std and then clipped to the range given.
POPULATION = {
    # adult stature [m]: half women N(1.61, 0.066), half men N(1.75, 0.072)
    "stature": {"female": (1.61, 0.066), "male": (1.75, 0.072)},
    # elbow-to-palm distance / stature, N(mean, std): 0.33 m at 1.70 m
    "elbow_to_palm_ratio": (0.33 / NOMINAL_STATURE, 0.006),
    # personal offset of the working hand position [m], per axis std
    "hand_position_std": 0.04,
    "size": (0.7, 1.3),  # gesture size factor, log-uniform
    "tempo": (0.6, 1.6),  # speed factor (stroke durations × 1/tempo), log-uniform
    "skew": (0.25, 0.4),  # log time-warp exponent: N(0, 0.25) clipped to ± 0.4
    "pause_centre": (0.03, 0.55),  # centre of the reversal pause range [s], log-uniform
    "pause_spread": (0.6, 1.45),  # the range is centre × spread
    "rest_centre": (0.12, 1.2),  # centre of the rest range before/after a gesture [s], log-uniform
    "rest_spread": (0.7, 1.4),
    "tremor": (0.5, (0.4, 2.5)),  # tremor amplitude scale: exp(N(0, 0.5)) clipped
    "heading": (math.radians(12.0), math.radians(30.0)),  # habitual heading: N(0, std) clipped
    "hand_tilt": (math.radians(10.0), math.radians(25.0)),  # habitual hand tilt per axis
    "forearm_rotation": ((math.radians(160.0), math.radians(10.0)),
                         (math.radians(135.0), math.radians(180.0))),
    "pronation_axis_offset": ((0.03, 0.008), (0.015, 0.05)),
    "elbow_flexion": ((math.radians(50.0), math.radians(8.0)),
                      (math.radians(35.0), math.radians(65.0))),
    "habitual_grip": 0.5,  # probability of holding the tracker the same way every time
    "grip_offset_low": (0.015, 0.035),  # [m]
    "grip_offset_width": (0.01, 0.03),  # [m]
    "variability": (0.6, 1.6),  # scale of the trial-to-trial variation, log-uniform
    "walk_speed": (1.0, 1.5),  # comfortable walking speed [m/s], uniform
    # hesitations in mid-stroke: share of people who hesitate at all; their probability per
    # stroke (log-uniform); the slow phase's duration [s] (centre log-uniform, range centre ×
    # spread); where in the stroke and how slow: population.HESITATION
    "hesitant": 0.35,
    "hesitation": (0.08, 0.5),
    "hesitation_centre": (0.15, 0.45),
    "hesitation_spread": (0.7, 1.4),
    # drawing fluently: share of people who join the strokes of a drawn shape without stopping
    # at its corners, and how much consecutive strokes overlap (uniform; motion.overlapped): up
    # to a third of each side of a square curved, the hand slowing to 0.01-0.37 of its peak
    "fluent": 0.5,
    "coarticulation": (0.05, 0.3),
}

#: Trial-to-trial wobble of a habitual grip: rotation [rad] per axis and offset [m] per axis (std).
HABITUAL_GRIP_WOBBLE = (math.radians(10.0), 0.005)


@dataclass(frozen=True)
class Person:
    """One person's way of moving (all fields have the replica's person as default).

    Attributes
    ----------
    seed : int or None
        The seed the person was drawn from (``None`` for :data:`DEFAULT_PERSON`).
    stature : float
        Body height [m] (sets ``elbow_to_palm`` and ``hand_position`` when drawn).
    size : float
        Gesture size factor (population 0.7–1.3).
    tempo : float
        Speed factor: stroke durations and deliberate moves take ``1 / tempo`` times as long
        (population 0.6–1.6).
    skew : float
        Natural logarithm of the person's time-warp exponent of the minimum-jerk profile (0:
        symmetric bell; > 0: speed peak late; < 0: early). Population ± 0.4, i.e. the peak at
        0.36–0.63 of the stroke.
    pause : tuple of float
        Range [s] of the pause at the reversal of an out-and-back gesture (uniform per trial).
    rest : tuple of float
        Range [s] of the rest before and after a gesture (uniform per gesture).
    tremor : float
        Scale on the physiological tremor amplitude.
    heading : float
        Habitual heading of the gestures about the vertical [rad].
    hand_tilt : tuple of float
        Habitual tilt of the hand, rotation vector [rad] in the hand frame.
    hand_position : tuple of float
        Usual palm position [m] in the user frame (x forward, y left, z up).
    elbow_to_palm : float
        Distance [m] from the elbow's flexion axis to the palm centre.
    pronation_axis_offset : float
        Distance [m] of the forearm's rotation axis from the palm centre.
    forearm_rotation : float
        Usual pronation/supination excursion [rad] of the forearm gestures.
    elbow_flexion : float
        Usual elbow flexion [rad] of *go_up*.
    grip : str
        ``"random"`` (any orientation, new every trial) or ``"habitual"`` (the same way every
        time, up to a small wobble).
    grip_offset : tuple of float
        Range [m] of the tracker's distance from the palm centre.
    grip_rotation : tuple of float
        Rotation vector [rad] of the habitual grip (tracker in the hand frame).
    variability : float
        Scale on every trial-to-trial standard deviation (consistency of the person).
    walk_speed : float
        Walking speed [m/s] between gestures.
    hesitation : float
        Probability that a stroke of a gesture nearly stops on the way (0: never).
    hesitation_pause : tuple of float
        Range [s] of the slow phase of a hesitation (uniform per hesitation).
    coarticulation : float
        How much consecutive strokes of a drawn shape overlap, in [0, 1) (0: the hand stops at
        every corner; :func:`~framefree.replica.motion.overlapped`).
    """

    seed: int | None = None
    stature: float = NOMINAL_STATURE
    size: float = 1.0
    tempo: float = 1.0
    skew: float = 0.0
    pause: tuple[float, float] = VARIATION["pause"]
    rest: tuple[float, float] = VARIATION["rest"]
    tremor: float = 1.0
    heading: float = 0.0
    hand_tilt: tuple[float, float, float] = (0.0, 0.0, 0.0)
    hand_position: tuple[float, float, float] = ANTHROPOMETRY["hand_position"][0]
    elbow_to_palm: float = ANTHROPOMETRY["elbow_to_palm"][0]
    pronation_axis_offset: float = ANTHROPOMETRY["pronation_axis_offset"][0]
    forearm_rotation: float = ANTHROPOMETRY["forearm_rotation"][0]
    elbow_flexion: float = ANTHROPOMETRY["elbow_flexion"][0]
    grip: str = "random"
    grip_offset: tuple[float, float] = GRIP_OFFSET_RANGE
    grip_rotation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    variability: float = 1.0
    walk_speed: float = 1.0
    hesitation: float = 0.0
    hesitation_pause: tuple[float, float] = (0.0, 0.0)
    coarticulation: float = 0.0

    def __post_init__(self) -> None:
        if self.grip not in ("random", "habitual"):
            raise ValueError(f"grip must be 'random' or 'habitual', got {self.grip!r}")
        for name in ("stature", "size", "tempo", "tremor", "elbow_to_palm", "variability",
                     "walk_speed"):
            if not getattr(self, name) > 0:
                raise ValueError(f"Person.{name} must be positive, got {getattr(self, name)}")
        if not 0 <= self.hesitation <= 1:
            raise ValueError(f"Person.hesitation must be a probability, got {self.hesitation}")
        if not 0 <= self.coarticulation < 1:
            raise ValueError(f"Person.coarticulation must be in [0, 1), got {self.coarticulation}")
        for name in ("pause", "rest", "grip_offset", "hesitation_pause"):
            lo, hi = getattr(self, name)
            if not 0 <= lo <= hi:
                raise ValueError(f"Person.{name} must be a range 0 <= low <= high, got {(lo, hi)}")

    @classmethod
    def nominal(cls) -> Person:
        """The replica's person (:data:`DEFAULT_PERSON`)."""
        return cls()

    @property
    def is_nominal(self) -> bool:
        """True for the replica's person."""
        return self == DEFAULT_PERSON

    def variation(self) -> dict[str, float | tuple[float, float]]:
        """The trial-to-trial standard deviations (``VARIATION``) scaled by :attr:`variability`;
        ranges (``rest``, ``pause``) are this person's."""
        v: dict[str, float | tuple[float, float]] = {
            k: val * self.variability for k, val in VARIATION.items() if not isinstance(val, tuple)
        }
        v["rest"] = self.rest
        v["pause"] = self.pause
        return v


#: The single person of the HPM replica (every generator's default).
DEFAULT_PERSON = Person()


def _normal(rng: np.random.Generator, mean: float, std: float, lo: float, hi: float) -> float:
    return float(np.clip(mean + std * np.clip(rng.standard_normal(), -2.5, 2.5), lo, hi))


def _log_uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _range(rng: np.random.Generator, centre: tuple[float, float], spread: tuple[float, float]
           ) -> tuple[float, float]:
    c = _log_uniform(rng, *centre)
    return (c * spread[0], c * spread[1])


def draw_person(rng: np.random.Generator) -> Person:
    """Draw one person from :data:`POPULATION`.

    Parameters
    ----------
    rng : numpy.random.Generator
        All randomness comes from here.

    Returns
    -------
    Person
        With ``seed=None`` (see :func:`person` for a seeded one).
    """
    P = POPULATION
    sex = "female" if rng.random() < 0.5 else "male"
    h = _normal(rng, *P["stature"][sex], 1.45, 2.05)
    ratio = _normal(rng, *P["elbow_to_palm_ratio"], 0.17, 0.22)
    k = h / NOMINAL_STATURE
    nominal_p = np.asarray(ANTHROPOMETRY["hand_position"][0])
    hand_p = nominal_p * k + np.clip(rng.normal(0.0, P["hand_position_std"], 3), -0.1, 0.1)
    skew_std, skew_max = P["skew"]
    tremor_std, tremor_range = P["tremor"]
    grip = "habitual" if rng.random() < P["habitual_grip"] else "random"
    grip_lo = rng.uniform(*P["grip_offset_low"])
    person = Person(
        stature=h,
        size=_log_uniform(rng, *P["size"]),
        tempo=_log_uniform(rng, *P["tempo"]),
        skew=_normal(rng, 0.0, skew_std, -skew_max, skew_max),
        pause=_range(rng, P["pause_centre"], P["pause_spread"]),
        rest=_range(rng, P["rest_centre"], P["rest_spread"]),
        tremor=math.exp(_normal(rng, 0.0, tremor_std, *np.log(tremor_range))),
        heading=_normal(rng, 0.0, P["heading"][0], -P["heading"][1], P["heading"][1]),
        hand_tilt=tuple(_normal(rng, 0.0, P["hand_tilt"][0], -P["hand_tilt"][1], P["hand_tilt"][1])
                        for _ in range(3)),
        hand_position=tuple(float(x) for x in hand_p),
        elbow_to_palm=ratio * h,
        pronation_axis_offset=_normal(rng, *P["pronation_axis_offset"][0],
                                      *P["pronation_axis_offset"][1]),
        forearm_rotation=_normal(rng, *P["forearm_rotation"][0], *P["forearm_rotation"][1]),
        elbow_flexion=_normal(rng, *P["elbow_flexion"][0], *P["elbow_flexion"][1]),
        grip=grip,
        grip_offset=(grip_lo, grip_lo + rng.uniform(*P["grip_offset_width"])),
        grip_rotation=tuple(float(x) for x in se3.vector_from_rotation(random_rotation(rng))),
        variability=_log_uniform(rng, *P["variability"]),
        walk_speed=rng.uniform(*P["walk_speed"]),
    )
    # drawn last, so that every other field is the one drawn before hesitations were modelled
    if rng.random() < P["hesitant"]:
        person = replace(person, hesitation=_log_uniform(rng, *P["hesitation"]),
                         hesitation_pause=_range(rng, P["hesitation_centre"],
                                                 P["hesitation_spread"]))
    # ... and after them, fluent drawing
    if rng.random() < P["fluent"]:
        person = replace(person, coarticulation=rng.uniform(*P["coarticulation"]))
    return person


def person(seed: int) -> Person:
    """The person of ``seed`` (deterministic; use :data:`DEV_PEOPLE` / :data:`HELDOUT_PEOPLE`).

    Parameters
    ----------
    seed : int
        Non-negative integer.

    Returns
    -------
    Person
    """
    if int(seed) < 0:
        raise ValueError(f"person seed must be non-negative, got {seed}")
    return replace(draw_person(np.random.default_rng([int(seed), 0xFE0])), seed=int(seed))


#: Kinds of performer at the edges of the population, to probe a recognizer beyond the typical
#: person: each maps a drawn person to one who keeps their body, grip and habits but moves so
#: (values relative to the replica's person, who made the models).
#: *hesitant*: a quarter smaller, 40 % slower (strokes 1.4 times as long), twice the tremor, and
#: a near-stop of 0.2–0.4 s in a quarter of the strokes; *sloppy*: 30 % larger, 30 % faster, and
#: 1.5 times less consistent.
STYLES = {
    "hesitant": {"size": 0.75, "tempo": 1 / 1.4, "tremor": 2.0, "variability": 1.0,
                 "hesitation": 0.25, "hesitation_pause": (0.2, 0.4)},
    "sloppy": {"size": 1.3, "tempo": 1.3, "tremor": 1.0, "variability": 1.5,
               "hesitation": 0.0, "hesitation_pause": (0.0, 0.0)},
}


def styled(who: Person, style: str) -> Person:
    """``who`` performing in one of the :data:`STYLES`: size, tempo, tremor, variability and
    hesitations become the style's; body, posture, grip, pauses and rests stay ``who``'s.

    Parameters
    ----------
    who : Person
    style : str
        A key of :data:`STYLES`.

    Returns
    -------
    Person
    """
    if style not in STYLES:
        raise ValueError(f"unknown style {style!r}; expected one of {', '.join(STYLES)}")
    k = STYLES[style]
    return replace(who, **k)


def person_grip(who: Person, rng: np.random.Generator) -> np.ndarray:
    """Pose (4, 4) of the tracker in the hand frame for one trial (or after a re-grip).

    ``"random"`` grip: uniformly random orientation and an offset drawn from
    :attr:`Person.grip_offset` in a random direction (for :data:`DEFAULT_PERSON` the same draws as
    :func:`~framefree.replica.recording.random_grip`). ``"habitual"``: the person's own grip
    rotation and offset direction, each wobbling by :data:`HABITUAL_GRIP_WOBBLE`.
    """
    G = np.eye(4)
    if who.grip == "random":
        d = rng.standard_normal(3)
        d *= rng.uniform(*who.grip_offset) / np.linalg.norm(d)
        G[:3, :3] = random_rotation(rng)
        G[:3, 3] = d
        return G
    rot_std, pos_std = HABITUAL_GRIP_WOBBLE
    R = se3.rotation_from_vector(np.asarray(who.grip_rotation, dtype=np.float64))
    G[:3, :3] = se3.rotation_from_vector(rng.normal(0.0, rot_std, 3)) @ R
    G[:3, 3] = -R[:, 2] * rng.uniform(*who.grip_offset) + rng.normal(0.0, pos_std, 3)
    return G


def scaled_noise(noise: MeasurementNoise, who: Person) -> MeasurementNoise:
    """``noise`` with its tremor scaled by :attr:`Person.tremor` (unchanged for a scale of 1)."""
    if who.tremor == 1.0:
        return noise
    return replace(noise, tremor_p=noise.tremor_p * who.tremor,
                   tremor_phi=noise.tremor_phi * who.tremor)


def record(
    t: np.ndarray,
    hand: np.ndarray,
    grip: np.ndarray,
    world: np.ndarray,
    rng: np.random.Generator,
    who: Person,
    source: str | None = None,
) -> Trajectory:
    """:func:`~framefree.replica.recording.measure` with the person's tremor level (the same
    draws; identical to ``measure`` for a tremor scale of 1).

    Parameters
    ----------
    t : ndarray, shape (n,)
        Time stamps [s].
    hand : ndarray, shape (n, 4, 4)
        Intended hand poses in the user frame.
    grip, world : ndarray, shape (4, 4) or (n, 4, 4)
        Tracker in the hand frame; user frame in the tracker world.
    rng : numpy.random.Generator
    who : Person
    source : str, optional

    Returns
    -------
    Trajectory
    """
    noise = scaled_noise(measurement_noise(t, rng), who)
    return Trajectory.from_poses(t - t[0], tracker_poses(hand, grip, world, noise), source=source)
