"""How real people vary a gesture's geometry: closure, size, corners and turns of every take of
a people data set, measured as the live recognizer measures its demonstrations.

The live recognizer's limits on a candidate (closure, size, corners, turns) come from one
person's takes and must hold for other people. A people data set (several people, several takes
of each gesture) tells how far another person goes beyond one person's takes
(``benchmarks/real_corners.py``, ``benchmarks/real_sizes.py``, ``benchmarks/real_turns.py``,
``benchmarks/real_vertical.py``, docs/online.md).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TypeVar

import numpy as np

from ..core.trajectory import Trajectory
from ..datasets.people_layout import load_people
from ..online.config import RecognizerConfig
from ..online.hand_direction import direction_limit
from ..online.limits import (
    gesture_directions,
    gesture_proportions,
    gesture_verticality,
    longest_corner_rest,
    recording_geometry,
)
from ..online.model_settings import segment_descriptor
from ..online.rest_levels import speed_levels
from ..online.segment_classifier import SegmentClassifier
from ..online.segmentation import SpeedLevels
from ..online.vertical import up_vector

__all__ = ["by_name", "cone_coverage", "other_peoples", "people_data_args", "take_directions",
           "take_geometry", "take_proportions", "take_rests", "take_verticality"]

#: (tracker index, person, gesture)
TakeKey = tuple[int, str, str]
V = TypeVar("V")


def people_data_args(doc: str | None, figure: bool = False) -> argparse.Namespace:
    """The command line of a ``benchmarks/real_*.py`` script: ``--data`` (a people data set,
    default ``../shared/data/machete_vive``) and ``--json`` (where to write the results, if
    anywhere), and with ``figure`` ``--figure`` (where to draw one); ``doc`` is the script's
    docstring, shown by ``--help``."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=Path, default=Path("../shared/data/machete_vive"))
    ap.add_argument("--json", type=Path)
    if figure:
        ap.add_argument("--figure", type=Path, help="draw the figure here (PNG)")
    return ap.parse_args()


def other_peoples(table: Mapping[TakeKey, Sequence[V]], key: TakeKey) -> list[V]:
    """The values of every other person's takes of ``key``'s gesture on ``key``'s tracker: what a
    limit set from ``key``'s takes meets in other people."""
    tracker, person, gesture = key
    return [v for (t, p, g), values in table.items() if (t, g) == (tracker, gesture) and p != person
            for v in values]


def by_name(table: Mapping[TakeKey, V]) -> dict[str, V]:
    """``table`` keyed by ``"tracker/person/gesture"``, sorted (for JSON)."""
    return {f"{t}/{p}/{g}": v for (t, p, g), v in sorted(table.items())}


def take_geometry(data: str | Path, config: RecognizerConfig | None = None
                  ) -> dict[TakeKey, list[tuple[float, float, int, int]]]:
    """Closure, size [m of screw path], corners and turn kinds of every take, per tracker, person
    and gesture.

    Each tracker of every recording is cut into movement units with speed levels from all
    recordings of that tracker (as a recognizer takes them from its models) and measured by
    :func:`~framefree.online.limits.recording_geometry`; a take with no movement unit is left
    out.

    Parameters
    ----------
    data : str or Path
        A people data set (:func:`~framefree.datasets.people_layout.load_people`).
    config : RecognizerConfig, optional
        ``L``, ``dt``, ``margin``, ``corner_angle`` and the descriptor settings (default: the
        recognizer's defaults).

    Returns
    -------
    dict
        ``{(tracker, person, gesture): [(closure, size, corners, turns) of each take]}``.
    """
    config = config or RecognizerConfig()
    classifier = SegmentClassifier(segment_descriptor(config), [])
    L, k = config.descriptor.L, config.constants
    return _per_take(data, config, lambda tr, levels, gesture: [
        m for m in [recording_geometry(tr, classifier, levels, L, k.margin, k.dt,
                                       k.corner_angle)] if m is not None])


def _per_take(data: str | Path, config: RecognizerConfig,
              measure: Callable[[Trajectory, SpeedLevels, str], list[V]]) -> dict[TakeKey, list[V]]:
    """``measure(trajectory, levels, gesture)`` of every tracker of every recording of a people
    data set, with speed levels from all recordings of that tracker (as a recognizer takes them
    from its models), collected per tracker, person and gesture (an empty list adds nothing)."""
    ds = load_people(data)
    out: dict[TakeKey, list[V]] = {}
    n_trackers = min((r.sample.n_trackers for r in ds), default=0)
    for tracker in range(n_trackers):
        trajs = [r.sample.trackers[tracker] for r in ds]
        levels = speed_levels(trajs, config.descriptor.L, config.constants.dt)
        for r, tr in zip(ds, trajs, strict=True):
            values = measure(tr, levels, r.gesture)
            if values:
                out.setdefault((tracker, r.person, r.gesture), []).extend(values)
    return out


def take_rests(data: str | Path, config: RecognizerConfig | None = None) -> dict[TakeKey, list[float]]:
    """The longest rest [s] at a corner of every take
    (:func:`~framefree.online.limits.longest_corner_rest`), per tracker, person and gesture,
    cut as :func:`take_geometry` cuts them; a take with no movement unit is left out."""
    config = config or RecognizerConfig()
    L, k = config.descriptor.L, config.constants
    return _per_take(data, config, lambda tr, levels, gesture: [
        r for r in [longest_corner_rest(tr, levels, L, k.dt, k.corner_angle)] if r is not None])


def take_proportions(data: str | Path, config: RecognizerConfig | None = None
                     ) -> dict[TakeKey, list[np.ndarray]]:
    """The :func:`~framefree.online.proportions.proportions` of every take (K,) for its K
    corners, per tracker, person and gesture, cut as :func:`take_geometry` cuts them; a take
    with no movement unit is left out."""
    config = config or RecognizerConfig()
    L, k = config.descriptor.L, config.constants
    return _per_take(data, config, lambda tr, levels, gesture: gesture_proportions(
        [tr], [gesture], levels, L, k.dt, k.corner_angle).get(gesture, []))


def take_verticality(data: str | Path, up: str = "+z", config: RecognizerConfig | None = None
                     ) -> dict[TakeKey, list[float]]:
    """:func:`~framefree.online.vertical.verticality` of every take, per tracker, person and
    gesture, measured as the live recognizer measures its demonstrations
    (:func:`~framefree.online.limits.gesture_verticality`; speed levels as in
    :func:`take_geometry`).

    Parameters
    ----------
    data : str or Path
        A people data set (:func:`~framefree.datasets.people_layout.load_people`), read into
        framefree's frame (``up`` = ``"+z"``).
    up : str
        The vertical axis of the data as read.
    config : RecognizerConfig, optional
        ``L`` and ``dt`` (default: the recognizer's defaults).
    """
    config = config or RecognizerConfig()
    vertical = up_vector(up)
    return _per_take(data, config, lambda tr, levels, gesture: gesture_verticality(
        [tr], [gesture], levels, config.descriptor.L, vertical, config.constants.dt
    ).get(gesture, []))


def take_directions(data: str | Path, config: RecognizerConfig | None = None
                    ) -> dict[TakeKey, list[np.ndarray]]:
    """The :func:`~framefree.online.hand_direction.hand_direction` (3,) of every take, per
    tracker, person and gesture, measured as the live recognizer measures its demonstrations
    (:func:`~framefree.online.limits.gesture_directions`; speed levels as in
    :func:`take_geometry`)."""
    config = config or RecognizerConfig()
    return _per_take(data, config, lambda tr, levels, gesture: gesture_directions(
        [tr], [gesture], levels, config.descriptor.L, config.constants.dt).get(gesture, []))


def cone_coverage(directions: Mapping[TakeKey, Sequence[np.ndarray]], coverage: float
                  ) -> dict[str, int]:
    """How many of a person's takes lie in the cone learned from every other person's takes of
    the same gesture and tracker (:func:`~framefree.online.hand_direction.direction_limit` at
    ``coverage``), over every person, gesture and tracker: ``{"cones", "checked", "inside",
    "angles"}``, ``angles`` holding each checked take's angle from its cone's axis and the
    cone's half-angle [deg] (a gesture whose other people's takes do not agree has no cone and
    is not checked)."""
    cones = checked = inside = 0
    pairs: list[tuple[float, float]] = []
    for (tracker, person, gesture), own in directions.items():
        others = [v for (t, p, g), vs in directions.items()
                  if (t, g) == (tracker, gesture) and p != person for v in vs]
        cone = direction_limit(others, coverage=coverage)
        if cone is None:
            continue
        mean, angle = cone
        angles = np.degrees(np.arccos(np.clip(np.asarray(own) @ mean, -1.0, 1.0)))
        cones += 1
        checked += len(own)
        inside += int((angles <= angle).sum())
        pairs += [(float(a), float(angle)) for a in angles]
    return {"cones": cones, "checked": checked, "inside": inside, "angles": pairs}
