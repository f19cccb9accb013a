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

from ..core.trajectory import Trajectory
from ..datasets.stream_files import Segment
from . import people
from .activities import Activity
from .people import Person
from .streams import StreamItem, _generate

__all__ = ["PersonStream", "make_person_streams", "person_stream"]


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
