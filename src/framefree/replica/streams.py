"""Continuous labelled sessions for the online recognizer.

A session is a few minutes of tracker data in which gestures are performed one after the other,
separated by everything a person does in between: holding still, repositioning the hand, walking
to another spot (the user frame moves in the tracker world), re-gripping the tracker (the tracker
moves in the hand) and distractor motions that are no gesture; plus stop signals (a fast
back-and-forth wrist rotation, peak angular speed above 5 rad/s). The activities are in
:mod:`~framefree.replica.activities`; a session performed by a simulated
:class:`~framefree.replica.people.Person` uses that person's style and a richer repertoire
(reach-and-stay, walk-and-turn, scratching-like loops; see
:mod:`~framefree.replica.people_streams` for sessions of many people).

Labels (``<name>_labels.csv``, header ``label,start_t,end_t``) span the gesture's movement, from
the onset of its first stroke to the end of its last stroke (the rest before and after is not
included). The label of a stop signal is ``stop``.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from ..datasets.stream_files import Segment, labels_path, write_labels
from ..errors import DatasetError
from ..labels import STOP
from .activities import (
    ACTIVITIES,
    PERSON_ACTIVITIES,
    STOP_SIGNAL,
    WALK,
    Activity,
    Session,
    interlude,
    reposition,
    stop_signal,
)
from .gestures import EXTRA_SHAPES, GESTURE_SHAPES, default_world, plan_gesture
from .people import Person, person_grip, record, scaled_noise
from .recording import (
    measure,
    measurement_noise,
    random_grip,
    sample_times,
    tracker_poses,
    write_recording,
)
from .shapes import DRAWN_SHAPES

__all__ = [
    "ACTIVITIES",
    "PERSON_ACTIVITIES",
    "STOP",
    "STOP_SIGNAL",
    "WALK",
    "Activity",
    "LivePerson",
    "StreamItem",
    "make_stream",
    "save_stream",
]


_MIN_SETTLE = 0.2  # shortest rest before a gesture [s]
_FILL_MARGIN = 3.0  # time kept free before a scripted onset for the approach and the settling [s]


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


def _fill(s: Session, rng: np.random.Generator, until: float) -> None:
    """Random interlude activities as long as they end before time ``until`` [s]."""
    for _ in range(100):
        if until - s.time < 1.0:
            return
        trial = s.fork()
        interlude(trial, rng)
        if s.time + trial.time > until:
            return
        s.extend(trial)


def _approach(s: Session, target: np.ndarray | None) -> float:
    return 0.0 if target is None else s.move_duration(s.hand_pose, target)


def _items(
    sequence: Sequence[str | StreamItem] | None,
    n_gestures: int,
    n_stops: int | None,
    rng: np.random.Generator,
    gestures: Sequence[str] | None = None,
) -> list[StreamItem]:
    known = {STOP, *GESTURE_SHAPES, *EXTRA_SHAPES, *DRAWN_SHAPES}
    if sequence is not None:
        items = [x if isinstance(x, StreamItem) else StreamItem(str(x)) for x in sequence]
        for it in items:
            if it.label not in known:
                raise ValueError(
                    f"unknown stream label {it.label!r}; expected a gesture name or {STOP!r}"
                )
        return items
    names = list(GESTURE_SHAPES) if gestures is None else [str(g) for g in gestures]
    for g in names:
        if g not in known - {STOP}:
            raise ValueError(f"unknown gesture {g!r} in gestures")
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
    person: Person | None = None,
    gestures: Sequence[str] | None = None,
) -> tuple[Trajectory, list[Segment]]:
    """Generate a continuous labelled session.

    Parameters
    ----------
    seed : int
        Everything is deterministic given the seed (and the person).
    sequence : sequence of str or StreamItem, optional
        Script to perform: gesture names (HPM, :data:`~framefree.replica.EXTRA_SHAPES` or
        :data:`~framefree.replica.shapes.DRAWN_SHAPES`) and
        ``"stop"``, or :class:`StreamItem` entries with requested onsets / gaps / speeds. Default:
        ``n_gestures`` gestures in random order (each gesture equally often) with ``n_stops`` stop
        signals at random positions.
    n_gestures : int
        Number of gestures without a script.
    n_stops : int, optional
        Number of stop signals without a script (default: 1 or 2 at random).
    world : ndarray, shape (4, 4), optional
        Initial user frame in the tracker world (default: random, y-up).
    person : Person, optional
        Who performs (:mod:`~framefree.replica.people`): their gesture style, tempo, rests,
        tremor and grip, and the full interlude repertoire (:data:`PERSON_ACTIVITIES`: also
        reach-and-stay, walk-and-turn, scratching-like loops). Default: the replica's person and
        repertoire (bit for bit the replica's streams).
    gestures : sequence of str, optional
        Gestures drawn without a script (default: the seven HPM gestures).

    Returns
    -------
    traj : Trajectory
        The tracker poses, ≈ 50 Hz with jitter, time starting at 0.
    segments : list of Segment
        The performed gestures and stop signals, in time order.
    """
    traj, segments, _ = _generate(seed, sequence, n_gestures, n_stops, world, person, gestures)
    return traj, segments


def _generate(
    seed: int,
    sequence: Sequence[str | StreamItem] | None,
    n_gestures: int,
    n_stops: int | None,
    world: np.ndarray | None,
    who: Person | None,
    gestures: Sequence[str] | None,
) -> tuple[Trajectory, list[Segment], list[Activity]]:
    rng = np.random.default_rng([int(seed), 0x5EA])
    items = _items(sequence, n_gestures, n_stops, rng, gestures)
    s = _start_session(seed, world, rng, who)
    segments = []
    for it in items:  # a loop, not a comprehension: warnings point at the caller of make_stream
        segments.append(_perform(s, it, rng))
    start = s.time
    s.add(duration=rng.uniform(1.0, 2.0))
    s.log("idle", start)
    t = sample_times(s.time, rng)
    source = f"synthetic stream {seed}"
    if who is None:
        traj = measure(t, s.hand.at(t), s.grip.at(t), s.world.at(t), rng, source=source)
    else:
        traj = record(t, s.hand.at(t), s.grip.at(t), s.world.at(t), rng, who, source=source)
    return traj, segments, s.activities


def _start_session(
    seed: int, world: np.ndarray | None, rng: np.random.Generator, who: Person | None = None
) -> Session:
    """A session resting at the first gesture's usual start pose, in a (random) user frame."""
    W0 = default_world(rng) if world is None else np.asarray(world, dtype=np.float64)
    plan0 = plan_gesture("go_left", np.random.default_rng([int(seed), 1]), person=who)
    grip = random_grip(rng) if who is None else person_grip(who, rng)
    s = Session(plan0.start, grip, W0, who)
    s.add(duration=rng.uniform(1.0, 2.0))
    s.log("idle", 0.0)
    return s


def _lead_in(s: Session, it: StreamItem, target: np.ndarray | None, rng: np.random.Generator,
             stacklevel: int) -> tuple[float, float]:
    """What comes before an item: free activities (or, for a scripted onset, as many as fit);
    returns the durations [s] of the approach to ``target`` and of the rest before the onset."""
    if it.start_t is None and it.gap is None:
        interlude(s, rng)
        approach = _approach(s, target)
        settle = rng.uniform(0.4, 1.0) if s.person is None else rng.uniform(*s.person.rest)
        return approach, settle
    onset = float(it.start_t) if it.start_t is not None else s.time + float(it.gap)
    need = _approach(s, target) + _MIN_SETTLE
    if onset < s.time + need - 1e-9:
        if it.gap != 0.0:
            warnings.warn(
                f"{it.label} requested at {onset:.2f} s cannot start before "
                f"{s.time + need:.2f} s; starting as early as possible",
                stacklevel=stacklevel + 1,
            )
        onset = s.time + need
    _fill(s, rng, until=onset - _FILL_MARGIN)
    approach = _approach(s, target)
    return approach, onset - s.time - approach


def _perform(s: Session, it: StreamItem, rng: np.random.Generator, stacklevel: int = 4) -> Segment:
    """Add one scripted item to the session: what comes before it (free activities or a scripted
    onset), the approach to its start pose, a short rest, and the gesture or stop signal itself
    (and, for a person, a rest after it)."""
    plan = None if it.label == STOP else plan_gesture(it.label, rng, it.speed, person=s.person)
    target = None if plan is None else plan.start
    approach, settle = _lead_in(s, it, target, rng, stacklevel)
    start = s.time
    if target is not None:
        reposition(s, rng, target, approach)
        s.log("approach", start)
    if settle > 1e-9:
        start = s.time
        s.add(duration=settle)
        s.log("settle", start)
    if plan is None:
        a, b = stop_signal(s, rng)
    else:
        a = s.time
        for piece in plan.strokes:
            s.add(hand=piece)
        b = s.time
        s.log("gesture", a, it.label)
    if s.person is not None and it.start_t is None and it.gap is None:
        s.add(duration=rng.uniform(*s.person.rest))
        s.log("rest", b)
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
    person : Person, optional
        Who performs (style, repertoire, tremor, grip; see :func:`make_stream`). Default: the
        replica's person.

    Examples
    --------
    >>> person = LivePerson(0)
    >>> seg = person.perform("go_left", start_t=5.0)
    >>> person.hold(2.0)                      # watch the robot for two seconds
    >>> t, p, q = person.samples_until()      # everything performed so far, not yet emitted
    """

    def __init__(self, seed: int, world: np.ndarray | None = None, max_duration: float = 1200.0,
                 person: Person | None = None):
        rng = np.random.default_rng([int(seed), 0x11FE])
        self._rng = rng
        self.person = person
        self._session = _start_session(seed, world, rng, person)
        self._times = sample_times(float(max_duration), rng)
        noise = measurement_noise(self._times, rng)
        self._noise = noise if person is None else scaled_noise(noise, person)
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
        seg = _perform(self._session, StreamItem(label, start_t, gap, speed), self._rng, stacklevel=3)
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


def save_stream(
    path: str | Path,
    traj: Trajectory,
    segments: Sequence[Segment],
    rng: np.random.Generator | None = None,
) -> Path:
    """Write the stream CSV and its ``<name>_labels.csv``; with ``rng``, quaternions are stored
    with SDK-like sign flips. Returns the stream path."""
    path = write_recording(path, traj, rng)
    write_labels(labels_path(path), segments)
    return path
