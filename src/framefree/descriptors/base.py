"""The descriptor protocol and the registry every descriptor module adds itself to.

A descriptor turns a :class:`~framefree.Trajectory` into a sequence of feature vectors (time
leading, shape (K, F)) and defines the distance its 1-NN classifier uses between a model sequence and
a query sequence. To add a descriptor, subclass :class:`Descriptor`, set ``name``, implement
``compute`` and ``distance_matrix`` (or ``distance``), and decorate the class with
:func:`register`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from ..progress import PROGRESS_TYPES
from ..trajectory import Trajectory

__all__ = ["Descriptor", "available_descriptors", "get_descriptor", "register"]

_REGISTRY: dict[str, type[Descriptor]] = {}


def register(cls: type[Descriptor]) -> type[Descriptor]:
    """Class decorator: make ``cls`` available to :func:`get_descriptor` under ``cls.name``."""
    key = cls.name.lower()
    if key in _REGISTRY and _REGISTRY[key] is not cls:
        raise ValueError(f"a descriptor named {cls.name!r} is already registered")
    _REGISTRY[key] = cls
    return cls


def available_descriptors() -> list[str]:
    """Names of all registered descriptors."""
    return sorted(_REGISTRY)


def get_descriptor(name: str, **params: Any) -> Descriptor:
    """Instantiate a registered descriptor by name, e.g. ``get_descriptor("bilts+", L=0.3)``.

    Parameters
    ----------
    name : str
        Registered name (case-insensitive), see :func:`available_descriptors`.
    **params
        Constructor parameters of that descriptor (``progress``, ``L``, ...).
    """
    try:
        cls = _REGISTRY[name.lower()]
    except KeyError:
        raise ValueError(
            f"unknown descriptor {name!r}; available: {', '.join(available_descriptors())}"
        ) from None
    return cls(**params)


class Descriptor(ABC):
    """A frame-invariant (or not) trajectory descriptor with its classifier distance.

    Subclasses store their constructor arguments unchanged as attributes (scikit-learn style) and
    list them in ``param_names``.
    """

    #: registry name
    name: ClassVar[str]
    #: progress types this descriptor supports
    progress_types: ClassVar[tuple[str, ...]] = PROGRESS_TYPES
    #: names of the constructor parameters, in order
    param_names: ClassVar[tuple[str, ...]] = ("progress",)

    def _check_progress(self, progress: str) -> str:
        if progress not in self.progress_types:
            raise ValueError(
                f"{self.name} supports progress types {self.progress_types}, not {progress!r}"
            )
        return progress

    @property
    def params(self) -> dict[str, Any]:
        """The constructor parameters as a dict."""
        return {k: getattr(self, k) for k in self.param_names}

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"get_descriptor({self.name!r}, {args})"

    def with_params(self, **changes: Any) -> Descriptor:
        """A copy with some parameters changed."""
        return type(self)(**{**self.params, **changes})

    @abstractmethod
    def compute(self, traj: Trajectory) -> np.ndarray:
        """Descriptor sequence of a trajectory, shape (K, F), time (progress) leading."""

    def distance(self, model: np.ndarray, query: np.ndarray) -> float:
        """Classifier distance between a model sequence and a query sequence (both (K, F))."""
        return float(self.distance_matrix([query], [model])[0, 0])

    @abstractmethod
    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """Distances (n_queries, n_models) between descriptor sequences."""
