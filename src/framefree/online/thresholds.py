"""Per-gesture rejection thresholds of the segment recognizer, from the model recordings alone.

**Positives.** Each model recording is cut into movement units by the live segmenter and every
candidate segment of it is classified against the *other* recordings of its gesture
(leave-one-out); its score is the best such distance. ``P_g`` is the largest score of gesture
``g``'s recordings: every demonstration must be recognized when it is left out.

**Negatives.** Two kinds:

* *generic motion* that is no gesture, built around every recording's start and end pose with the
  recording's own sensor noise (:func:`framefree.online.negatives.non_gesture_motions`):
  holding still, and unhurried via-point moves (repositioning, reaching). Each episode's score for
  ``g`` is the best distance to the models of ``g`` among its candidates that pass ``g``'s closure
  and size limits; an episode none of whose candidates passes them cannot be taken for ``g`` and
  scores infinity (*gated*). Their ``negative_quantile`` (5 %) quantile is the generic part;
* *rivals*: the other gestures. The distance (the classifier's, between whole recordings) of the
  nearest pair of a recording of ``g`` and a recording of another gesture bounds ``N_g`` from
  above: a segment that far from ``g`` may as well be the other gesture.

Generic motion also includes random shapes drawn in the air (``drawn``,
:mod:`framefree.online.scribbles`), so that a threshold also meets shapes nobody enrolled.
``N_g`` is the smaller of the two.

**Rule.** Distances are scale-like, so the threshold is placed on a log scale between them:
``τ_g = P_g^(1-a) · N_g^a`` with ``a = position`` (the recognizer's default 0.7 leans towards the
negatives: another person's performance lies farther from the models than one person's
demonstrations lie from each other). When ``P_g ≥ N_g`` the gesture is reported as not separated.
If no negative is finite, ``τ_g = 2 P_g``.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..core.trajectory import Trajectory
from .negatives import non_gesture_motions
from .segmentation import (
    ALTERNATING,
    SAME_SENSE,
    MotionSegmenter,
    SpeedLevels,
    Unit,
    closure,
    corner_count,
    corner_rest,
    turn_kinds,
)
from .spotting import SegmentClassifier, Spotter, candidate_spans
from .vertical import verticality

__all__ = [
    "SegmentScores",
    "SegmentThresholds",
    "calibrate_segment_thresholds",
    "candidate_limits",
    "closure_limit",
    "corner_limit",
    "forbidden_turns",
    "gesture_geometry",
    "gesture_pause_limits",
    "gesture_verticality",
    "longest_corner_rest",
    "opening_limit",
    "pooled_closures",
    "reach_down",
    "recording_geometry",
    "segment_distances",
    "size_limits",
]


@dataclass(frozen=True)
class SegmentThresholds:
    """Result of the calibration.

    Attributes
    ----------
    thresholds : dict of str to float
        τ_g per gesture.
    positives : dict of str to list of float
        Leave-one-out scores of each gesture's recordings.
    negatives : dict of str to float
        ``N_g``: the low quantile of the non-gesture episodes' distances to the models of ``g``.
    separated : dict of str to bool
        ``P_g < N_g``.
    smallest_sizes : dict of str to float
        Lower size limit [m] of each gesture whose range may reach further down (see
        :func:`reach_down`); gestures that keep theirs are not listed.
    """

    thresholds: dict[str, float]
    positives: dict[str, list[float]]
    negatives: dict[str, float]
    separated: dict[str, bool] = field(default_factory=dict)
    smallest_sizes: dict[str, float] = field(default_factory=dict)

    def summary(self) -> dict:
        """JSON-friendly summary."""
        return {
            "rule": "tau_g = P_g^(1-a) * N_g^a (P_g: worst leave-one-out demonstration, N_g: the "
                    "smaller of the 5 % quantile of generic non-gesture episodes and the nearest "
                    "other gesture's recording)",
            "thresholds": dict(self.thresholds),
            "positives_max": {g: float(max(v)) for g, v in self.positives.items()},
            "negatives_quantile": dict(self.negatives),
            "separated": dict(self.separated),
            "smallest_sizes": dict(self.smallest_sizes),
        }


def _units(traj: Trajectory, levels: SpeedLevels, L: float, dt: float
           ) -> tuple[MotionSegmenter, list[Unit]]:
    seg = MotionSegmenter(levels, L, dt, capacity=max(16, int(traj.duration / dt) + 8))
    times, poses = traj.uniform_poses(dt)
    units = [u for k in range(times.size) if (u := seg.push(float(times[k]), poses[k])) is not None]
    return seg, units


class SegmentScores(NamedTuple):
    """Every candidate segment of a recording (:func:`segment_distances`)."""

    distances: np.ndarray
    """(C, M): to every model."""
    closures: np.ndarray
    """(C,)"""
    sizes: np.ndarray
    """(C,) [m]"""
    corners: np.ndarray
    """(C,)"""
    turns: np.ndarray
    """(C,): :func:`~framefree.online.segmentation.turn_kinds` bits."""


def segment_distances(
    traj: Trajectory,
    classifier: SegmentClassifier,
    levels: SpeedLevels,
    spotter: Spotter,
    L: float,
    dt: float = 0.02,
) -> SegmentScores:
    """Distances (C, M) of every candidate segment of a recording to every model, and the closure,
    size [m], corners and turn kinds (C,) of each candidate.

    The recording is resampled on the uniform grid, cut by :class:`MotionSegmenter` and its
    candidates formed with the limits of ``spotter`` (no threshold is applied).
    """
    seg, units = _units(traj, levels, L, dt)
    rows: list[np.ndarray] = []
    closures: list[float] = []
    sizes: list[float] = []
    corners: list[int] = []
    turns: list[int] = []
    for k in range(len(units)):
        for first, n in candidate_spans(units[: k + 1], spotter.max_units, spotter.max_duration,
                                        spotter.max_pause, -1, spotter.pause_ratio,
                                        spotter.min_pause):
            i = k + 1 - n
            if i > 0 and first.start_t - units[i - 1].end_t < spotter.rest_before:
                continue  # starts in the middle of a motion, as the spotter would not take it
            t, P = seg.buffer.slice(first.start - spotter.margin, units[k].end + spotter.margin)
            d, size = classifier.distances(t, P)
            rows.append(d)
            sizes.append(size)
            closures.append(closure(P[spotter.margin:P.shape[0] - spotter.margin], L))
            corners.append(corner_count(units[i:k + 1], spotter.corner_angle))
            turns.append(turn_kinds(units[i:k + 1], spotter.corner_angle))
    if not rows:
        empty = np.zeros(0)
        return SegmentScores(np.full((0, len(classifier.models)), np.inf), empty, empty, empty,
                             np.zeros(0, dtype=np.int64))
    return SegmentScores(np.vstack(rows), np.array(closures), np.array(sizes), np.array(corners),
                         np.array(turns, dtype=np.int64))


def recording_geometry(
    traj: Trajectory, classifier: SegmentClassifier, levels: SpeedLevels, L: float,
    margin: int = 5, dt: float = 0.02, corner_angle: float = 60.0,
) -> tuple[float, float, int, int] | None:
    """Closure, size [m], corners and turn kinds of one recording's gesture, measured on the
    whole gesture (first unit's start to last unit's end; the size with ``margin`` samples around
    it, as a live candidate is cut), corners and turns as in
    :func:`~framefree.online.segmentation.corner_count` and
    :func:`~framefree.online.segmentation.turn_kinds`; ``None`` if the recording has no movement
    unit."""
    seg, units = _units(traj, levels, L, dt)
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
    """:func:`~framefree.online.vertical.verticality` of each gesture's recordings, measured on
    the whole gesture (first unit's start to last unit's end) as :func:`recording_geometry`
    measures the rest: ``{g: [verticality of each recording]}`` (a recording without a movement
    unit is left out)."""
    out: dict[str, list[float]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        seg, units = _units(tr, levels, L, dt)
        if units:
            _, P = seg.buffer.slice(units[0].start, units[-1].end)
            out.setdefault(g, []).append(verticality(P, up))
    return out


def size_limits(smallest: float, largest: float, factor: float, growth: float | None = None
                ) -> tuple[float, float]:
    """Sizes accepted for a gesture whose demonstrations span ``[smallest, largest]`` [m]: people
    make the same gesture smaller by up to ``factor`` and larger by up to ``growth`` (``None``:
    ``factor``)."""
    return smallest / factor, largest * (factor if growth is None else growth)


def candidate_limits(
    trajectories: Sequence[Trajectory], levels: SpeedLevels, L: float, span_factor: float,
    pause_factor: float, dt: float = 0.02,
) -> tuple[int, float, float, float]:
    """Candidate limits from the model recordings: ``(max_units, max_duration, max_pause,
    pause_ratio)``.

    Twice the most units of any recording plus one (a hesitation may cut every stroke in two, and
    one unit more); ``span_factor`` × the longest gesture (first
    unit's start to last unit's end); ``span_factor`` × the longest rest between two units of one
    recording [s]; ``pause_factor`` × the largest ratio of such a rest to the mean duration of the
    two units around it.
    """
    most, longest, pause, ratio = 1, 0.0, 0.0, 0.0
    for tr in trajectories:
        _, units = _units(tr, levels, L, dt)
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
    (:func:`~framefree.online.segmentation.corner_rest` of its movement units, as the live
    segmenter cuts them; 0 without a corner); ``None`` if it has no movement unit."""
    _, units = _units(traj, levels, L, dt)
    if not units:
        return None
    return corner_rest(units, corner_angle)


def gesture_pause_limits(
    trajectories: Sequence[Trajectory], labels: Sequence[str], levels: SpeedLevels, L: float,
    max_pause: float, pause_ratio: float, pause: float, dt: float = 0.02,
    corner_angle: float = 60.0,
) -> dict[str, tuple[float, float]]:
    """Which gestures pause at their corners, and the pause limits of each: ``{g: (max_pause,
    pause_ratio)}``.

    A gesture whose recordings typically (the median of their :func:`longest_corner_rest`) rest
    at a corner for ``pause`` seconds or more pauses, as at the reversal of an out-and-back
    move; it keeps the limits common to all gestures, ``max_pause`` [s] and ``pause_ratio``
    (:func:`candidate_limits`: how long the demonstrator pauses, whichever gesture, stretched for
    slower people). A gesture performed in one go, as a Z drawn without stopping at its
    corners, gets ``(0, 0)``: at a corner, only the rest every candidate is allowed
    (``min_pause``). A reposition, a rest and two sides of a triangle are then no Z, while a
    hesitation in mid-stroke, where the hand goes on the same way, is no corner and is not
    limited. A gesture with no movement unit is left out.
    """
    longest: dict[str, list[float]] = {}
    for tr, g in zip(trajectories, labels, strict=True):
        rest = longest_corner_rest(tr, levels, L, dt, corner_angle)
        if rest is not None:
            longest.setdefault(g, []).append(rest)
    return {g: (max_pause, pause_ratio) if float(np.median(v)) >= pause else (0.0, 0.0)
            for g, v in longest.items()}


def corner_limit(counts: Sequence[int], slack: int = 1) -> int | None:
    """Most corners accepted for a gesture whose recordings have ``counts`` corners: their common
    number plus ``slack`` when at least two recordings all agree, else ``None`` (no limit).

    A square's corners are part of its shape, and every take has them; a smooth curve of varying
    bend (a wave) slows down, and may count a corner, where it bends most, in some takes and not
    in others: there the number says nothing about another person's performance. Even where one
    person's takes agree, another person may break a stroke where they did not: on the six real
    people of ``machete_vive`` (both controllers, every gesture), limits from one person's
    agreeing takes were exceeded by 11.0 % of the other people's performances with no slack and
    by 1.6 % with a slack of one."""
    if len(counts) < 2 or len(set(counts)) > 1:
        return None
    return int(counts[0]) + int(slack)


def forbidden_turns(kinds: Sequence[int]) -> int:
    """The :func:`~framefree.online.segmentation.turn_kinds` a gesture never makes, from the turn
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


def reach_down(
    records: Sequence[SegmentScores],
    own: np.ndarray,
    model: int,
    threshold: float,
    spotter: Spotter,
    reach: float,
) -> float | None:
    """A lower size limit [m] further down, if nothing that is no gesture looks like the gesture
    at those sizes; ``None`` to keep the limit.

    The band below the gesture's lower size limit ``lo`` down to ``lo / reach`` is open when no
    candidate of the non-gesture episodes in it (``records``: per episode the scores of its
    candidates), with the gesture's closure, opening, corners and turns,
    lies below ``threshold`` from the gesture's models (``own``, (M,) bool). A circle drawn
    smaller than the demonstrations is still a circle; a forearm turned out and back by less is
    a re-grip.

    Parameters
    ----------
    model : int
        Index of one of the gesture's models (whose limits ``spotter`` holds).
    reach : float
        How much further down the limit may go (≥ 1).
    """
    lo = float(spotter.size_limits[model, 0])
    if not (reach > 1.0 and lo > 0.0):
        return None
    floor = lo / reach
    for D, c, size, corners, turns in records:
        band = (size >= floor) & (size < lo)
        if not band.any():
            continue
        shaped = spotter.admissible(model, c[band], np.full(int(band.sum()), lo), corners[band],
                                    turns[band])
        if shaped.any() and float(D[band][shaped][:, own].min()) < threshold:
            return None
    return floor


def _quantile(values: list[float], q: float) -> float:
    """The ``q`` quantile; with infinite values one of the values (no interpolation into inf)."""
    if not values:
        return np.inf
    method = "inverted_cdf" if np.isinf(values).any() else "linear"
    return float(np.quantile(values, q, method=method))


#: Size factor of the copies that stand in for other performances of a gesture demonstrated only
#: once: its hand path scaled by 1/1.3 and 1.3 (the wrist turning as far), the spread of gesture
#: size between people (docs/dataset.md, *People*) that ``framefree check`` also probes.
ONE_TAKE_SIZE = 1.3


def _positive_scores(
    trajectories: Sequence[Trajectory],
    labels: Sequence[str],
    classifier: SegmentClassifier,
    levels: SpeedLevels,
    spotter: Spotter,
    L: float,
) -> dict[str, list[float]]:
    """Leave-one-out score of every recording, per gesture: the best distance of its admissible
    candidates to the other recordings of its gesture (a single demonstration: of its copies
    scaled by ``1/ONE_TAKE_SIZE`` and ``ONE_TAKE_SIZE`` to itself)."""
    labels_arr = np.asarray(labels)
    positives: dict[str, list[float]] = {g: [] for g in dict.fromkeys(labels)}
    for r, tr in enumerate(trajectories):
        same = labels_arr == labels[r]
        same[r] = False
        if not same.any():  # a single demonstration: another person's, larger and smaller
            same[r] = True
            copies = [tr.path_scaled(k) for k in (1 / ONE_TAKE_SIZE, ONE_TAKE_SIZE)]
        else:
            copies = [tr]
        for copy in copies:
            D, c, size, corners, turns = segment_distances(copy, classifier, levels, spotter, L)
            ok = spotter.admissible(r, c, size, corners, turns)
            positives[labels[r]].append(float(D[ok][:, same].min()) if ok.any() else np.inf)
    return positives


def calibrate_segment_thresholds(
    trajectories: Sequence[Trajectory],
    labels: Sequence[str],
    classifier: SegmentClassifier,
    levels: SpeedLevels,
    spotter: Spotter,
    L: float,
    negative_quantile: float = 0.05,
    position: float = 0.5,
    seed: int = 0,
    gated: bool = True,
    rivals: bool = True,
    drawn: bool = True,
    reach: float = 1.0,
) -> SegmentThresholds:
    """τ_g for every gesture (see the module docstring).

    A gesture with a single demonstration has no leave-one-out distance: its ``P_g`` is the
    larger distance of two copies of it, its hand path scaled by ``1/ONE_TAKE_SIZE`` and
    ``ONE_TAKE_SIZE``, to the demonstration itself.

    Parameters
    ----------
    trajectories, labels
        The model recordings (the same as ``classifier.models``, in order) and their gestures.
    classifier, levels, spotter, L
        The live recognizer's stages, so the calibration cuts, classifies and admits candidates
        (closure and size limits of ``spotter``) as it will.
    negative_quantile : float
        ``N_g`` is this quantile of the non-gesture episodes' scores (0.05: one generic motion
        episode in twenty may come closer to ``g`` than ``N_g``; the minimum would hinge on the
        single most gesture-like of an arbitrary number of random episodes).
    position : float
        Where τ_g lies between ``P_g`` and ``N_g`` on a log scale: ``τ_g = P_g^(1-a) N_g^a``
        (0.5: the geometric midpoint).
    seed : int
        Seed of the generated non-gesture motion (the calibration is deterministic).
    gated : bool
        Count an episode none of whose candidates passes ``g``'s closure and size limits as
        infinitely far from ``g`` (True), or leave it out of ``g``'s quantile (False).
    rivals : bool
        Also count the other gestures' recordings as negatives: ``N_g`` is at most the distance
        between the nearest pair of a recording of ``g`` and a recording of another gesture.
    drawn : bool
        Also count random shapes drawn in the air (the ``drawn`` family of
        :func:`~framefree.online.negatives.non_gesture_motions`) among the generic episodes.
    reach : float
        How many times further down than ``spotter``'s lower size limit a gesture's size range
        may reach where no non-gesture episode (re-grips included) looks like it
        (:func:`reach_down`; 1: never).
        Re-grips take no part in ``N_g``: a forearm turned out and back is a re-grip with a
        return, told apart by its amount alone, which the size limits judge.
    """
    labels_arr = np.asarray(labels)
    gestures = list(dict.fromkeys(labels))
    admissible = spotter.admissible

    first = {g: int(np.flatnonzero(labels_arr == g)[0]) for g in gestures}
    positives = _positive_scores(trajectories, labels, classifier, levels, spotter, L)
    episodes: dict[str, list[float]] = {g: [] for g in gestures}
    kinds = ("rest", "moves", "drawn") if drawn else ("rest", "moves")
    records = []  # every episode's candidates, for the size reach
    reaching = reach > 1.0
    for kind, neg in non_gesture_motions(trajectories, labels, L, seed=seed,
                                         kinds=(*kinds, "regrip") if reaching else kinds):
        scores = segment_distances(neg, classifier, levels, spotter, L)
        D, c, size, corners, turns = scores
        if reaching:
            records.append(scores)
        if kind == "regrip":
            continue
        for g in gestures:
            ok = admissible(first[g], c, size, corners, turns)
            if ok.any():
                episodes[g].append(float(D[ok][:, labels_arr == g].min()))
            elif gated:
                episodes[g].append(np.inf)
    thresholds, separated, negatives = {}, {}, {}
    between = (classifier.descriptor.distance_matrix(classifier.models, classifier.models)
               if rivals else None)
    for g in gestures:
        finite = [p for p in positives[g] if np.isfinite(p)]
        P = max(finite) if finite else np.inf
        N = _quantile(episodes[g], negative_quantile)
        own = labels_arr == g
        if between is not None and (~own).any():
            N = min(N, float(between[np.ix_(own, ~own)].min()))
        negatives[g] = N
        separated[g] = bool(P < N)
        if np.isfinite(P) and np.isfinite(N):
            thresholds[g] = float(P ** (1.0 - position) * N**position)
        elif np.isfinite(P):  # nothing generic comes close to this gesture
            thresholds[g] = 2.0 * P
        elif np.isfinite(N):
            thresholds[g] = 0.5 * N
        else:
            raise ValueError(f"cannot calibrate gesture {g!r}: no positive and no negative score")
    smallest = {}
    for g in gestures if reaching else ():
        floor = reach_down(records, labels_arr == g, first[g], thresholds[g], spotter, reach)
        if floor is not None:
            smallest[g] = floor
    return SegmentThresholds(thresholds, positives, negatives, separated, smallest)
