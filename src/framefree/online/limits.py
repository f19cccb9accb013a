"""What a gesture's demonstrations say a performance of it must be, whoever performs it: the
limits a live candidate must keep besides the threshold.

Every limit is measured on the model recordings as the live recognizer measures a candidate
(cut into movement units by :class:`~framefree.online.segmentation.MotionSegmenter`):

* how many units, how long, how long a rest inside (:func:`candidate_limits`), and whether a
  gesture pauses at its corners or is drawn in one go (:func:`one_go_gestures`);
* how far it ends from its start (:func:`closure_limit`, :func:`opening_limit`,
  :func:`pooled_closures`), how large it is (:func:`size_limits`);
* how many corners (:func:`corner_limit`), which way they turn (:func:`forbidden_turns`) and
  how long the strokes between them are, one against the next (:func:`gesture_proportions`,
  :mod:`framefree.online.proportions`);
* with a known vertical, how vertically it moves (:func:`gesture_verticality`).

The constants that widen them (how much slower, larger, or more broken up another person may
be) were chosen on development people and, where they exist, real people
(``benchmarks/real_*.py``, docs/online.md). The thresholds on the distance are
:mod:`framefree.online.thresholds`'.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import numpy as np

from ..core.progress import cumulative_progress
from ..core.trajectory import Trajectory
from .hand_direction import hand_direction
from .proportions import proportions
from .segment_classifier import SegmentClassifier
from .segmentation import MotionSegmenter, SpeedLevels, Unit
from .span_shape import (
    ALTERNATING,
    SAME_SENSE,
    closure,
    corner_count,
    corner_rest,
    travel,
    turn_kinds,
)
from .vertical import verticality

__all__ = [
    "candidate_limits",
    "closure_limit",
    "corner_limit",
    "forbidden_turns",
    "gesture_directions",
    "gesture_geometry",
    "gesture_proportions",
    "gesture_travels",
    "gesture_verticality",
    "limits_of_units",
    "longest_corner_rest",
    "longest_gaps",
    "measure_gestures",
    "odd_rest_take",
    "one_go_gestures",
    "opening_limit",
    "pooled_closures",
    "recording_direction",
    "recording_geometry",
    "recording_units",
    "size_limits",
    "travel_limit",
    "travel_percentiles",
    "travel_shares",
]


def recording_units(traj: Trajectory, levels: SpeedLevels, L: float, dt: float
                    ) -> tuple[MotionSegmenter, list[Unit]]:
    """A recording cut into movement units on the uniform grid, as the live segmenter cuts a
    stream: ``(segmenter, units)``; the segmenter's buffer holds the poses. A recording is one
    gesture, so a unit still in progress at its end (a take cut without a rest after it) ends
    there."""
    seg = MotionSegmenter(levels, L, dt, capacity=max(16, int(traj.duration / dt) + 8))
    times, poses = traj.uniform_poses(dt)
    units = [u for k in range(times.size) if (u := seg.push(float(times[k]), poses[k])) is not None]
    if (last := seg.finish()) is not None:
        units.append(last)
    return seg, units




def gesture_proportions(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    dt: float = 0.02, corner_angle: float = 60.0,
) -> dict[str, list[np.ndarray]]:
    """The :func:`~framefree.online.proportions.proportions` of each gesture's recordings, cut
    into units as the live segmenter cuts them: ``{g: [(K,) of each recording]}``; a recording
    with no movement unit is left out."""
    out: dict[str, list[np.ndarray]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        _, units = recording_units(tr, levels, L, dt)
        if units:
            out.setdefault(g, []).append(proportions(units, corner_angle))
    return out


def recording_geometry(
    traj: Trajectory, classifier: SegmentClassifier, levels: SpeedLevels, L: float,
    margin: int = 5, dt: float = 0.02, corner_angle: float = 60.0,
) -> tuple[float, float, int, int] | None:
    """Closure, size [m], corners and turn kinds of one recording's gesture, measured on the
    whole gesture (first unit's start to last unit's end; the size with ``margin`` samples around
    it, as a live candidate is cut), corners and turns as in
    :func:`~framefree.online.span_shape.corner_count` and
    :func:`~framefree.online.span_shape.turn_kinds`; ``None`` if the recording has no movement
    unit."""
    seg, units = recording_units(traj, levels, L, dt)
    if not units:
        return None
    _, P = seg.buffer.slice(units[0].start, units[-1].end)
    t, P_margin = seg.buffer.slice(units[0].start - margin, units[-1].end + margin)
    described = classifier.describe(t, P_margin)
    size = 0.0 if described is None else float(described[1])
    return closure(P, L), size, corner_count(units, corner_angle), turn_kinds(units, corner_angle)


def gesture_geometry(
    trajectories: Sequence[Trajectory], labels: Sequence[str], classifier: SegmentClassifier,
    levels: SpeedLevels, L: float, margin: int = 5, dt: float = 0.02, corner_angle: float = 60.0,
) -> tuple[dict[str, tuple[float, float]], dict[str, tuple[float, float]], dict[str, list[int]],
           dict[str, list[int]]]:
    """Closure range, size range [m], corners and turn kinds of each gesture's recordings
    (:func:`recording_geometry`): ``({g: (smallest, largest closure)}, {g: (smallest, largest
    size)}, {g: [corners of each recording]}, {g: [turn kinds of each recording]})``."""
    closures: dict[str, tuple[float, float]] = {}
    sizes: dict[str, tuple[float, float]] = {}
    corners: dict[str, list[int]] = {}
    turns: dict[str, list[int]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        measured = recording_geometry(tr, classifier, levels, L, margin, dt, corner_angle)
        if measured is None:
            continue
        c, size, n, kinds = measured
        corners.setdefault(g, []).append(n)
        turns.setdefault(g, []).append(kinds)
        lo, hi = closures.get(g, (np.inf, 0.0))
        closures[g] = (min(lo, c), max(hi, c))
        lo, hi = sizes.get(g, (np.inf, 0.0))
        sizes[g] = (min(lo, size), max(hi, size))
    return closures, sizes, corners, turns


def gesture_verticality(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    up: np.ndarray, dt: float = 0.02,
) -> dict[str, list[float]]:
    """:func:`~framefree.online.vertical.verticality` of each gesture's recordings
    (:func:`measure_gestures`): ``{g: [verticality of each recording]}``."""
    return measure_gestures(trajectories, labels, levels, L, dt, lambda P: verticality(P, up))


def gesture_directions(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    dt: float = 0.02, measure: Callable[[np.ndarray], np.ndarray | None] = hand_direction,
) -> dict[str, list[np.ndarray]]:
    """:func:`~framefree.online.hand_direction.hand_direction` (3,) of each gesture's recordings
    (or another ``measure`` of their poses (n, 4, 4), such as
    :func:`~framefree.online.hand_direction.hand_turn`), taken on the whole gesture as
    :func:`measure_gestures` takes its measures (a recording without a movement unit, or whose
    measure is undefined, is left out)."""
    out: dict[str, list[np.ndarray]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        if (way := recording_direction(tr, levels, L, dt, measure)) is not None:
            out.setdefault(g, []).append(way)
    return out


def recording_direction(traj: Trajectory, levels: SpeedLevels, L: float, dt: float = 0.02,
                        measure: Callable[[np.ndarray], np.ndarray | None] = hand_direction,
                        ) -> np.ndarray | None:
    """A recording's :func:`~framefree.online.hand_direction.hand_direction` (3,) (or
    ``measure``) from its first movement unit's start to its last one's end (None without a
    unit or a direction)."""
    seg, units = recording_units(traj, levels, L, dt)
    if not units:
        return None
    return measure(seg.buffer.slice(units[0].start, units[-1].end)[1])


def measure_gestures(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    dt: float, measure: Callable[[np.ndarray], float],
) -> dict[str, list[float]]:
    """``measure`` of each recording's grid poses (n, 4, 4), taken on the whole gesture (first
    unit's start to last unit's end) as :func:`recording_geometry` measures the rest: ``{g:
    [value of each recording]}`` (a recording without a movement unit is left out)."""
    out: dict[str, list[float]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        seg, units = recording_units(tr, levels, L, dt)
        if units:
            _, P = seg.buffer.slice(units[0].start, units[-1].end)
            out.setdefault(g, []).append(float(measure(P)))
    return out


def gesture_travels(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    dt: float = 0.02, presmooth: int = 5,
) -> dict[str, list[float]]:
    """How far the hand travels [m] in each gesture's recordings
    (:func:`~framefree.online.span_shape.travel`, :func:`measure_gestures`): ``{g: [travel of
    each recording]}``."""
    return measure_gestures(trajectories, labels, levels, L, dt, lambda P: travel(P, presmooth))


#: Percentile of the takes' travel that sets the travel limit of a gesture that turns the hand
#: more than it moves it (:func:`travel_percentiles`).
TURNING_PERCENTILE = 10.0


def travel_shares(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    dt: float = 0.02, presmooth: int = 5,
) -> dict[str, list[float]]:
    """How much of each recording's screw path is the hand's path
    (:func:`~framefree.online.span_shape.travel` over the screw path, :func:`measure_gestures`):
    about 1 for a stroke of the hand, small for a turn of the forearm in place. ``{g: [share of
    each recording]}``."""
    def share(P: np.ndarray) -> float:
        path = float(cumulative_progress(P, "screw", L)[-1])
        return travel(P, presmooth) / path if path > 0 else 0.0
    return measure_gestures(trajectories, labels, levels, L, dt, share)


def travel_percentiles(shares: dict[str, Sequence[float]], percentile: float,
                       moving_share: float) -> dict[str, float]:
    """Which percentile of its takes' travel sets each gesture's travel limit: ``percentile`` for
    a gesture that moves the hand (its median take's ``shares`` at least ``moving_share``),
    :data:`TURNING_PERCENTILE` for one that turns it more than it moves it, whose travel is
    incidental and uneven (a forearm turn moves the hand 0.12-0.36 m in five takes)."""
    return {g: percentile if len(s) and float(np.median(s)) >= moving_share
            else TURNING_PERCENTILE for g, s in shares.items()}


def travel_limit(travels: Sequence[float], factor: float, percentile: float = 10.0) -> float:
    """The shortest travel [m] accepted for a gesture whose recordings travel ``travels``: their
    ``percentile`` (a typical or small performance, robust to one take far smaller than the
    others) over ``factor``, how much smaller people make a gesture (``size_factor``). 0 (no
    limit) without recordings."""
    if len(travels) == 0:
        return 0.0
    return float(np.percentile(np.asarray(travels, dtype=float), percentile)) / factor


def size_limits(smallest: float, largest: float, factor: float, growth: float | None = None
                ) -> tuple[float, float]:
    """Sizes accepted for a gesture whose demonstrations span ``[smallest, largest]`` [m]: people
    make the same gesture smaller by up to ``factor`` and larger by up to ``growth`` (``None``:
    ``factor``)."""
    return smallest / factor, largest * (factor if growth is None else growth)


#: How many times longer than every other take's its longest rest between two moves must be for
#: a take to take no part in the candidate limits (:func:`odd_rest_take`).
OUTLIER_RATIO = 2.0


def candidate_limits(
    trajectories: Sequence[Trajectory], levels: SpeedLevels, L: float, span_factor: float,
    pause_factor: float, dt: float = 0.02, labels: Sequence[str] | None = None,
    min_pause: float = 0.5,
) -> tuple[int, float, float, float]:
    """Candidate limits from the model recordings: ``(max_units, max_duration, max_pause,
    pause_ratio)``.

    Twice the most units of any recording plus one (a hesitation may cut every stroke in two, and
    one unit more); ``span_factor`` × the longest gesture (first
    unit's start to last unit's end); ``span_factor`` × the longest rest between two units of one
    recording [s]; ``pause_factor`` × the largest ratio of such a rest to the mean duration of the
    two units around it. With ``labels`` (the recordings' gestures), a recording that rests far
    longer than any other (:func:`odd_rest_take`, with ``min_pause`` [s]) takes no part.
    """
    return limits_of_units([recording_units(tr, levels, L, dt)[1] for tr in trajectories],
                           span_factor, pause_factor, labels, min_pause)


def longest_gaps(recordings: Sequence[Sequence[Unit]]) -> np.ndarray:
    """The longest rest [s] between two consecutive movement units of each recording (N,)
    (0: one unit, or none)."""
    return np.array([max((b.start_t - a.end_t for a, b in itertools.pairwise(units)),
                         default=0.0) for units in recordings])


def odd_rest_take(gaps: Sequence[float] | np.ndarray, labels: Sequence[str], min_pause: float,
                  ratio: float = OUTLIER_RATIO) -> int | None:
    """The take that rests far longer between two of its moves than any other, or ``None``.

    Its longest rest ``gaps[k]`` [s] (:func:`longest_gaps`) is longer than a gesture may rest at
    a corner anyway (``min_pause``) and more than ``ratio`` times every other take's, and its
    gesture has other takes, which rest less than half as long: such a take holds a second move
    after a real rest (the way back, a settling move, two performances), not a pause its gesture
    makes. A gesture of one take may pause as it does. ``None`` with fewer than three takes.
    """
    gaps = np.asarray(gaps, dtype=float)
    if gaps.size < 3:
        return None
    order = np.argsort(gaps)
    k = int(order[-1])
    if gaps[k] <= min_pause or gaps[k] <= ratio * gaps[order[-2]]:
        return None
    return k if sum(label == labels[k] for label in labels) > 1 else None


def limits_of_units(recordings: Sequence[Sequence[Unit]], span_factor: float, pause_factor: float,
                    labels: Sequence[str] | None = None, min_pause: float = 0.5,
                    ) -> tuple[int, float, float, float]:
    """:func:`candidate_limits` from the movement units of each model recording (one list per
    recording, of one tracker or of several trackers' combined motion). With ``labels``, the
    recording :func:`odd_rest_take` names is left out: one take holding its way back would
    otherwise let every gesture pause, span and last as long as that take."""
    odd = None if labels is None else odd_rest_take(longest_gaps(recordings), labels, min_pause)
    most, longest, pause, ratio = 1, 0.0, 0.0, 0.0
    for units in (r for k, r in enumerate(recordings) if k != odd):
        if not units:
            continue
        most = max(most, len(units))
        longest = max(longest, units[-1].end_t - units[0].start_t)
        for a, b in itertools.pairwise(units):
            gap = b.start_t - a.end_t
            pause = max(pause, gap)
            ratio = max(ratio, gap / (0.5 * (a.end_t - a.start_t + b.end_t - b.start_t)))
    if longest == 0.0:
        raise ValueError("no movement found in the model recordings")
    return 2 * most + 1, span_factor * longest, span_factor * pause, pause_factor * ratio


def longest_corner_rest(traj: Trajectory, levels: SpeedLevels, L: float, dt: float = 0.02,
                        corner_angle: float = 60.0) -> float | None:
    """The longest rest [s] at a corner of a recording's gesture
    (:func:`~framefree.online.span_shape.corner_rest` of its movement units, as the live
    segmenter cuts them; 0 without a corner); ``None`` if it has no movement unit."""
    _, units = recording_units(traj, levels, L, dt)
    if not units:
        return None
    return corner_rest(units, corner_angle)


def one_go_gestures(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    pause: float, dt: float = 0.02, corner_angle: float = 60.0,
) -> list[str]:
    """The gestures drawn in one go: those whose recordings typically (the median of their
    :func:`longest_corner_rest`) rest at a corner for less than ``pause`` seconds.

    A gesture that pauses at a corner, as at the reversal of an out-and-back move, keeps the
    pause limits common to all gestures (:func:`candidate_limits`: how long the demonstrator
    pauses, whichever gesture, stretched for slower people). One drawn in one go, as a Z drawn
    without stopping at its corners, admits at a corner only the rest every candidate is allowed
    (``min_pause``): a reposition, a rest and two sides of a triangle are then no Z, while a
    hesitation in mid-stroke, where the hand goes on the same way, is no corner and is not
    limited. A gesture with no movement unit is left out.
    """
    longest: dict[str, list[float]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        rest = longest_corner_rest(tr, levels, L, dt, corner_angle)
        if rest is not None:
            longest.setdefault(g, []).append(rest)
    return [g for g, v in longest.items() if float(np.median(v)) < pause]


def corner_limit(counts: Sequence[int], slack: int = 1, smooth: int | None = None) -> int | None:
    """Most corners accepted for a gesture whose recordings have ``counts`` corners: their common
    number plus ``slack`` when at least two recordings all agree, else ``None`` (no limit). With
    ``smooth``, only a gesture of at most ``smooth`` corners gets the slack.

    A square's corners are part of its shape, and every take has them; a smooth curve of varying
    bend (a wave) slows down, and may count a corner, where it bends most, in some takes and not
    in others: there the number says nothing about another person's performance. Even where one
    person's takes agree, another person may break a stroke where they did not: on the six real
    people of ``machete_vive`` (both controllers, every gesture), limits from one person's
    agreeing takes were exceeded by 11.0 % of the other people's performances with no slack and
    by 1.6 % with a slack of one. Every one of them was a gesture of no corner or one (a swing,
    an out-and-back move that another person hooks): where one person's takes agreed on two or
    more corners, no other person's performance had more (0 of 475), so a drawn polygon or a Z
    needs no slack (``smooth`` = 1, v15)."""
    if len(counts) < 2 or len(set(counts)) > 1:
        return None
    agreed = int(counts[0])
    return agreed + (int(slack) if smooth is None or agreed <= smooth else 0)


def forbidden_turns(kinds: Sequence[int]) -> int:
    """The :func:`~framefree.online.span_shape.turn_kinds` a gesture never makes, from the turn
    kinds of its recordings: when at least two recordings all turn one way only (every pair of
    corners the same way, or every pair back), the other way; else none (0).

    Which way a shape turns is part of it, as its corners are: a triangle or a square never
    turns back, a Z always does, and the three are told apart by it whatever their sizes and
    however loose the threshold. A gesture whose recordings mix both, or have fewer than two
    corners, is not limited."""
    if len(kinds) < 2 or len(set(kinds)) > 1:
        return 0
    return {SAME_SENSE: ALTERNATING, ALTERNATING: SAME_SENSE}.get(int(kinds[0]), 0)


def closure_limit(largest: float, exponent: float = 0.5) -> float:
    """Closure limit of a gesture whose demonstrations close up to ``largest``: ``largest **
    exponent`` — with 0.5 the geometric midpoint between them and a one-way motion (closure 1)."""
    return float(max(largest, 1e-6) ** exponent)


def opening_limit(smallest: float, exponent: float = 0.5) -> float:
    """Smallest closure accepted for a gesture whose demonstrations close at least ``smallest``:
    ``smallest ** (1 / exponent)``, the mirror of :func:`closure_limit` — on a log scale as far
    below the demonstrations as the closure limit lies above them. Negligible for a gesture that
    returns; for an open stroke (a Z, an L) it keeps out shapes that come back to their start."""
    return float(min(max(smallest, 0.0), 1.0) ** (1.0 / exponent))


def pooled_closures(largest: dict[str, float]) -> dict[str, float]:
    """Largest closure per gesture, pooled over the gestures that return.

    A gesture *returns* when its demonstrations close up to less than ½ (nearer a motion back to
    the start than a one-way motion). Every returning gesture gets the largest closure of any
    returning gesture; a one-way gesture keeps its own.
    """
    returning = [v for v in largest.values() if v < 0.5]
    pooled = max(returning, default=0.0)
    return {g: (pooled if v < 0.5 else v) for g, v in largest.items()}
