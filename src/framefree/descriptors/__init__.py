"""Trajectory descriptors, one module each, all reachable through :func:`get_descriptor`."""

from .base import Descriptor, available_descriptors, get_descriptor, register
from .bilts import BILTS, BILTSPlus
from .dhb import DHB
from .dsrf import DSRF
from .efs import EFS
from .isa import ISA
from .rrv import RRV

__all__ = [
    "BILTS",
    "DHB",
    "DSRF",
    "EFS",
    "ISA",
    "RRV",
    "BILTSPlus",
    "Descriptor",
    "available_descriptors",
    "get_descriptor",
    "register",
]
