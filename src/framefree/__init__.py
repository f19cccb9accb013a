"""framefree: recognize hand-held 6-DoF motion gestures without calibrating any reference frame.

The names below are imported on first use (:pep:`562`), so that ``import framefree`` and the
``framefree`` command start without compiling or loading any kernel they do not need.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from .errors import (
    DatasetError,
    DegenerateMotionError,
    FramefreeError,
    FramefreeWarning,
    TrajectoryError,
)

if TYPE_CHECKING:
    from .classifier import NearestNeighborClassifier
    from .descriptors import Descriptor, available_descriptors, get_descriptor, register
    from .posecsv import PlausibilityWarning
    from .trajectory import Trajectory

__version__ = "0.1.0"

#: public name -> module that defines it
_LAZY = {
    "NearestNeighborClassifier": ".classifier",
    "Descriptor": ".descriptors",
    "available_descriptors": ".descriptors",
    "get_descriptor": ".descriptors",
    "register": ".descriptors",
    "PlausibilityWarning": ".posecsv",
    "Trajectory": ".trajectory",
}

__all__ = [
    "DatasetError",
    "DegenerateMotionError",
    "Descriptor",
    "FramefreeError",
    "FramefreeWarning",
    "NearestNeighborClassifier",
    "PlausibilityWarning",
    "Trajectory",
    "TrajectoryError",
    "__version__",
    "available_descriptors",
    "get_descriptor",
    "register",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'framefree' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
