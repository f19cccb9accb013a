"""Gesture libraries: the takes of a vocabulary, its recognizer settings and calibrated thresholds,
in one versioned file that starts a recognizer without recalibrating.

Building models from recordings is cheap (0.04 s for the 35 HPM recordings); calibrating the
recognizer is not (about 10 s for the same). So a library stores what is needed to rebuild the
models exactly — the rows of the takes — together with the outcome of the calibration (the
resolved :class:`~framefree.online.RecognizerConfig`), and loading rebuilds the models and
restores everything else.

The file format is :mod:`framefree.io.library_file`.
"""

from __future__ import annotations

import datetime
import hashlib
import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..core.trajectory import Trajectory
from ..errors import DatasetError, FramefreeError
from ..io.library_file import (
    FORMAT_VERSION,
    LibraryError,
    library_takes,
    read_library_file,
    rebuild_hint,
    write_library_file,
)
from ..online.config import RecognizerConfig
from ..online.recognizer import Recognizer

__all__ = [
    "FORMAT_VERSION",
    "GestureLibrary",
    "LibraryError",
    "TakeSet",
    "build_recognizer",
    "combine_takes",
    "enroll",
    "load_library",
    "load_recognizer",
    "read_takes",
    "refuse_copies",
]

#: Context folder that ``framefree record`` writes by default and :func:`read_takes` prefers.
OWN_CONTEXT = "own"
_PREFERRED_CONTEXTS = (OWN_CONTEXT, "original_1")


def _now() -> str:
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")


@dataclass(frozen=True)
class TakeSet:
    """Takes of a vocabulary: the recordings, their gesture labels and their names.

    Attributes
    ----------
    takes : tuple of Trajectory
        One gesture performance each.
    labels : tuple of str
        Gesture of each take.
    names : tuple of str
        ``<gesture>/<context>/<trial>`` of each take (its place in a library folder).
    arrays : tuple of ndarray, shape (N_k, 8), optional
        The rows ``t, x, y, z, qw, qx, qy, qz`` the takes were built from, when known (a library
        file stores these; see :meth:`as_stored`).
    """

    takes: tuple[Trajectory, ...]
    labels: tuple[str, ...]
    names: tuple[str, ...]
    arrays: tuple[np.ndarray, ...] = ()

    def __post_init__(self) -> None:
        if not len(self.takes) == len(self.labels) == len(self.names):
            raise ValueError(f"{len(self.takes)} takes, {len(self.labels)} labels, {len(self.names)} names")
        if self.arrays and len(self.arrays) != len(self.takes):
            raise ValueError(f"{len(self.takes)} takes but {len(self.arrays)} arrays")

    def rows(self) -> tuple[np.ndarray, ...]:
        """The rows of every take as stored in a library file, (N_k, 8) each."""
        return self.arrays or tuple(tr.to_array() for tr in self.takes)

    def as_stored(self) -> TakeSet:
        """The takes exactly as a library file gives them back.

        Building a trajectory renormalizes its quaternions, which can change their last bit (and
        does not settle: it may alternate). A library stores the rows and every reader rebuilds the
        trajectories from them, so enrolment calibrates on these, and a loaded library rebuilds
        bit-identical models.
        """
        rows = self.rows()
        takes = tuple(Trajectory.from_array(r, source=tr.source)
                      for r, tr in zip(rows, self.takes, strict=True))
        return TakeSet(takes, self.labels, self.names, rows)

    def __len__(self) -> int:
        return len(self.takes)

    @property
    def gestures(self) -> list[str]:
        """Distinct gesture labels in first-appearance order."""
        return list(dict.fromkeys(self.labels))

    def counts(self) -> dict[str, int]:
        """Number of takes per gesture."""
        return {g: self.labels.count(g) for g in self.gestures}

    def __add__(self, other: TakeSet) -> TakeSet:
        return TakeSet(self.takes + other.takes, self.labels + other.labels, self.names + other.names,
                       self.rows() + other.rows())

    def without(self, patterns: Iterable[str]) -> TakeSet:
        """A copy without the takes matching any pattern.

        A pattern is a gesture (``wave``), a take (``wave/own/trial_3``) or a gesture and a trial
        (``wave/trial_3``).

        Raises
        ------
        LibraryError
            For a pattern that matches no take.
        """
        drop = np.zeros(len(self), dtype=bool)
        for pat in patterns:
            hit = np.array([_matches(pat, lab, name)
                            for lab, name in zip(self.labels, self.names, strict=True)], dtype=bool)
            if not hit.any():
                raise LibraryError(f"--remove {pat}: no such gesture or take (gestures: "
                                   f"{', '.join(self.gestures)})")
            drop |= hit
        keep = np.flatnonzero(~drop)
        rows = self.rows()
        return TakeSet(tuple(self.takes[k] for k in keep), tuple(self.labels[k] for k in keep),
                       tuple(self.names[k] for k in keep), tuple(rows[k] for k in keep))


def _matches(pattern: str, label: str, name: str) -> bool:
    parts = pattern.strip("/").split("/")
    if len(parts) == 1:
        return parts[0] == label
    name_parts = name.split("/")
    return parts[0] == label and name_parts[-len(parts) + 1:] == parts[1:]


def _choose_context(gdir: Path, context: str | None) -> Path:
    found = sorted(p.name for p in gdir.iterdir() if p.is_dir() and not p.name.startswith("."))
    if context is not None:
        if context not in found:
            raise LibraryError(f"{gdir}: no context folder {context!r} (found: {', '.join(found) or 'none'})")
        return gdir / context
    for pref in _PREFERRED_CONTEXTS:
        if pref in found:
            return gdir / pref
    if len(found) == 1:
        return gdir / found[0]
    raise LibraryError(f"{gdir}: several context folders ({', '.join(found) or 'none'}); "
                       "choose one with --context")


def read_takes(folder: str | Path, context: str | None = None) -> TakeSet:
    """Takes of a library folder laid out as ``<folder>/<gesture>/<context>/<trial>.csv``.

    Parameters
    ----------
    folder : str or Path
        The library folder (``framefree record`` writes it; a dataset such as the HPM replica has
        the same layout).
    context : str, optional
        Context folder to read in every gesture. Default: ``own`` if present, else ``original_1``
        if present, else the gesture's only context folder.

    Returns
    -------
    TakeSet

    Raises
    ------
    LibraryError
        For a missing folder, a gesture without takes, or ambiguous contexts.
    DatasetError
        For a malformed CSV file (naming the file and row).
    """
    root = Path(folder).expanduser()
    if not root.is_dir():
        raise LibraryError(f"{root}: no such library folder "
                           "(expected <folder>/<gesture>/<context>/<trial>.csv)")
    takes: list[Trajectory] = []
    labels: list[str] = []
    names: list[str] = []
    for gdir in sorted(p for p in root.iterdir() if p.is_dir() and p.name not in ("streams",)
                       and not p.name.startswith(".")):
        cdir = _choose_context(gdir, context)
        files = sorted(cdir.glob("*.csv"), key=lambda f: _natural(f.stem))
        if not files:
            raise LibraryError(f"{cdir}: no takes (*.csv)")
        for f in files:
            try:
                takes.append(Trajectory.from_csv(f))
            except FramefreeError as exc:
                raise DatasetError(f"bad take: {exc}") from exc
            labels.append(gdir.name)
            names.append(f"{gdir.name}/{cdir.name}/{f.stem}")
    if not takes:
        raise LibraryError(f"{root}: no gesture folders with takes")
    return TakeSet(tuple(takes), tuple(labels), tuple(names))


def combine_takes(parts: Sequence[tuple[str, TakeSet]], merge: Iterable[str] = ()) -> TakeSet:
    """The takes of several sources as one vocabulary, refusing what would corrupt it.

    Parameters
    ----------
    parts : sequence of (str, TakeSet)
        Each source (a folder or library file, for messages) and its takes.
    merge : iterable of str
        Gestures whose takes may come from several sources (e.g. a second person's takes of the
        same gesture); any other gesture name found in two sources is an error.

    Raises
    ------
    LibraryError
        When two sources hold a gesture of the same name that was not named in ``merge`` (two
        different gestures would silently become one).
    """
    allowed = set(merge)
    owner: dict[str, str] = {}
    for source, part in parts:
        for g in part.gestures:
            if g in owner and owner[g] != source and g not in allowed:
                raise LibraryError(
                    f"gesture {g!r} is in both {owner[g]} and {source}: rename one of the folders if "
                    f"they are different gestures, or add --merge {g} to pool their takes")
            owner.setdefault(g, source)
    takes = parts[0][1]
    for _, part in parts[1:]:
        takes = takes + part
    return takes


def refuse_copies(takes: TakeSet) -> None:
    """Raise :class:`LibraryError` if a take is an exact copy of another (the same samples, at any
    time offset): leave-one-out calibration would put its gesture's threshold at about zero."""
    seen: dict[bytes, str] = {}
    for name, rows in zip(takes.names, takes.rows(), strict=True):
        key = hashlib.sha256(np.ascontiguousarray(rows[:, 1:]).tobytes()).digest()
        if key in seen:
            raise LibraryError(f"take {name} is an exact copy of take {seen[key]}: remove one "
                               f"(--remove {name}); a copied take makes its gesture's threshold "
                               "meaningless")
        seen[key] = name


def _natural(name: str) -> list:
    import re

    return [int(s) if s.isdigit() else s for s in re.split(r"(\d+)", name)]


def fingerprint(takes: TakeSet, settings: dict[str, Any]) -> str:
    """SHA-256 (hex) of the takes (their stored rows), labels, names, settings and format version."""
    h = hashlib.sha256()
    h.update(json.dumps({"format": FORMAT_VERSION, "labels": list(takes.labels), "names": list(takes.names),
                         "settings": settings}, sort_keys=True).encode())
    for rows in takes.rows():
        h.update(np.ascontiguousarray(rows).tobytes())
    return h.hexdigest()


def build_recognizer(
    takes: Sequence[Trajectory],
    labels: Sequence[str],
    config: RecognizerConfig,
    gesture_thresholds: dict[str, float],
) -> Recognizer:
    """A recognizer over models rebuilt from ``takes``, with the given thresholds (no calibration);
    see :meth:`~framefree.online.Recognizer.restore`."""
    return Recognizer.restore(takes, labels, config, gesture_thresholds)


@dataclass(frozen=True)
class GestureLibrary:
    """A vocabulary ready to go live: takes, settings and the calibrated thresholds.

    Build one with :func:`enroll`, write it with :meth:`save`, read it with :func:`load_library`,
    and start recognizing with :meth:`recognizer` (no recalibration).

    Attributes
    ----------
    takes : TakeSet
        The takes the models are built from.
    settings : dict
        The :class:`~framefree.online.RecognizerConfig` fields asked for at enrolment (``None``
        where calibration chooses).
    config : dict
        The configuration in use (``RecognizerConfig.to_dict``), with the calibrated values.
    gesture_thresholds : dict of str to float
        Decision threshold τ_g of each gesture.
    stop_threshold : float
        Stop-detector threshold on ``|q̇|`` [1/s].
    calibration : dict or None
        Summary of the calibration (for reports).
    built_from : tuple of str
        Folders and library files the takes came from.
    framefree_version : str
    format_version : int
    created : str
        UTC time of the enrolment (ISO 8601).
    """

    takes: TakeSet
    settings: dict[str, Any]
    config: dict[str, Any]
    gesture_thresholds: dict[str, float]
    stop_threshold: float
    calibration: dict[str, Any] | None = None
    built_from: tuple[str, ...] = ()
    framefree_version: str = __version__
    format_version: int = FORMAT_VERSION
    created: str = field(default_factory=lambda: _now())

    @property
    def gestures(self) -> list[str]:
        """Gesture labels in first-appearance order."""
        return self.takes.gestures

    @property
    def fingerprint(self) -> str:
        """SHA-256 of the takes and settings (equal fingerprints need no new calibration)."""
        return fingerprint(self.takes, self.settings)

    def recognizer_config(self) -> RecognizerConfig:
        """The stored configuration as a :class:`~framefree.online.RecognizerConfig` (a library
        saved before the ``align`` setting existed was calibrated with the singular values, one
        saved before ``gesture_pauses`` existed keeps the pause limits common to all gestures)."""
        old = {"align": "singular", "gesture_pauses": False}
        return RecognizerConfig.from_dict({**old, **self.config}).replace(
            stop_threshold=self.stop_threshold)

    def recognizer(self) -> Recognizer:
        """A live recognizer: models rebuilt from the takes, thresholds restored (no calibration)."""
        return Recognizer.restore(self.takes.takes, self.takes.labels, self.recognizer_config(),
                                  self.gesture_thresholds)

    def meta(self) -> dict[str, Any]:
        """The JSON member of the library file."""
        return {
            "format_version": self.format_version,
            "framefree_version": self.framefree_version,
            "created": self.created,
            "built_from": list(self.built_from),
            "names": list(self.takes.names),
            "labels": list(self.takes.labels),
            "settings": self.settings,
            "config": self.config,
            "gesture_thresholds": self.gesture_thresholds,
            "stop_threshold": self.stop_threshold,
            "calibration": self.calibration,
            "fingerprint": self.fingerprint,
        }

    def save(self, path: str | Path) -> Path:
        """Write the library file (:mod:`framefree.io.library_file`); parent folders are created."""
        return write_library_file(path, self.meta(), list(self.takes.rows()))

    def summary(self) -> str:
        """One line per gesture: takes, threshold, whether it is performed in one go (no long rest
        at a corner) and, with a known vertical, verticality range."""
        counts = self.takes.counts()
        up = self.config.get("up")
        vertical = (self.config.get("vertical_limits") or {}) if up else {}
        one_go = (self.config.get("one_go") or []) if self.config.get("gesture_pauses") else []
        lines = [f"{len(self.takes)} takes of {len(counts)} gestures, "
                 f"stop above {self.stop_threshold:.3g} rad/s"
                 + (f", up {up} (verticality limits)" if up else "")]
        for g, n in counts.items():
            line = f"  {g:<16} {n:3d} takes  τ = {self.gesture_thresholds.get(g, float('nan')):.4g}"
            if g in one_go:
                line += f"  in one go (rests ≤ {self.config.get('min_pause', 0.5):.2g} s at a corner)"
            if g in vertical:
                line += f"  vertical {vertical[g][0]:.2f}–{vertical[g][1]:.2f}"
            lines.append(line)
        return "\n".join(lines)


def load_library(path: str | Path) -> GestureLibrary:
    """Read a library file written by :meth:`GestureLibrary.save`.

    Raises
    ------
    LibraryError
        When the file is not a library, was written by another format version, or its settings
        do not fit this framefree (the message says how to rebuild it).
    """
    path = Path(path)
    meta, rows = read_library_file(path)
    if meta.get("trackers"):
        raise LibraryError(f"{path}: a gesture library of several trackers; read it with "
                           "framefree.library.multi_library.load_multi_library")
    names, labels = meta["names"], meta["labels"]
    takes = tuple(library_takes(path, rows, names))
    lib = GestureLibrary(
        TakeSet(takes, tuple(labels), tuple(names), tuple(rows)), meta["settings"], meta["config"],
        {str(k): float(v) for k, v in meta["gesture_thresholds"].items()}, float(meta["stop_threshold"]),
        meta.get("calibration"), tuple(meta.get("built_from") or ()), meta.get("framefree_version", "?"),
        int(meta["format_version"]), meta.get("created", ""),
    )
    try:
        lib.recognizer_config()
    except (TypeError, ValueError) as exc:
        raise LibraryError(f"{path}: settings do not fit framefree {__version__} ({exc}); "
                           f"{rebuild_hint(path, meta)}") from None
    return lib


def _as_json(d: dict[str, Any]) -> dict[str, Any]:
    """``d`` as it comes back from the library's JSON (tuples become lists)."""
    return json.loads(json.dumps(d))


def load_recognizer(path: str | Path) -> Recognizer:
    """A live recognizer from a library file, without recalibration (= :meth:`Recognizer.load`)."""
    return Recognizer.load(path)


def enroll(
    takes: TakeSet,
    config: RecognizerConfig | None = None,
    built_from: Sequence[str] = (),
    **overrides: Any,
) -> GestureLibrary:
    """Build the models and calibrate the thresholds once: a library ready to save.

    Parameters
    ----------
    takes : TakeSet
        The vocabulary's takes (:func:`read_takes`, or a loaded library's ``takes``).
    config : RecognizerConfig, optional
        Recognizer settings (default ``RecognizerConfig()``); ``overrides`` replace fields.
        Fields left ``None`` (resolution, thresholds) are calibrated from the takes.
    built_from : sequence of str
        Where the takes came from (stored, and used in rebuild hints).

    Returns
    -------
    GestureLibrary

    Raises
    ------
    LibraryError
        For a vocabulary with a take that is an exact copy of another (:func:`refuse_copies`).

    Notes
    -----
    A gesture of one take is enrolled: its threshold stands on copies of the take made larger
    and smaller (:data:`~framefree.online.thresholds.ONE_TAKE_SIZE`) instead of on other takes.
    What one, two and three takes give on held-out people is measured in docs/library.md.
    """
    refuse_copies(takes)
    config = (config or RecognizerConfig()).replace(**overrides)
    takes = takes.as_stored()
    rec = Recognizer.from_trajectories(list(takes.takes), list(takes.labels), config)
    calib = rec.calibration.summary() if getattr(rec, "calibration", None) is not None else None
    return GestureLibrary(
        takes, _as_json(config.to_dict()), _as_json(rec.config.to_dict()),
        {g: float(v) for g, v in rec.gesture_thresholds.items()},
        float(rec.stop_threshold), calib, tuple(str(s) for s in built_from),
    )
