"""Offline rejection: a threshold per class from the models alone, so that 1-NN can say "no
gesture" for motion that is none (docs/algorithms/dtw.md, *Rejection*)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["REJECTED", "thresholds_from_models"]

#: the label :meth:`~framefree.NearestNeighborClassifier.predict` gives a rejected sample
REJECTED = "no_gesture"


def thresholds_from_models(D: np.ndarray, labels: Sequence[str]) -> dict[str, float]:
    """A distance threshold per class from the model-to-model distances.

    For a class ``g``: ``P_g``, the largest leave-one-out distance of its models to their nearest
    other model of ``g`` (how far apart its own performances lie), and ``N_g``, the smallest
    distance of a model of ``g`` to a model of another class (how far the vocabulary's other
    gestures begin). ``τ_g = P_g + N_g``. The label is 1-NN's; the threshold only decides whether
    the query is any gesture at all, so it may lie beyond the nearest other gesture: models are
    usually recorded in one sitting, and new performances (slower, faster, another day or world
    frame) lie farther from them than the models from each other. A tighter rule, the geometric
    midpoint ``√(P_g · N_g)``, rejected 10.8 % of the replica's genuine test trials; ``P_g + N_g``
    rejects 0.3 % of them (0.5 % of its training trials), 8 of 9 recorded everyday motions
    (pouring, scooping, free motion) and 30-49 % of synthetic ones built to resemble gestures
    (via-point moves, re-grips, drawn shapes; ``benchmarks/auto_thresholds.py``). A class with a single
    model takes for ``P`` the median ``P`` of the other classes.

    Parameters
    ----------
    D : ndarray, shape (M, M)
        Distances between the models (row: query, column: model).
    labels : sequence of str, length M

    Returns
    -------
    dict of str to float

    Raises
    ------
    ValueError
        With fewer than two classes, or when no class has two models.
    """
    labels = np.asarray(labels)
    classes = list(dict.fromkeys(labels.tolist()))
    if len(classes) < 2:
        raise ValueError("thresholds from the models need at least two gestures")
    D = np.array(D, dtype=np.float64)
    np.fill_diagonal(D, np.inf)
    positive, negative = {}, {}
    for g in classes:
        own = labels == g
        negative[g] = float(D[np.ix_(own, ~own)].min())
        if own.sum() > 1:
            positive[g] = float(D[np.ix_(own, own)].min(axis=1).max())
    if not positive:
        raise ValueError("thresholds from the models need a gesture with two or more models")
    typical = float(np.median(list(positive.values())))
    out = {}
    for g in classes:
        out[g] = float(positive.get(g, typical) + negative[g])
    return out
