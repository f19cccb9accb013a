"""Trajectory descriptors, one module each, all reachable through :func:`get_descriptor`."""

from .base import Descriptor, available_descriptors, get_descriptor, register
from .bilts import BILTS, BILTSPlus

__all__ = [
    "BILTS",
    "BILTSPlus",
    "Descriptor",
    "available_descriptors",
    "get_descriptor",
    "register",
]
