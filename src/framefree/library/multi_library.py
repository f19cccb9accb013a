"""Gesture libraries of several trackers: the takes of a vocabulary performed with a controller in
each hand, the settings of the :class:`~framefree.online.multi.MultiRecognizer` and its calibrated
thresholds, in one file that starts the recognizer without recalibrating.

The file is the single-tracker library file (:mod:`framefree.io.library_file`: a JSON member and
every take's rows), with rows of ``1 + 7 n`` columns — ``t``, then ``x y z qw qx qy qz`` of each of
the ``n`` trackers, in framefree's frame — and three more JSON keys: ``trackers`` (their names, in
column order), ``up`` (the takes' vertical) and ``invariance`` (of the offline classifier). A file
with ``trackers`` is a library of several trackers (:func:`is_multi_library`).

Takes come from a folder that ``framefree record`` writes from a multi-tracker source,
``<library>/<gesture>/<trial>.csv``, or from a folder of people
``<library>/<person>/<gesture>/<recording>`` (Machete files or multi-tracker CSV), or from another
such library file (:func:`read_multi_takes`, :func:`load_multi_library`).
"""

from __future__ import annotations

import datetime
import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import Trajectory
from ..datasets.multi_models import is_multi_library, multi_recordings
from ..errors import FramefreeError
from ..io.library_file import (
    FORMAT_VERSION,
    LibraryError,
    read_library_file,
    rebuild_hint,
    write_library_file,
)
from ..online.config import RecognizerConfig
from ..online.multi import MultiRecognizer
from .store import StoredSettings
from .take_set import LabelledTakes, refuse_copies

__all__ = [
    "MultiGestureLibrary",
    "MultiTakeSet",
    "enroll_multi",
    "is_multi_library",
    "load_multi_library",
    "multi_fingerprint",
    "read_multi_takes",
]


@dataclass(frozen=True)
class MultiTakeSet(LabelledTakes):
    """Takes of a vocabulary made with several trackers.

    Attributes
    ----------
    takes : tuple of MultiTrajectory
        One gesture performance each, all with the same trackers in the same order.
    labels : tuple of str
        Gesture of each take.
    names : tuple of str
        Where each take lies below its folder, without suffix (``hook_left/trial_3``,
        ``Sub_U001/hook_left/ex_0_moderate``); ``--remove`` and the reports use it.
    arrays : tuple of ndarray, shape (N_k, 1 + 7 n_trackers), optional
        The rows the takes were built from, when known (a library file stores these).
    """

    takes: tuple[MultiTrajectory, ...]
    labels: tuple[str, ...]
    names: tuple[str, ...]
    arrays: tuple[np.ndarray, ...] = ()

    @property
    def trackers(self) -> tuple[str, ...]:
        """Tracker names, in column order (those of the first take)."""
        return self.takes[0].names if self.takes else ()

    def rows(self) -> tuple[np.ndarray, ...]:
        """Every take's rows as stored in a library file, (N_k, 1 + 7 n_trackers) each."""
        return self.arrays or tuple(_rows(s) for s in self.takes)

    def as_stored(self) -> MultiTakeSet:
        """The takes exactly as a library file gives them back (rebuilt from their rows, so that
        enrolment calibrates on what a loaded library rebuilds, bit for bit)."""
        rows = self.rows()
        takes = tuple(_from_rows(r, s.names, s.up, s.source)
                      for r, s in zip(rows, self.takes, strict=True))
        return MultiTakeSet(takes, self.labels, self.names, rows)

    def __add__(self, other: MultiTakeSet) -> MultiTakeSet:
        if self.takes and other.takes and len(self.trackers) != len(other.trackers):
            raise LibraryError(f"{other.takes[0].source}: {len(other.trackers)} trackers, but "
                               f"{self.takes[0].source} has {len(self.trackers)}; a library's "
                               "takes all have the same trackers")
        theirs = tuple(_in_order(s, self.trackers) for s in other.takes) if self.takes else other.takes
        return MultiTakeSet(self.takes + theirs, self.labels + other.labels,
                            self.names + other.names,
                            self.rows() + tuple(_rows(s) for s in theirs))

    @staticmethod
    def matches(pattern: str, label: str, name: str) -> bool:
        """Whether ``pattern`` names a take of gesture ``label`` called ``name``: its gesture
        (``hook_left``) or the end of its name (``hook_left/trial_3``,
        ``Sub_U001/hook_left/ex_0_moderate``)."""
        parts = pattern.strip("/").split("/")
        return label == pattern.strip("/") or name.split("/")[-len(parts):] == parts


def _rows(sample: MultiTrajectory) -> np.ndarray:
    """(N, 1 + 7 n) rows ``t, x, y, z, qw, qx, qy, qz`` of each tracker in turn."""
    return np.column_stack([sample.t] + [np.column_stack([tr.p, tr.q]) for tr in sample.trackers])


def _from_rows(rows: np.ndarray, names: Sequence[str], up: Any, source: str | None
               ) -> MultiTrajectory:
    n = (rows.shape[1] - 1) // 7
    trackers = tuple(Trajectory(rows[:, 0], rows[:, 1 + 7 * k:4 + 7 * k], rows[:, 4 + 7 * k:8 + 7 * k],
                                source=f"{source}:{names[k]}") for k in range(n))
    return MultiTrajectory(trackers, tuple(names), up, source)


def _in_order(sample: MultiTrajectory, names: tuple[str, ...]) -> MultiTrajectory:
    """``sample`` with its trackers in the order ``names`` when it has the same names, else as it
    is (matched by position) under those names."""
    if set(sample.names) == set(names):
        return MultiTrajectory(tuple(sample[n] for n in names), names, sample.up, sample.source)
    return MultiTrajectory(sample.trackers, names, sample.up, sample.source)


def read_multi_takes(folder: str | Path) -> MultiTakeSet:
    """The takes below a folder of multi-tracker recordings: ``<gesture>/<recording>`` (what
    ``framefree record`` writes from a multi-tracker source) or ``<person>/<gesture>/<recording>``.

    Raises
    ------
    DatasetError
        When the folder holds no multi-tracker recordings, or recordings of different numbers of
        trackers.
    TrajectoryError
        When a recording does not read (naming the file, the row and the problem).
    """
    root = Path(folder).expanduser()
    found = multi_recordings(root)
    names = tuple(str(p.relative_to(root).with_suffix("")) for p in found.paths)
    takes = MultiTakeSet(tuple(found.samples[:1]), tuple(found.labels[:1]), names[:1])
    rest = MultiTakeSet(tuple(found.samples[1:]), tuple(found.labels[1:]), names[1:])
    return takes + rest


def _now() -> str:
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")


def _fingerprint(takes: MultiTakeSet, settings: dict[str, Any], invariance: str) -> str:
    h = hashlib.sha256()
    h.update(json.dumps({"format": FORMAT_VERSION, "labels": list(takes.labels),
                         "names": list(takes.names), "trackers": list(takes.trackers),
                         "settings": settings, "invariance": invariance}, sort_keys=True).encode())
    for rows in takes.rows():
        h.update(np.ascontiguousarray(rows).tobytes())
    return h.hexdigest()


def multi_fingerprint(takes: MultiTakeSet, config: RecognizerConfig, invariance: str) -> str:
    """The fingerprint a library enrolled from ``takes`` with ``config`` and ``invariance`` has
    (:attr:`MultiGestureLibrary.fingerprint`): equal means nothing to recalibrate."""
    return _fingerprint(takes.as_stored(), _as_json(config.to_dict()), invariance)


@dataclass(frozen=True)
class MultiGestureLibrary(StoredSettings):
    """A vocabulary of several trackers ready to go live (:func:`enroll_multi`,
    :func:`load_multi_library`, :meth:`recognizer`).

    Attributes
    ----------
    takes : MultiTakeSet
    invariance : {"gravity", "full"}
        Of the offline classifier that compares candidates with the takes.
    config : dict
        The user's settings (:meth:`RecognizerConfig.to_dict`).
    learned : dict
        Every value derived from the takes, with its provenance
        (:meth:`~framefree.online.learned.LearnedSettings.to_dict`: levels, candidate limits,
        size ranges, thresholds τ_g, stop threshold).
    gate_speeds : (float, float)
        The acceptance gates' fastest plausible speed [m/s] and angular speed [rad/s].
    built_from : tuple of str
    framefree_version, format_version, created
    """

    takes: MultiTakeSet
    invariance: str
    config: dict[str, Any]
    learned: dict[str, Any]
    gate_speeds: tuple[float, float]
    built_from: tuple[str, ...] = ()
    framefree_version: str = __version__
    format_version: int = FORMAT_VERSION
    created: str = field(default_factory=_now)

    @property
    def fingerprint(self) -> str:
        """SHA-256 of the takes, trackers, settings and invariance (equal: nothing to recalibrate)."""
        return _fingerprint(self.takes, self.settings, self.invariance)

    def recognizer(self) -> MultiRecognizer:
        """A live :class:`~framefree.online.multi.MultiRecognizer`: the offline classifier fitted
        on the takes, every threshold and limit restored (no calibration)."""
        return MultiRecognizer.from_samples(list(self.takes.takes), list(self.takes.labels),
                                            self.recognizer_config(), self.invariance,
                                            self.learned_settings())

    def meta(self) -> dict[str, Any]:
        """The JSON member of the library file."""
        return {
            "format_version": self.format_version, "framefree_version": self.framefree_version,
            "created": self.created, "built_from": list(self.built_from),
            "names": list(self.takes.names), "labels": list(self.takes.labels),
            "trackers": list(self.takes.trackers),
            "up": [float(x) for x in self.takes.takes[0].up],
            "invariance": self.invariance, "config": self.config,
            "learned": self.learned, "gate_speeds": list(self.gate_speeds), "calibration": None,
            "fingerprint": self.fingerprint,
        }

    def save(self, path: str | Path) -> Path:
        """Write the library file; parent folders are created."""
        return write_library_file(path, self.meta(), list(self.takes.rows()))

    def summary(self) -> str:
        """One line for the vocabulary, one per gesture (takes, τ_g)."""
        counts = self.takes.counts()
        lines = [f"{len(self.takes)} takes of {len(counts)} gestures, {len(self.takes.trackers)} "
                 f"trackers ({', '.join(self.takes.trackers)}), invariance {self.invariance}, "
                 f"stop above {self.stop_threshold:.3g} rad/s"]
        tau = self.gesture_thresholds
        lines += [f"  {g:<22} {n:3d} takes  τ = {tau.get(g, float('nan')):.4g}"
                  for g, n in counts.items()]
        return "\n".join(lines)


def enroll_multi(takes: MultiTakeSet, config: RecognizerConfig | None = None,
                 invariance: str = "gravity", built_from: Sequence[str] = ()
                 ) -> MultiGestureLibrary:
    """Fit the models and calibrate the thresholds of a vocabulary of several trackers once.

    Parameters
    ----------
    takes : MultiTakeSet
        At least one take of each gesture, all with the same trackers.
    config : RecognizerConfig, optional
        Settings asked for (default ``RecognizerConfig()``); fields left ``None`` are derived
        from the takes (:func:`~framefree.online.multi.resolve_multi_config`).
    invariance : {"gravity", "full"}
        Of the offline classifier (:meth:`~framefree.online.multi.MultiRecognizer.from_samples`).
    built_from : sequence of str
        Where the takes came from (stored; used in rebuild hints).

    Raises
    ------
    LibraryError
        For fewer than two gestures, or a take that is an exact copy of another (its gesture's
        threshold would be about 0).
    """
    if len(takes.gestures) < 2:
        raise LibraryError(f"takes of {len(takes.gestures)} gesture(s) ({', '.join(takes.gestures)}): "
                           "a library needs at least two, each gesture's threshold is measured "
                           "against the others")
    refuse_copies(takes)
    config = config or RecognizerConfig()
    stored = takes.as_stored()
    rec = MultiRecognizer.from_samples(list(stored.takes), list(stored.labels), config, invariance)
    return MultiGestureLibrary(stored, invariance, _as_json(rec.config.to_dict()),
                               _as_json(rec.learned_.to_dict()),
                               rec.gate_speeds,
                               tuple(str(s) for s in built_from))


def _as_json(d: dict[str, Any]) -> dict[str, Any]:
    """``d`` as it comes back from the library's JSON (tuples become lists, numpy scalars numbers)."""
    return json.loads(json.dumps(d, default=lambda x: x.item() if hasattr(x, "item") else float(x)))


def load_multi_library(path: str | Path) -> MultiGestureLibrary:
    """Read a library file of several trackers written by :meth:`MultiGestureLibrary.save`.

    Raises
    ------
    LibraryError
        When the file is not a library of several trackers, was written in another format
        version, or its settings do not fit this framefree (the message says how to rebuild it).
    """
    path = Path(path)
    meta, rows = read_library_file(path)
    trackers = meta.get("trackers")
    if not trackers:
        raise LibraryError(f"{path}: a gesture library of one tracker, not of several")
    width = 1 + 7 * len(trackers)
    bad = next((n for n, r in zip(meta["names"], rows, strict=True) if r.shape[1:] != (width,)), None)
    if bad is not None:
        raise LibraryError(f"{path}: take {bad} does not have {width} columns "
                           f"({len(trackers)} trackers); {rebuild_hint(path, meta)}")
    try:
        takes = tuple(_from_rows(r, trackers, meta["up"], f"{path}:{n}")
                      for r, n in zip(rows, meta["names"], strict=True))
        lib = MultiGestureLibrary(
            MultiTakeSet(takes, tuple(meta["labels"]), tuple(meta["names"]), tuple(rows)),
            str(meta["invariance"]), meta["config"], meta["learned"],
            (float(meta["gate_speeds"][0]), float(meta["gate_speeds"][1])),
            tuple(meta.get("built_from") or ()), meta.get("framefree_version", "?"),
            int(meta["format_version"]), meta.get("created", ""))
        lib.recognizer_config()
        lib.learned_settings()
    except (KeyError, TypeError, ValueError, FramefreeError) as exc:
        raise LibraryError(f"{path}: settings do not fit framefree {__version__} ({exc}); "
                           f"{rebuild_hint(path, meta)}") from None
    return lib
