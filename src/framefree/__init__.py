"""framefree: recognize hand-held 6-DoF motion gestures without calibrating any reference frame.

The names below are imported on first use (:pep:`562`), so that ``import framefree`` and the
``framefree`` command start without compiling or loading any kernel they do not need.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._lazy import lazy_attributes
from ._version import __version__
from .errors import (
    DatasetError,
    DegenerateMotionError,
    FramefreeError,
    FramefreeWarning,
    TrajectoryError,
)

if TYPE_CHECKING:
    from .classifier import NearestNeighborClassifier
    from .core.posecsv import PlausibilityWarning
    from .core.trajectory import Trajectory
    from .descriptors import Descriptor, available_descriptors, get_descriptor, register


#: public name -> module that defines it
_LAZY = {
    "NearestNeighborClassifier": ".classifier",
    "Descriptor": ".descriptors",
    "available_descriptors": ".descriptors",
    "get_descriptor": ".descriptors",
    "register": ".descriptors",
    "PlausibilityWarning": ".core.posecsv",
    "Trajectory": ".core.trajectory",
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


__getattr__, __dir__ = lazy_attributes(__name__, globals(), _LAZY)
