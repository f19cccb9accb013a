"""The recognizer of the replica's ``original_1`` takes with the default settings, calibrated
once per test process.

Many test modules need exactly this recognizer; each used to calibrate its own (about 9 s each:
12 of the suite's 162 calibrations, 113 of their 443 s, session 39). :func:`replica_recognizer`
calibrates once and builds every further copy from the calibrated settings and learned values,
as loading a library file does (``Recognizer.from_trajectories(takes, labels, config,
learned)``, the same decisions: tests/library/test_store.py). A test that needs the calibration
itself (``Recognizer.calibration``) builds its own.
"""

from __future__ import annotations

from functools import cache

from framefree.datasets.layout import load_model_recordings
from framefree.online import Recognizer
from framefree.replica import replica_path


@cache
def _calibrated() -> tuple:
    takes, labels = load_model_recordings(replica_path(0), "original_1")
    rec = Recognizer.from_trajectories(takes, labels)
    return takes, labels, rec.config, rec.learned_


def replica_recognizer() -> Recognizer:
    """A new recognizer (its own state) of the replica's takes, default settings."""
    takes, labels, config, learned = _calibrated()
    return Recognizer.from_trajectories(takes, labels, config, learned)
