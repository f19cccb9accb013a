"""framefree: recognize hand-held 6-DoF motion gestures without calibrating any reference frame."""

from .classifier import NearestNeighborClassifier
from .descriptors import Descriptor, available_descriptors, get_descriptor, register
from .errors import (
    DatasetError,
    DegenerateMotionError,
    FramefreeError,
    FramefreeWarning,
    TrajectoryError,
)
from .posecsv import PlausibilityWarning
from .trajectory import Trajectory

__version__ = "0.1.0"

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
