"""Candidates of several trackers, classified exactly as the offline classifier classifies a
recording of several trackers.

A candidate segment of the combined movement units (:mod:`~framefree.online.multi_stream`) is
cut out of every tracker's grid poses, becomes a
:class:`~framefree.core.multitrajectory.MultiTrajectory`, and is compared with the models by the
fitted :class:`~framefree.classifier.NearestNeighborClassifier` itself
(:meth:`~framefree.classifier.NearestNeighborClassifier.distance_matrix`): the same comparison
(the canonical paths of the chosen invariance), the same DTW, the same nearest model. The
pending/fire decision is the single-tracker spotter's (:class:`~framefree.online.spotting.Spotter`);
only the candidates differ: they are accepted below their gesture's threshold and within its size
range (the summed path length of the trackers), as the closure, corner, turn and vertical rules
describe one tracker's path.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import Trajectory
from ..errors import DegenerateMotionError, TrajectoryError
from .segmentation import PoseBuffer
from .spotting import Candidate, Spotter, candidate_spans

__all__ = ["MultiSegmentClassifier", "MultiSpotter", "path_size"]


def path_size(sample: MultiTrajectory) -> float:
    """Size [m] of a multi-tracker motion: the path length of every tracker's position, summed."""
    return float(sum(np.linalg.norm(np.diff(tr.p, axis=0), axis=1).sum() for tr in sample.trackers))


class MultiSegmentClassifier:
    """Distances from a multi-tracker pose segment to every model, by the offline classifier.

    Parameters
    ----------
    classifier : NearestNeighborClassifier
        Fitted on the model recordings (:class:`~framefree.core.multitrajectory.MultiTrajectory`
        samples).
    names : sequence of str
        Tracker names of the models (a candidate gets the same).
    up : ndarray, shape (3,)
        The models' vertical (used by ``invariance="gravity"``).

    Attributes
    ----------
    models : list of ndarray
        The classifier's model descriptors (one per model; the spotter counts them).
    prune : bool
        Always False: every model's distance is computed (one DTW kernel call per candidate).
    cells : list of int
        Kept for the recognizer's statistics (no pruning: 0 and 0).
    """

    pruning = False

    def __init__(self, classifier: Any, names: Sequence[str], up: np.ndarray) -> None:
        self.classifier = classifier
        self.models = list(classifier.models_)
        self.names = tuple(names)
        self.up = np.asarray(up, dtype=np.float64)
        self.prune = False
        self.cells = [0, 0]

    def sample(self, times: np.ndarray, poses: np.ndarray) -> MultiTrajectory | None:
        """The segment (times (n,) [s], poses (n, n_trackers, 4, 4)) as a multi-tracker sample, or
        None if it is too short."""
        try:
            trackers = tuple(Trajectory.from_poses(times - times[0], poses[:, j], source="live segment")
                             for j in range(poses.shape[1]))
            return MultiTrajectory(trackers, self.names, self.up, "live segment")
        except TrajectoryError:
            return None

    def distances(self, times: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, float]:
        """Distance (M,) from the segment to every model (``inf`` when the segment defines no
        canonical frame, e.g. the trackers do not move) and its :func:`path_size` [m]."""
        inf = np.full(len(self.models), math.inf)
        s = self.sample(times, poses) if poses.shape[0] >= 5 else None
        if s is None:
            return inf, 0.0
        try:
            return self.classifier.distance_matrix([s])[0], path_size(s)
        except DegenerateMotionError:
            return inf, path_size(s)


class MultiSpotter(Spotter):
    """The spotter of several trackers: candidates of the combined units, classified by
    :class:`MultiSegmentClassifier`, accepted below their gesture's threshold and within its size
    range; pending, replacing and firing as :class:`~framefree.online.spotting.Spotter`.

    Parameters
    ----------
    classifier : MultiSegmentClassifier
    model_thresholds : ndarray, shape (M,)
        τ of each model's gesture.
    size_limits : ndarray, shape (M, 2), optional
        Smallest and largest :func:`path_size` [m] of a candidate of each model's gesture.
    model_waits : ndarray, shape (M,), optional
        Longest wait [s] for a rest after a candidate of each model's gesture while the hands
        move on (at least ``max_wait``, the default for all).
    **kw
        The candidate and timing settings of :class:`~framefree.online.spotting.Spotter`
        (``max_units``, ``max_duration``, ``max_pause``, ``pause_ratio``, ``min_pause``,
        ``margin``, ``confirm``, ``max_wait``, ``fire_on_motion``, ``rest_before``).
    """

    def __init__(self, classifier: MultiSegmentClassifier, model_thresholds: np.ndarray,
                 size_limits: np.ndarray | None = None, model_waits: np.ndarray | None = None,
                 **kw: Any) -> None:
        super().__init__(classifier, model_thresholds, size_limits=size_limits, **kw)
        self.model_waits = (np.full(len(model_thresholds), self.max_wait) if model_waits is None
                            else np.maximum(np.asarray(model_waits, dtype=float), self.max_wait))

    def rest_start(self, pending: Candidate) -> float:
        """The confirming rest follows the hands' last motion, not merely the candidate's end:
        the hands may have carried it on (the other hand's stroke of a combo)."""
        return max(pending.end_t, self._last_end_t)

    def longest_wait(self, pending: Candidate) -> float:
        """``max_wait``, or longer for a gesture that another enrolled gesture begins with
        (``model_waits``, :func:`~framefree.online.continuations.continuation_waits`)."""
        return float(self.model_waits[pending.model])

    def candidates(self, buffer: PoseBuffer) -> list[Candidate]:
        """Classify every candidate that ends with the latest unit (all of them: no pruning)."""
        out: list[Candidate] = []
        last = self.units[-1]
        after = max(self.consumed, buffer.oldest + self.margin - 1)
        for first, n in candidate_spans(list(self.units), self.max_units, self.max_duration,
                                        self.max_pause, after, self.pause_ratio, self.min_pause):
            if not self.may_start_after(self.rests[len(self.units) - n]):
                continue  # it starts in the middle of a motion
            times, poses = buffer.slice(max(first.start - self.margin, buffer.oldest),
                                        last.end + self.margin)
            d, size = self.classifier.distances(times, poses)
            self.last_distances = d
            self.evaluated.append((last.end_t, d))
            j = int(np.argmin(d))
            ratio = float(d[j] / self.model_thresholds[j])
            lo, hi = self.size_limits[j]
            ok = ratio < 1.0 and lo <= size <= hi
            out.append(Candidate(first.start, last.end, first.start_t, last.end_t, j, float(d[j]),
                                 ratio, n, size=size, accepted=bool(ok)))
        return out
