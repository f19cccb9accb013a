"""Recognition of people the models never saw: leave one person out, or held-out people against
the models of others, with the world frame of every recording as recorded, turned about the
vertical, or tilted at random (docs/real-people.md).

Methods compared (:data:`PEOPLE_METHODS`):

``framefree``
    :class:`~framefree.classifier.NearestNeighborClassifier` with the chosen ``invariance`` on the
    whole multi-tracker sample (canonical paths).
``paper``
    the paper's BILTS+ (screw path) on each tracker, the trackers' distance matrices summed.
``recommended``
    framefree's recommended single-tracker recognizer on each tracker, summed likewise.
``baseline``
    a practitioner's first try: 1-NN (Euclidean) on every tracker's positions relative to their
    start, resampled to 32 points in time; depends on the world frame.
``baseline-heading``
    the same after turning each sample about the vertical by its heading (the horizontal direction
    from the first tracker to the second, as ``invariance="gravity"`` finds it): invariant to turns
    about the vertical, not to tilts.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..classifier import NearestNeighborClassifier
from ..core import se3
from ..core.multitrajectory import MultiTrajectory
from ..datasets.people_layout import PeopleDataset, Recording
from ..descriptors.canonical import INVARIANCES, canonical_frame

__all__ = ["FRAMES", "PEOPLE_METHODS", "PeopleResult", "distance_matrix", "evaluate_people", "reframe"]

#: world-frame conditions: as recorded, turned about the vertical, tilted at random
FRAMES = ("recorded", "turned", "tilted")
PEOPLE_METHODS = ("framefree", "paper", "recommended", "baseline", "baseline-heading")


@dataclass(frozen=True)
class PeopleResult:
    """Accuracy on people the models never saw.

    Attributes
    ----------
    accuracy : float
        Fraction of query recordings given their gesture (all people pooled).
    per_person : dict of str to float
        Accuracy of each query person.
    labels : list of str
        Gestures, in the order of the confusion matrix.
    confusion : ndarray, shape (n_gestures, n_gestures)
        Counts: row = true gesture, column = recognized gesture.
    settings : dict
        Method, invariance, frames, seed, protocol.
    """

    accuracy: float
    per_person: dict[str, float]
    labels: list[str]
    confusion: np.ndarray
    settings: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {"accuracy": self.accuracy, "per_person": self.per_person, "labels": self.labels,
                "confusion": self.confusion.tolist(), "settings": self.settings}

    def mistakes(self) -> list[tuple[str, str, int]]:
        """``(true, recognized, count)`` for every off-diagonal cell, most frequent first."""
        out = [(self.labels[i], self.labels[j], int(self.confusion[i, j]))
               for i, j in zip(*np.nonzero(self.confusion), strict=True) if i != j]
        return sorted(out, key=lambda m: -m[2])


def _world_change(kind: str, rng: np.random.Generator, up: np.ndarray) -> np.ndarray:
    W = np.eye(4)
    if kind == "turned":
        W[:3, :3] = se3.rotation_from_vector((up * rng.uniform(0.0, 2.0 * np.pi))[None])[0]
    elif kind == "tilted":
        q = rng.standard_normal(4)
        W[:3, :3] = se3.matrix_from_quaternion((q / np.linalg.norm(q))[None])[0]
    elif kind != "recorded":
        raise ValueError(f"unknown frames {kind!r}; choose one of {', '.join(FRAMES)}")
    if kind != "recorded":
        W[:3, 3] = rng.uniform(-2.0, 2.0, 3)
    return W


def reframe(samples: Sequence[MultiTrajectory], kind: str, seed: int = 0) -> list[MultiTrajectory]:
    """Every sample seen from its own random world frame (``kind`` in :data:`FRAMES`).

    The stated vertical stays what the tracking system's convention says (a tilted tracking
    system does not know it is tilted), so ``gravity`` invariance holds under ``turned`` but not
    under ``tilted``.
    """
    rng = np.random.default_rng(seed)
    out = []
    for s in samples:
        moved = s.transformed(_world_change(kind, rng, s.up))
        out.append(MultiTrajectory(moved.trackers, moved.names, s.up, s.source))
    return out


def _baseline_features(samples: Sequence[MultiTrajectory], heading: bool) -> np.ndarray:
    feats = []
    for s in samples:
        P = np.stack([tr.p - tr.p[0] for tr in s.trackers])  # (k, N, 3)
        if heading:
            P = P @ canonical_frame(s, "gravity")
        grid = np.linspace(s.t[0], s.t[-1], 32)
        feats.append(np.concatenate([np.interp(grid, s.t, P[k, :, c])
                                     for k in range(P.shape[0]) for c in range(3)]))
    return np.asarray(feats)


def _per_tracker(make: Callable[[], NearestNeighborClassifier], queries: Sequence[MultiTrajectory],
                 models: Sequence[MultiTrajectory], labels: Sequence[str]) -> np.ndarray:
    total = np.zeros((len(queries), len(models)))
    for k in range(models[0].n_trackers):
        clf = make().fit([m.trackers[k] for m in models], list(labels))
        total += clf.distance_matrix([q.trackers[k] for q in queries])
    return total


def distance_matrix(method: str, queries: Sequence[MultiTrajectory], models: Sequence[MultiTrajectory],
                    labels: Sequence[str], invariance: str = "full") -> np.ndarray:
    """Distances (n_queries, n_models) of one of :data:`PEOPLE_METHODS`."""
    if method == "framefree":
        clf = NearestNeighborClassifier(invariance=invariance).fit(list(models), list(labels))
        return clf.distance_matrix(list(queries))
    if method == "paper":
        return _per_tracker(NearestNeighborClassifier.paper, queries, models, labels)
    if method == "recommended":
        return _per_tracker(NearestNeighborClassifier.recommended, queries, models, labels)
    if method in ("baseline", "baseline-heading"):
        heading = method == "baseline-heading"
        Q, M = _baseline_features(queries, heading), _baseline_features(models, heading)
        return np.sqrt(((Q[:, None, :] - M[None, :, :]) ** 2).sum(axis=2))
    raise ValueError(f"unknown method {method!r}; choose one of {', '.join(PEOPLE_METHODS)}")


def evaluate_people(
    data: PeopleDataset,
    models: PeopleDataset | None = None,
    method: str = "framefree",
    invariance: str = "full",
    frames: str = "recorded",
    seed: int = 0,
    progress: Callable[[Any], Any] | None = None,
) -> PeopleResult:
    """Accuracy on people the models never saw.

    Parameters
    ----------
    data : PeopleDataset
        The query people (and, without ``models``, the model people too).
    models : PeopleDataset, optional
        Model people: every recording of ``data`` is classified against all of these. Without it,
        one person of ``data`` is left out at a time and classified against the others.
    method : str
        One of :data:`PEOPLE_METHODS`.
    invariance : {"full", "gravity"}
        The invariance of the ``framefree`` method.
    frames : {"recorded", "turned", "tilted"}
        World frame of every recording (queries and models alike), seeded by ``seed``.
    progress : callable, optional
        Wraps the iterable of folds (e.g. ``tqdm``).
    """
    if invariance not in INVARIANCES:
        raise ValueError(f"unknown invariance {invariance!r}; choose one of {', '.join(INVARIANCES)}")
    queries: list[Recording] = list(data)
    pool: list[Recording] = list(models) if models is not None else queries
    moved = dict(zip([id(r) for r in queries + pool],
                     reframe([r.sample for r in queries + pool], frames, seed), strict=True))
    folds = [(None, queries)] if models is not None else [
        (p, [r for r in queries if r.person == p]) for p in data.people]
    wrap = progress or (lambda it: it)
    labels = sorted({r.gesture for r in queries} | {r.gesture for r in pool})
    index = {g: i for i, g in enumerate(labels)}
    confusion = np.zeros((len(labels), len(labels)), dtype=int)
    hits: dict[str, list[bool]] = {}
    for left_out, fold in wrap(folds):
        train = [r for r in pool if r.person != left_out] if left_out is not None else pool
        D = distance_matrix(method, [moved[id(r)] for r in fold], [moved[id(r)] for r in train],
                            [r.gesture for r in train], invariance)
        for r, j in zip(fold, np.argmin(D, axis=1), strict=True):
            guess = train[int(j)].gesture
            confusion[index[r.gesture], index[guess]] += 1
            hits.setdefault(r.person, []).append(guess == r.gesture)
    per_person = {p: float(np.mean(v)) for p, v in hits.items()}
    accuracy = float(np.mean([h for v in hits.values() for h in v]))
    protocol = "models given" if models is not None else "leave one person out"
    settings = {"method": method, "invariance": invariance, "frames": frames, "seed": seed,
                "protocol": protocol, "queries": len(queries), "models": len(pool)}
    return PeopleResult(accuracy, per_person, labels, confusion, settings)
