"""Which level of a folder of several people's examples names the gestures.

Several people's segmented examples come as ``<person>/<gesture>/*.csv`` or as
``<gesture>/<person>/*.csv``, and the two have the same shape: folders of folders of CSV files,
the names of one level repeating under every folder of the other. Nothing in the names tells
which is which (``Sub_U001`` or ``swipe_left`` are only words), so the motions decide. A
gesture is what a new person performs alike: for each take, the nearest take *of another
group* (another person, when the labels are gestures) should have its label. People are told
apart far less well by their motions than gestures are (on the Machete people, one person left
out, the gestures are 90 % right), so the level whose names the motions recover better, that way,
names the gestures.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..core.trajectory import Trajectory
from ..errors import DegenerateMotionError

__all__ = ["PER_FOLDER", "first_level_names_gestures", "group_recovery", "oriented"]

#: Takes of each innermost folder that the decision compares (the first ones): enough to see
#: which names the motions follow, few enough that it costs seconds, not a calibration.
PER_FOLDER = 2


def group_recovery(distances: np.ndarray, labels: Sequence[str], groups: Sequence[str]) -> float:
    """The share of takes whose nearest take of another group has their label.

    Parameters
    ----------
    distances : ndarray, shape (n, n)
        Distances between the takes (the diagonal is not used).
    labels, groups : sequence of str, length n
        Each take's label and group (e.g. gesture and person).

    Returns
    -------
    float
        In [0, 1]; a take with several nearest takes counts the share of them with its label; one
        with no take of another group does not count. 0 when no take counts.
    """
    labels_arr, groups_arr = np.asarray(labels), np.asarray(groups)
    hits, counted = 0.0, 0
    for i in range(len(labels_arr)):
        other = groups_arr != groups_arr[i]
        if not other.any():
            continue
        row = distances[i, other]
        nearest = np.isclose(row, row.min(), rtol=1e-9, atol=0.0)
        hits += float(np.mean(labels_arr[other][nearest] == labels_arr[i]))
        counted += 1
    return hits / counted if counted else 0.0


def first_level_names_gestures(people: Sequence[tuple[str, str, Path]],
                               trajectories: Sequence[Trajectory]) -> bool:
    """Whether a folder read as ``<person>/<label>/*.csv`` is ``<gesture>/<person>/*.csv`` instead.

    Parameters
    ----------
    people : sequence of (str, str, Path)
        ``(label, person, file)`` of every recording, read as ``<person>/<label>/``
        (:func:`~framefree.datasets.layout.people_trials`).
    trajectories : sequence of Trajectory
        The recordings, in the same order.

    Returns
    -------
    bool
        True when the first-level folders' names are the gestures: the motions recover them, each
        take from the other second-level folders' takes, better than the second-level names. On a
        tie (or where no take moves) the second level stays the gestures.
    """
    from ..classifier import NearestNeighborClassifier

    descriptor = NearestNeighborClassifier.recommended().build_descriptor()
    seen: dict[tuple[str, str], int] = {}
    kept, descriptors = [], []
    for (label, person, _), trajectory in zip(people, trajectories, strict=True):
        if seen.get((label, person), 0) >= PER_FOLDER:
            continue
        try:
            descriptors.append(descriptor.compute(trajectory))
        except DegenerateMotionError:
            continue
        seen[(label, person)] = seen.get((label, person), 0) + 1
        kept.append((label, person))
    if len(kept) < 2:
        return False
    distances = descriptor.distance_matrix(descriptors, descriptors)
    seconds, firsts = [k[0] for k in kept], [k[1] for k in kept]
    return group_recovery(distances, firsts, seconds) > group_recovery(distances, seconds, firsts)


def oriented(people: Sequence[tuple[str, str, Path]], trajectories: Sequence[Trajectory]
             ) -> tuple[list[tuple[str, str, Path]], bool]:
    """``(label, person, file)`` of every recording of a folder of people, the two levels swapped
    where the first-level folders name the gestures (:func:`first_level_names_gestures`), and
    whether they were."""
    if first_level_names_gestures(people, trajectories):
        return [(person, label, f) for label, person, f in people], True
    return list(people), False
