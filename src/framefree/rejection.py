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
    other model of ``g`` (how far a new performance may lie), and ``N_g``, the smallest distance of
    a model of ``g`` to a model of another class (how near the nearest other gesture is).
    ``τ_g = √(P_g · N_g)``, the geometric midpoint (distances are scale-like), when ``P_g < N_g``;
    otherwise ``N_g`` (the classes overlap: favour rejection). A class with a single model gets
    ``√(P · N_g)`` with ``P`` the median ``P`` of the other classes.

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
        p, n = positive.get(g, typical), negative[g]
        out[g] = float(np.sqrt(p * n)) if p < n else n
    return out
