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
  above: a segment that far from ``g`` may as well be the other gesture. A recording that moves
  outside ``g``'s cone of hand directions (``hand_frame``) counts as the cone's factor farther
  from ``g``, as the live spotter counts it (:mod:`framefree.online.hand_direction`; so does
  one that turns the hand about an axis outside ``g``'s cone of axes). Nothing
  else here sees the cones. With
  ``rival_quantile`` > 0 the bound is that quantile, over the other gestures' recordings, of
  each one's distance to its nearest recording of ``g``, so that one stray pair does not set it.

Generic motion also includes random shapes drawn in the air (``drawn``,
:mod:`framefree.online.scribbles`), so that a threshold also meets shapes nobody enrolled.
``N_g`` is the smaller of the two.

**Rule.** Distances are scale-like, so the threshold is placed on a log scale between them:
``τ_g = P_g^(1-a) · N_g^a`` with ``a = position`` (the recognizer's default 0.7 leans towards the
negatives: another person's performance lies farther from the models than one person's
demonstrations lie from each other, so τ_g goes into the gap between the two). When
``P_g ≥ N_g`` the gesture is reported as not separated: there is no gap to lean into, takes
lie beyond some negatives, and ``a = unseparated_position`` (the recognizer's default 0.5, the
geometric midpoint, favouring neither error). If no negative is finite, ``τ_g = 2 P_g``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..core.trajectory import Trajectory
from .hand_direction import farther, hand_turn
from .limits import recording_direction, recording_units
from .negatives import non_gesture_motions
from .proportions import proportions
from .segment_classifier import SegmentClassifier
from .segmentation import SpeedLevels
from .span_shape import closure, corner_count, corner_rest, turn_kinds
from .spotting import Spotter, candidate_spans

__all__ = [
    "ONE_TAKE_SIZE",
    "SegmentScores",
    "SegmentThresholds",
    "calibrate_segment_thresholds",
    "reach_down",
    "segment_distances",
    "take_scores",
    "unseen_gestures",
    "worst_take",
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
                    "other gesture's recording; a: threshold_position where P_g < N_g, "
                    "unseparated_position where not)",
            "thresholds": dict(self.thresholds),
            "positives_max": {g: worst_take(v) for g, v in self.positives.items()},
            "negatives_quantile": dict(self.negatives),
            "separated": dict(self.separated),
            "smallest_sizes": dict(self.smallest_sizes),
        }


def worst_take(scores: Sequence[float]) -> float | None:
    """``P_g``: the largest finite leave-one-out score (a take none of whose candidates is
    admitted scores infinity and takes no part); ``None`` where no take has a finite one."""
    finite = [float(s) for s in scores if np.isfinite(s)]
    return max(finite) if finite else None


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
    """(C,): :func:`~framefree.online.span_shape.turn_kinds` bits."""
    pauses: np.ndarray
    """(C,) [s]: the longest rest at a corner (:func:`~framefree.online.span_shape.corner_rest`),
    which the spotter's one-go limit judges."""
    proportions: list[np.ndarray] | None = None
    """(C,) of (K,): each candidate's :func:`~framefree.online.proportions.proportions`, which
    the spotter's proportion limits judge (None: not measured, no limit applies)."""


def segment_distances(
    traj: Trajectory,
    classifier: SegmentClassifier,
    levels: SpeedLevels,
    spotter: Spotter,
    L: float,
    dt: float = 0.02,
) -> SegmentScores:
    """Distances (C, M) of every candidate segment of a recording to every model, and the closure,
    size [m], corners, turn kinds, longest rest at a corner [s] and proportions (C,) of each
    candidate.

    The recording is resampled on the uniform grid, cut by :class:`MotionSegmenter` and its
    candidates formed with the limits of ``spotter`` (no threshold is applied).
    """
    seg, units = recording_units(traj, levels, L, dt)
    rows: list[np.ndarray] = []
    closures: list[float] = []
    sizes: list[float] = []
    corners: list[int] = []
    turns: list[int] = []
    pauses: list[float] = []
    shares: list[np.ndarray] = []
    for k in range(len(units)):
        for first, n in candidate_spans(units[: k + 1], spotter.max_units, spotter.max_duration,
                                        spotter.max_pause, -1, spotter.pause_ratio,
                                        spotter.min_pause):
            i = k + 1 - n
            if i > 0 and not spotter.may_start_after(first.start_t - units[i - 1].end_t):
                continue  # starts in the middle of a motion, as the spotter would not take it
            t, P = seg.buffer.slice(first.start - spotter.margin, units[k].end + spotter.margin)
            d, size = classifier.distances(t, P)
            rows.append(d)
            sizes.append(size)
            closures.append(closure(P[spotter.margin:P.shape[0] - spotter.margin], L))
            corners.append(corner_count(units[i:k + 1], spotter.corner_angle))
            turns.append(turn_kinds(units[i:k + 1], spotter.corner_angle))
            pauses.append(corner_rest(units[i:k + 1], spotter.corner_angle))
            shares.append(proportions(units[i:k + 1], spotter.corner_angle))
    if not rows:
        empty = np.zeros(0)
        return SegmentScores(np.full((0, len(classifier.models)), np.inf), empty, empty, empty,
                             np.zeros(0, dtype=np.int64), empty, [])
    return SegmentScores(np.vstack(rows), np.array(closures), np.array(sizes), np.array(corners),
                         np.array(turns, dtype=np.int64), np.array(pauses), shares)


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
    for D, c, size, corners, turns, pauses, shares in records:
        band = (size >= floor) & (size < lo)
        if not band.any():
            continue
        shaped = spotter.admissible(model, c[band], np.full(int(band.sum()), lo), corners[band],
                                    turns[band], pauses=pauses[band],
                                    shares=_selected(shares, band))
        if shaped.any() and float(D[band][shaped][:, own].min()) < threshold:
            return None
    return floor


def _selected(values: list[np.ndarray] | None, mask: np.ndarray) -> list[np.ndarray] | None:
    """The entries of ``values`` (C,) where ``mask`` (C,) is True (None stays None)."""
    return None if values is None else [v for v, m in zip(values, mask, strict=True) if m]


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


def unseen_gestures(positives: dict[str, list[float]], fraction: float = 0.5) -> list[str]:
    """The gestures the tracker does not follow: at most ``fraction`` of their takes have a
    finite leave-one-out score (``positives``, :func:`take_scores`), i.e. no more than that
    share of their takes gives the spotter a candidate it admits as themselves.

    A gesture another limb performs is such a gesture: the hand holding the tracker barely moves
    in its takes, so their motion is no shape (real Machete sessions, one controller: the right
    controller's *hook left* has 7 findable takes of 25, every gesture its hand performs all 25).
    Its threshold would rest on the few takes that happen to move, and idle motion of the hand
    would fire it; the recognizer keeps its models, so motion nearest them is refused rather
    than given to another gesture, but never fires it. With ``fraction`` 0 only a gesture none
    of whose takes can be found is not followed.
    """
    out = []
    for g, scores in positives.items():
        found = np.isfinite(np.asarray(scores, dtype=float))
        if found.size and found.mean() <= fraction:
            out.append(g)
    return out


def take_scores(
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
    for r, tr in enumerate(_bar(trajectories, "calibrating: the takes", "take")):
        same = labels_arr == labels[r]
        same[r] = False
        if not same.any():  # a single demonstration: another person's, larger and smaller
            same[r] = True
            copies = [tr.path_scaled(k) for k in (1 / ONE_TAKE_SIZE, ONE_TAKE_SIZE)]
        else:
            copies = [tr]
        for copy in copies:
            D, c, size, corners, turns, pauses, shares = segment_distances(
                copy, classifier, levels, spotter, L)
            ok = spotter.admissible(r, c, size, corners, turns, pauses=pauses, shares=shares)
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
    unseparated_position: float | None = None,
    rival_quantile: float = 0.0,
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
    unseparated_position : float or None
        ``a`` for a gesture that is not separated (``P_g ≥ N_g``); ``None``: ``position``.
    seed : int
        Seed of the generated non-gesture motion (the calibration is deterministic).
    gated : bool
        Count an episode none of whose candidates passes ``g``'s closure and size limits as
        infinitely far from ``g`` (True), or leave it out of ``g``'s quantile (False).
    rivals : bool
        Also count the other gestures' recordings as negatives: ``N_g`` is at most the distance
        between the nearest pair of a recording of ``g`` and a recording of another gesture.
    rival_quantile : float
        With ``rivals``: ``N_g`` is at most this quantile, over the other gestures' recordings,
        of each one's distance to its nearest recording of ``g`` (0: their minimum, the nearest
        pair). The nearest pair falls as takes are added; a low quantile lets one stray pair
        go (docs/online-history.md, *Session 27: one sensor that performs every gesture*).
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
    first = {g: int(np.flatnonzero(labels_arr == g)[0]) for g in gestures}
    positives = take_scores(trajectories, labels, classifier, levels, spotter, L)
    reaching = reach > 1.0
    episodes, records = _episode_scores(trajectories, labels, classifier, levels, spotter, L,
                                        seed, gated, drawn, reaching)
    thresholds, separated, negatives = {}, {}, {}
    between = (classifier.descriptor.distance_matrix(classifier.models, classifier.models)
               if rivals else None)
    ways = ([recording_direction(tr, levels, L) for tr in trajectories]
            if rivals and spotter.directions.active else [None] * len(labels))
    axes = ([recording_direction(tr, levels, L, measure=hand_turn) for tr in trajectories]
            if rivals and spotter.rotations.active else [None] * len(labels))
    for g in gestures:
        worst = worst_take(positives[g])
        P = np.inf if worst is None else worst
        N = _quantile(episodes[g], negative_quantile)
        own = labels_arr == g
        if between is not None and (~own).any():
            # per take of another gesture; one that moves outside g's cone counts farther, as the
            # live spotter counts it
            factors = np.array([max(spotter.directions.factors(w)[first[g]],
                                    spotter.rotations.factors(a)[first[g]])
                                for w, a, mine in zip(ways, axes, own, strict=True) if not mine])
            nearest_of_g = farther(between[np.ix_(own, ~own)].min(axis=0), factors)
            N = min(N, _rival_bound(nearest_of_g, rival_quantile))
        negatives[g] = N
        separated[g] = bool(P < N)
        a = position if separated[g] or unseparated_position is None else unseparated_position
        thresholds[g] = _between(g, P, N, a)
    smallest = {}
    for g in gestures if reaching else ():
        floor = reach_down(records, labels_arr == g, first[g], thresholds[g], spotter, reach)
        if floor is not None:
            smallest[g] = floor
    return SegmentThresholds(thresholds, positives, negatives, separated, smallest)


def _rival_bound(nearest: np.ndarray, quantile: float) -> float:
    """The ``quantile`` of the other gestures' takes' distances to their nearest take of a
    gesture (weighed by its cones); those outside a cone of a fixed frame lie at infinity and
    bound nothing, so a quantile that reaches them is taken without interpolating."""
    if np.isfinite(nearest).all():
        return float(np.quantile(nearest, quantile))
    return float(np.quantile(nearest, quantile, method="inverted_cdf"))


def _episode_scores(
    trajectories: Sequence[Trajectory],
    labels: Sequence[str],
    classifier: SegmentClassifier,
    levels: SpeedLevels,
    spotter: Spotter,
    L: float,
    seed: int,
    gated: bool,
    drawn: bool,
    regrips: bool,
) -> tuple[dict[str, list[float]], list[SegmentScores]]:
    """The generic non-gesture episodes' scores per gesture (the best distance to its models of
    the candidates that pass its limits; ``inf`` where none does and ``gated``), and every
    episode's candidates (re-grips included when ``regrips``) for :func:`reach_down`."""
    labels_arr = np.asarray(labels)
    gestures = list(dict.fromkeys(labels))
    first = {g: int(np.flatnonzero(labels_arr == g)[0]) for g in gestures}
    episodes: dict[str, list[float]] = {g: [] for g in gestures}
    records: list[SegmentScores] = []
    kinds = ("rest", "moves", "drawn") if drawn else ("rest", "moves")
    motions = non_gesture_motions(trajectories, labels, L, seed=seed,
                                  kinds=(*kinds, "regrip") if regrips else kinds)
    for kind, neg in _bar(motions, "calibrating: other motion", "episode"):
        scores = segment_distances(neg, classifier, levels, spotter, L)
        D, c, size, corners, turns, pauses, shares = scores
        if regrips:
            records.append(scores)
        if kind == "regrip":
            continue
        for g in gestures:
            ok = spotter.admissible(first[g], c, size, corners, turns, pauses=pauses,
                                    shares=shares)
            if ok.any():
                episodes[g].append(float(D[ok][:, labels_arr == g].min()))
            elif gated:
                episodes[g].append(np.inf)
    return episodes, records


def _bar(items: Sequence, desc: str, unit: str) -> Iterable:
    """``items`` with a progress bar on a terminal, shown once the loop has run a second (a few
    hundred takes calibrate for minutes), none elsewhere."""
    from tqdm import tqdm

    return tqdm(items, desc=desc, unit=unit, leave=False, disable=None, delay=1.0)


def _between(gesture: str, P: float, N: float, a: float) -> float:
    """τ at ``a`` of the way from the worst take ``P`` to the negatives ``N`` on a log scale;
    twice ``P`` when no negative is finite, half ``N`` when no take is."""
    if np.isfinite(P) and np.isfinite(N):
        return float(P ** (1.0 - a) * N**a)
    if np.isfinite(P):  # nothing generic comes close to this gesture
        return 2.0 * P
    if np.isfinite(N):
        return 0.5 * N
    raise ValueError(f"cannot calibrate gesture {gesture!r}: no positive and no negative score")
