"""Gesture libraries: the takes of a vocabulary, its recognizer settings and calibrated thresholds,
in one versioned file that starts a recognizer without recalibrating.

Building models from recordings is cheap (0.04 s for the 35 HPM recordings); calibrating the
recognizer is not (about 10 s for the same). So a library stores what is needed to rebuild the
models exactly — the rows of the takes — together with the user's settings
(:class:`~framefree.online.RecognizerConfig`) and everything learned from the takes, with its
provenance (:class:`~framefree.online.learned.LearnedSettings`); loading rebuilds the models and
restores the rest.

The file format is :mod:`framefree.io.library_file`; the takes themselves, read from a folder,
are :mod:`framefree.library.take_set`'s.
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
from ..core.trajectory import Trajectory
from ..io.library_file import (
    FORMAT_VERSION,
    LibraryError,
    library_takes,
    read_library_file,
    write_library_file,
)
from ..online.config import RecognizerConfig
from ..online.learned import GIVEN, LearnedSettings, split_settings
from ..online.library_settings import settings_from_meta
from ..online.recognizer import Recognizer
from .take_set import TakeSet, combine_takes, read_takes, refuse_copies

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


def _now() -> str:
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")


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
    learned: LearnedSettings,
) -> Recognizer:
    """A recognizer over models rebuilt from ``takes``, with the learned values restored (no
    calibration); see :meth:`~framefree.online.Recognizer.restore`."""
    return Recognizer.restore(takes, labels, config, learned)


class StoredSettings:
    """What every gesture library holds beside its takes, read the same way whatever the
    trackers: ``takes``, ``config`` (the user's settings, ``RecognizerConfig.to_dict``) and
    ``learned`` (``LearnedSettings.to_dict``, with provenance), as attributes of the subclass."""

    takes: Any
    config: dict[str, Any]
    learned: dict[str, Any]

    @property
    def gestures(self) -> list[str]:
        """Gesture labels in first-appearance order."""
        return self.takes.gestures

    @property
    def gesture_thresholds(self) -> dict[str, float]:
        """Decision threshold τ_g of each gesture."""
        return {str(g): float(v) for g, v in self.learned["gesture_thresholds"].items()}

    @property
    def stop_threshold(self) -> float:
        """Stop-detector threshold on the windowed angular speed [rad/s]."""
        return float(self.learned["stop_threshold"])

    @property
    def settings(self) -> dict[str, Any]:
        """What was asked for at enrolment: the user's settings and any learned value fixed
        instead of learned (``--set max_units=3``); enrolling again starts from these."""
        rules = self.learned.get("provenance", {}).get("rules", {})
        given = {k: self.learned[k] for k, r in rules.items() if r == GIVEN}
        return {**self.config, **given}

    def recognizer_config(self) -> RecognizerConfig:
        """The user's settings as a :class:`~framefree.online.RecognizerConfig`."""
        return RecognizerConfig.from_dict(self.config)

    def learned_settings(self) -> LearnedSettings:
        """The learned values as :class:`~framefree.online.learned.LearnedSettings`."""
        return LearnedSettings.from_dict(self.learned)


@dataclass(frozen=True)
class GestureLibrary(StoredSettings):
    """A vocabulary ready to go live: takes, the user's settings and what was learned from them.

    Build one with :func:`enroll`, write it with :meth:`save`, read it with :func:`load_library`,
    and start recognizing with :meth:`recognizer` (no recalibration).

    Attributes
    ----------
    takes : TakeSet
        The takes the models are built from.
    config : dict
        The user's settings (``RecognizerConfig.to_dict``: descriptor settings and constants
        nested).
    learned : dict
        Every value learned from the takes, with its provenance (``LearnedSettings.to_dict``).
    calibration : dict or None
        Summary of the calibration (for reports).
    built_from : tuple of str
        Folders and library files the takes came from.
    framefree_version : str
    format_version : int
        The format of the file it was read from (a library of format 3 is migrated on loading).
    created : str
        UTC time of the enrolment (ISO 8601).
    """

    takes: TakeSet
    config: dict[str, Any]
    learned: dict[str, Any]
    calibration: dict[str, Any] | None = None
    built_from: tuple[str, ...] = ()
    framefree_version: str = __version__
    format_version: int = FORMAT_VERSION
    created: str = field(default_factory=lambda: _now())

    @property
    def fingerprint(self) -> str:
        """SHA-256 of the takes and settings (equal fingerprints need no new calibration)."""
        return fingerprint(self.takes, self.settings)

    @property
    def unseparated(self) -> list[str]:
        """Gestures whose calibration found no gap between their takes and non-gesture motion
        (:mod:`framefree.library.separation`), in order; none without a calibration summary."""
        separated = (self.calibration or {}).get("separated") or {}
        return [g for g, ok in separated.items() if not ok]

    def recognizer(self) -> Recognizer:
        """A live recognizer: models rebuilt from the takes, learned values restored (no
        calibration)."""
        return Recognizer.restore(self.takes.takes, self.takes.labels, self.recognizer_config(),
                                  self.learned_settings())

    def meta(self) -> dict[str, Any]:
        """The JSON member of the library file (always the current format)."""
        return {
            "format_version": FORMAT_VERSION,
            "framefree_version": self.framefree_version,
            "created": self.created,
            "built_from": list(self.built_from),
            "names": list(self.takes.names),
            "labels": list(self.takes.labels),
            "config": self.config,
            "learned": self.learned,
            "calibration": self.calibration,
            "fingerprint": self.fingerprint,
        }

    def save(self, path: str | Path) -> Path:
        """Write the library file (:mod:`framefree.io.library_file`); parent folders are created."""
        return write_library_file(path, self.meta(), list(self.takes.rows()))

    def summary(self) -> str:
        """One line per gesture: takes, threshold, whether it is performed in one go (no long rest
        at a corner), with a known vertical its verticality range, whether it never fires, and
        whether it is not apart from non-gesture motion (:attr:`unseparated`)."""
        config, learned = self.recognizer_config(), self.learned_settings()
        counts = self.takes.counts()
        up = config.up
        vertical = (learned.vertical_limits or {}) if up else {}
        one_go = (learned.one_go or []) if config.gesture_pauses else []
        lines = [f"{len(self.takes)} takes of {len(counts)} gestures, "
                 f"stop above {self.stop_threshold:.3g} rad/s"
                 + (f", up {up} (verticality limits)" if up else "")]
        for g, n in counts.items():
            line = f"  {g:<16} {n:3d} takes  τ = {self.gesture_thresholds.get(g, float('nan')):.4g}"
            if g in one_go:
                line += f"  in one go (rests ≤ {config.constants.min_pause:.2g} s at a corner)"
            if g in vertical:
                line += f"  vertical {vertical[g][0]:.2f}–{vertical[g][1]:.2f}"
            if g in (learned.unseen or []):
                line += "  never fires (most takes do not move this tracker)"
            if g in self.unseparated:
                line += "  not apart from other motion (framefree check explains)"
            lines.append(line)
        return "\n".join(lines)


def load_library(path: str | Path) -> GestureLibrary:
    """Read a library file written by :meth:`GestureLibrary.save` (one of format 3 is migrated,
    :mod:`framefree.online.library_settings`).

    Raises
    ------
    LibraryError
        When the file is not a library, was written in a format that is no longer read, or its
        settings do not fit this framefree (one line, saying how to enroll it again).
    """
    path = Path(path)
    meta, rows = read_library_file(path)
    if meta.get("trackers"):
        raise LibraryError(f"{path}: a gesture library of several trackers; read it with "
                           "framefree.library.multi_library.load_multi_library")
    names, labels = meta["names"], meta["labels"]
    takes = tuple(library_takes(path, rows, names))
    config, learned = settings_from_meta(path, meta, rows)
    return GestureLibrary(
        TakeSet(takes, tuple(labels), tuple(names), tuple(rows)), _as_json(config.to_dict()),
        _as_json(learned.to_dict()), meta.get("calibration"), tuple(meta.get("built_from") or ()),
        meta.get("framefree_version", "?"), int(meta["format_version"]), meta.get("created", ""),
    )


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
        The user's settings (default ``RecognizerConfig()``); ``overrides`` change them by
        name (:meth:`~framefree.online.RecognizerConfig.replace`) or fix a learned value
        instead of learning it. Everything else is learned from the takes.
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
    config, given = split_settings(overrides, config)
    takes = takes.as_stored()
    rec = Recognizer.from_trajectories(list(takes.takes), list(takes.labels), config, **given)
    calib = rec.calibration.summary() if getattr(rec, "calibration", None) is not None else None
    return GestureLibrary(takes, _as_json(config.to_dict()), _as_json(rec.learned_.to_dict()),
                          calib, tuple(str(s) for s in built_from))
