"""Stroke spotting: every span between two boundaries is a candidate, classified as offline.

When a boundary becomes known (:class:`~framefree.online.valleys.Valleys`), the candidates that
end at it are the spans from each earlier boundary, as long as the span lasts between
``min_duration`` and ``max_duration`` seconds and begins after the last event. A span whose
smoothed path fits no gesture's size range is dropped unclassified; the others are cut out of
the pose buffer with a short margin and classified exactly as the offline 1-NN classifier
classifies a recording (:class:`~framefree.online.spotting.SegmentClassifier`).

A candidate is **accepted** when its nearest model (among the gestures whose size range holds the
candidate's size and whose slowest take its peak speed reaches, over ``tempo_factor``) is nearer
than that model's gesture threshold τ_g; its *ratio* is distance / τ_g. Acceptance is all the recognizer decides from the candidate; no rest, closure or
corner rule is applied.

The **decision**: the best accepted candidate is held pending; an accepted candidate that
overlaps it with a lower ratio replaces it (a whole gesture wins over a part of it, a well-cut
span over a badly cut one). It fires once the next stroke after it has ended and been tried as
its continuation (at least ``wait`` seconds after the boundary that ended it became known), or
``max_pause`` seconds after its end if the hand does not move on; candidates that begin before
its end are not considered again.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from .segmentation import PoseBuffer
from .spotting import SegmentClassifier
from .valleys import Valleys

__all__ = ["StrokeCandidate", "StrokeSpotter"]


@dataclass(frozen=True)
class StrokeCandidate:
    """An accepted candidate: running indices and times of its first and last pose, nearest model,
    its distance, ``distance / τ`` and its size [m]; ``fire_at`` [s] is when it fires unless a
    better overlapping candidate replaces it."""

    start: int
    end: int
    start_t: float
    end_t: float
    model: int
    distance: float
    ratio: float
    size: float
    fire_at: float


class StrokeSpotter:
    """Candidates between boundaries, their classification and the decision.

    Parameters
    ----------
    classifier : SegmentClassifier
        The models and the offline descriptor.
    model_thresholds : ndarray, shape (M,)
        τ of each model's gesture.
    size_ranges : ndarray, shape (M, 2)
        Smallest and largest size [m] of each model's gesture.
    min_speeds : ndarray, shape (M,)
        Lowest peak speed [m/s] of a performance of each model's gesture.
    min_duration, max_duration : float
        Shortest and longest candidate [s].
    wait : float
        Seconds a pending candidate waits for a better one after its end became known.
    max_pause : float
        Longest pause [s] inside a gesture: a pending candidate also waits until the next stroke
        after it has ended (it may be the rest of a longer gesture), but no longer than this after
        its end.
    margin : int
        Grid samples added on each side of a candidate before it is described.
    """

    def __init__(self, classifier: SegmentClassifier, model_thresholds: np.ndarray,
                 size_ranges: np.ndarray, min_speeds: np.ndarray, min_duration: float,
                 max_duration: float, wait: float, max_pause: float, margin: int = 5) -> None:
        self.classifier = classifier
        self.tau = np.asarray(model_thresholds, dtype=float)
        self.size_ranges = np.asarray(size_ranges, dtype=float).reshape(-1, 2)
        self.min_duration, self.max_duration = float(min_duration), float(max_duration)
        self.wait = float(wait)
        self.max_pause = float(max_pause)
        self.margin = int(margin)
        self.min_speeds = np.asarray(min_speeds, dtype=float)
        self._path_lo = float(self.size_ranges[:, 0].min()) / 2.0
        self._speed_lo = float(self.min_speeds.min())
        self._boundaries: deque[tuple[int, float, float]] = deque(maxlen=256)
        #: (end time [s], distances (M,)) of every candidate classified during the latest call
        self.evaluated: list[tuple[float, np.ndarray]] = []
        self.last_distances: np.ndarray | None = None
        self.reset()

    def reset(self) -> None:
        """Forget the boundaries and the pending candidate (a new stream or a restart)."""
        self._boundaries.clear()
        self.pending: StrokeCandidate | None = None
        self.queued: StrokeCandidate | None = None  # accepted after the pending one's end
        self.extended = False  # a stroke after the pending candidate ended and was tried
        self.after = -1

    def discard_before(self, index: int) -> None:
        """Nothing up to running index ``index`` may become a gesture (a stop fired there)."""
        self.pending = self.queued = None
        self.after = max(self.after, index)

    def boundary(self, index: int, path: float, valleys: Valleys, now: float) -> None:
        """A boundary at running ``index`` (smoothed path ``path`` [m]) of ``valleys`` became
        known at ``now``."""
        buffer = valleys.buffer
        t_end = buffer.time(index)
        for start, start_t, start_path in reversed(self._boundaries):
            span = t_end - start_t
            if start <= self.after or span > self.max_duration:
                break
            if span < self.min_duration or path - start_path < self._path_lo:
                continue
            peak = valleys.peak_speed(start, index)
            if peak < self._speed_lo:
                continue
            self._consider(self._classify(start, index, buffer, peak, now))
        p = self.pending
        if p is not None and index > p.end and valleys.peak_speed(p.end, index) >= self._speed_lo:
            self.extended = True
        self._boundaries.append((index, t_end, path))

    def _classify(self, start: int, end: int, buffer: PoseBuffer, peak: float, now: float
                  ) -> StrokeCandidate | None:
        times, poses = buffer.slice(start - self.margin, end + self.margin)
        described = self.classifier.describe(times, poses)
        if described is None:
            return None
        descriptor, size = described
        fits = ((self.size_ranges[:, 0] <= size) & (size <= self.size_ranges[:, 1])
                & (peak >= self.min_speeds))
        accept_below = np.where(fits, self.tau, 0.0)
        if self.classifier.pruning:
            d = self.classifier.search_described(descriptor, accept_below)
        else:
            d = self.classifier.descriptor.distance_matrix([descriptor], self.classifier.models)[0]
        self.evaluated.append((buffer.time(end), d))
        self.last_distances = d
        nearest = np.where(fits, d, math.inf)
        j = int(np.argmin(nearest))  # the offline 1-NN label, among the gestures of this size
        if not nearest[j] < self.tau[j]:
            return None
        return StrokeCandidate(start, end, buffer.time(start), buffer.time(end), j, float(d[j]),
                               float(d[j] / self.tau[j]), float(size), now + self.wait)

    def _consider(self, cand: StrokeCandidate | None) -> None:
        if cand is None:
            return
        p = self.pending
        if p is None or (cand.start < p.end and cand.ratio < p.ratio):
            self.pending, self.extended = cand, False
        elif cand.start >= p.end:  # a next gesture already: the pending one fires now
            self.pending = StrokeCandidate(**{**p.__dict__, "fire_at": -math.inf})
            if self.queued is None or cand.ratio < self.queued.ratio:
                self.queued = cand

    def poll(self, now: float) -> StrokeCandidate | None:
        """The pending candidate if its time has come (it is then no longer pending)."""
        p = self.pending
        if p is None or now < p.fire_at:
            return None
        if not self.extended and now < p.end_t + self.max_pause:
            return None
        self.pending, self.queued, self.extended = self.queued, None, False
        self.after = p.end
        return p
