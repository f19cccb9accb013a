"""Continuous sessions of many simulated people, for studies that tune on some people and report
on others.

>>> from framefree.datasets import DEV_PEOPLE, HELDOUT_PEOPLE, make_person_streams  # doctest: +SKIP
>>> tuning = make_person_streams(DEV_PEOPLE, n_streams_per_person=2)               # doctest: +SKIP
>>> report = make_person_streams(HELDOUT_PEOPLE, n_streams_per_person=2)           # doctest: +SKIP
>>> item = report[0]; item.person_seed, item.stream_seed, len(item.segments)       # doctest: +SKIP
(1000, 1000000, 21)
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import NamedTuple

import numpy as np
from tqdm.auto import tqdm

from ..core import se3
from ..core.trajectory import Trajectory
from ..datasets.stream_files import Segment
from . import people
from .activities import Activity, Session, reposition
from .gestures import default_world, plan_gesture
from .motion import Piece, make_pose
from .people import Person, person_grip, record
from .recording import sample_times
from .streams import StreamItem, _generate

__all__ = ["PersonStream", "make_person_streams", "person_stream", "take_session"]


class PersonStream(NamedTuple):
    """A session performed by a simulated person (:func:`person_stream`).

    Attributes
    ----------
    person_seed : int or None
        Seed of the person (:func:`~framefree.replica.people.person`); ``None`` if unseeded.
    stream_seed : int
        Seed of the session.
    traj : Trajectory
        The tracker poses, ≈ 50 Hz with jitter.
    segments : list of Segment
        The labelled gestures and stop signals.
    activities : list of Activity
        Everything the person did, in time order (interludes, approaches, rests, gestures).
    """

    person_seed: int | None
    stream_seed: int
    traj: Trajectory
    segments: list[Segment]
    activities: list[Activity]


def person_stream(
    seed: int,
    person: Person,
    sequence: Sequence[str | StreamItem] | None = None,
    n_gestures: int = 20,
    n_stops: int | None = None,
    world: np.ndarray | None = None,
    gestures: Sequence[str] | None = None,
) -> PersonStream:
    """:func:`make_stream` performed by ``person``, with the log of everything they did.

    Returns
    -------
    PersonStream
        ``(person_seed, stream_seed, traj, segments, activities)``; the trajectory and segments are
        those of ``make_stream(seed, ..., person=person)``.
    """
    traj, segments, activities = _generate(seed, sequence, n_gestures, n_stops, world, person, gestures)
    return PersonStream(person.seed, int(seed), traj, segments, activities)


def make_person_streams(
    person_seeds: Iterable[int],
    n_streams_per_person: int = 3,
    n_gestures: int = 20,
    n_stops: int | None = None,
    gestures: Sequence[str] | None = None,
    progress: bool = False,
) -> list[PersonStream]:
    """Sessions of several simulated people, e.g. ``make_person_streams(DEV_PEOPLE)`` to tune and
    ``make_person_streams(HELDOUT_PEOPLE)`` to report.

    Person ``p`` performs the sessions of seeds ``1000·p + k`` (k = 0 … n−1), so the sessions of
    :data:`~framefree.replica.DEV_PEOPLE` and :data:`~framefree.replica.HELDOUT_PEOPLE` never share
    a seed.

    Parameters
    ----------
    person_seeds : iterable of int
        Seeds of :func:`~framefree.replica.people.person`.
    n_streams_per_person : int
    n_gestures, n_stops, gestures
        As in :func:`make_stream`.
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of PersonStream
        In the order of ``person_seeds``, then of the session.
    """
    jobs = [(int(p), 1000 * int(p) + k) for p in person_seeds for k in range(n_streams_per_person)]
    return [
        person_stream(stream_seed, people.person(p), n_gestures=n_gestures, n_stops=n_stops,
                      gestures=gestures)
        for p, stream_seed in tqdm(jobs, desc="person streams", disable=not progress)
    ]


#: How far from the first performance's start a person begins the next one in a recording
#: session (std per axis): position [m] and rotation vector [rad], in the hand frame.
_BACK_POS, _BACK_ROT = 0.02, np.radians(4.0)


def _anchored(strokes: Sequence[Piece], T: np.ndarray) -> list[Piece]:
    """The pieces of a motion moved rigidly by ``T`` (4, 4), applied on the left."""
    return [Piece(p.duration, lambda t, f=p.fn: T @ f(t)) for p in strokes]


def take_session(
    gesture: str, who: Person, n_takes: int = 5, seed: int = 0, rest: tuple[float, float] = (1.2, 2.0),
    world: np.ndarray | None = None,
) -> PersonStream:
    """One recording of a gesture performed ``n_takes`` times, as ``framefree record`` asks for it:
    rest, perform, rest, move the hand back to where the gesture starts, rest, perform, ...

    The rests last ``rest`` seconds (uniform), longer than the recorder's shortest rest between
    takes. For a gesture that ends where it starts the move back is short; for an open stroke (a
    swipe, a Z) it is a motion of its own, which the activity log calls ``"way back"``.

    Parameters
    ----------
    gesture : str
        Any name :func:`~framefree.replica.gestures.plan_gesture` accepts.
    who : Person
    n_takes : int
    seed : int
    rest : (float, float)
        Range of each rest [s].
    world : ndarray, shape (4, 4), optional
        User frame in the tracker world (default: random, y-up).

    Returns
    -------
    PersonStream
        The recording, one segment per performance, and the log.
    """
    rng = np.random.default_rng([int(seed), 0x7A4E])
    plan = plan_gesture(gesture, rng, person=who)
    home = plan.start
    W = default_world(rng) if world is None else np.asarray(world, dtype=np.float64)
    s = Session(home, person_grip(who, rng), W, who)
    segments = []
    for k in range(n_takes):
        strokes = plan.strokes
        if k:  # back to about where the first performance began, and perform from there
            start = s.time
            back = home @ make_pose(se3.rotation_from_vector(rng.normal(0.0, _BACK_ROT, 3)),
                                    rng.normal(0.0, _BACK_POS, 3))
            reposition(s, rng, back)
            s.log("way back", start)
            plan = plan_gesture(gesture, rng, person=who)
            strokes = _anchored(plan.strokes, back @ se3.transform_inverse(plan.start))
        start = s.time
        s.add(duration=rng.uniform(*rest))
        s.log("rest", start)
        a = s.time
        for piece in strokes:
            s.add(hand=piece)
        s.log("gesture", a, gesture)
        segments.append(Segment(gesture, a, s.time))
        start = s.time
        s.add(duration=rng.uniform(*rest))
        s.log("rest", start)
    t = sample_times(s.time, rng)
    traj = record(t, s.hand.at(t), s.grip.at(t), s.world.at(t), rng, who,
                  source=f"synthetic recording of {gesture}")
    return PersonStream(who.seed, int(seed), traj, segments, s.activities)
