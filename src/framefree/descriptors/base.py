"""The descriptor contract and the registry every descriptor module adds itself to.

A descriptor turns a :class:`~framefree.Trajectory` into a sequence of feature vectors (time
leading, shape (K, F)) and defines the distance its 1-NN classifier uses between a model sequence
and a query sequence. Everything the classifier and the benchmark need to know about a descriptor
is declared here, on :class:`Descriptor`, and nowhere else:

==========================  ===========================================================================
``name``                    registry name (``get_descriptor(name)``, ``--methods name:progress``)
``display_name``            name as printed in Table I
``scope``                   ``"local"`` (a feature vector per progress sample) or ``"global"``
                            (features in one frame fitted to the whole motion)
``progress_types``          progress types it accepts
``param_names``             constructor arguments, stored unchanged (scikit-learn style)
``trained_parameter``       the constructor argument the benchmark grid-searches besides ``L``
                            (``"lam"``, ``"ds_scale"``) or None; its values: :meth:`parameter_grid`
:meth:`trains_scale_length`  whether ``L`` is searched for a progress type
``shares_representation``   whether :meth:`representation` does not depend on the trained
                            parameter (it only weights the result), so a grid search computes the
                            representation once per trial and calls :meth:`weight` per grid point
``supports_open_end``       whether the constructor takes ``open_end`` (open-end alignment)
:meth:`alignment_columns`,   how the distance aligns two sequences (for figures): the columns DTW
:meth:`prealign`            aligns on, and the model as compared with a query
:meth:`compute`             descriptor of a trajectory
:meth:`from_reparameterized`  descriptor of poses already at equidistant progress (the benchmark's
                            cached input), given the 50 Hz arclength for global descriptors
:meth:`distance_matrix`     classifier distances between descriptor sequences
:meth:`distance_spec`       how the distance is computed, for exact pruned search
                            (:mod:`framefree.core.pruning`); None: no pruning
==========================  ===========================================================================

To add a descriptor: one module with a :class:`Descriptor` subclass decorated with :func:`register`,
imported in ``framefree/descriptors/__init__.py``, and its tests. The shared contract test
(``tests/descriptors/test_contract.py``) then checks it together with every other registered
descriptor, and ``framefree benchmark --methods <name>:<progress>`` runs it through the protocol.
The maths: ``docs/algorithms/descriptors.md``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from ..core.progress import PROGRESS_TYPES
from ..core.pruning import DistanceSpec
from ..core.trajectory import Trajectory

__all__ = [
    "L_GRID",
    "SCOPES",
    "Descriptor",
    "available_descriptors",
    "descriptor_class",
    "get_descriptor",
    "register",
]

_REGISTRY: dict[str, type[Descriptor]] = {}


def register(cls: type[Descriptor]) -> type[Descriptor]:
    """Class decorator: make ``cls`` available to :func:`get_descriptor` under ``cls.name``."""
    key = cls.name.lower()
    if cls.scope not in SCOPES:
        raise ValueError(f"{cls.name}: scope must be one of {SCOPES}, not {cls.scope!r}")
    if key in _REGISTRY and _REGISTRY[key] is not cls:
        raise ValueError(f"a descriptor named {cls.name!r} is already registered")
    _REGISTRY[key] = cls
    return cls


def available_descriptors() -> list[str]:
    """Names of all registered descriptors."""
    return sorted(_REGISTRY)


def descriptor_class(name: str) -> type[Descriptor]:
    """The registered class of ``name`` (case-insensitive).

    Raises
    ------
    ValueError
        If no descriptor of that name is registered.
    """
    try:
        return _REGISTRY[name.lower()]
    except KeyError:
        raise ValueError(
            f"unknown descriptor {name!r}; available: {', '.join(available_descriptors())}"
        ) from None


def get_descriptor(name: str, **params: Any) -> Descriptor:
    """Instantiate a registered descriptor by name, e.g. ``get_descriptor("bilts+", L=0.3)``.

    Parameters
    ----------
    name : str
        Registered name (case-insensitive), see :func:`available_descriptors`.
    **params
        Constructor parameters of that descriptor (``progress``, ``L``, ...).
    """
    return descriptor_class(name)(**params)


#: the two descriptor scopes
SCOPES = ("local", "global")
#: scale lengths L [m] searched for every descriptor that trains L (``linspace(0.1, 0.9, 5)``,
#: the reference's grid)
L_GRID: tuple[float, ...] = (0.1, 0.3, 0.5, 0.7, 0.9)


class Descriptor(ABC):
    """A frame-invariant (or not) trajectory descriptor with its classifier distance.

    Subclasses store their constructor arguments unchanged as attributes (scikit-learn style) and
    list them in ``param_names``. See the module docstring for the whole contract.
    """

    #: registry name
    name: ClassVar[str]
    #: name as printed in Table I (default: ``name``)
    display_name: ClassVar[str | None] = None
    #: ``"local"`` or ``"global"``
    scope: ClassVar[str] = "local"
    #: constructor argument searched by the benchmark besides L (None: only L, if anything)
    trained_parameter: ClassVar[str | None] = None
    #: whether the trained parameter only weights a representation computed without it
    shares_representation: ClassVar[bool] = False
    #: whether the constructor takes ``open_end`` (align the query with a prefix of the model)
    supports_open_end: ClassVar[bool] = False
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

    @classmethod
    def label(cls) -> str:
        """Display name (``display_name``, else ``name``)."""
        return cls.display_name or cls.name

    @classmethod
    def parameter_grid(cls, progress: str) -> tuple[float, ...]:
        """Values of :attr:`trained_parameter` searched with this progress type (empty: none)."""
        return ()

    @classmethod
    def trains_scale_length(cls, progress: str) -> bool:
        """Whether the scale length ``L`` is searched with this progress type."""
        return True

    @classmethod
    def scale_length_grid(cls, progress: str) -> tuple[float, ...]:
        """Values of ``L`` [m] searched with this progress type (empty: L is not trained)."""
        return L_GRID if cls.trains_scale_length(progress) else ()

    @abstractmethod
    def compute(self, traj: Trajectory) -> np.ndarray:
        """Descriptor sequence of a trajectory, shape (K, F), time (progress) leading."""

    @abstractmethod
    def from_reparameterized(
        self, poses: np.ndarray, ds: float, arclength: float | None = None
    ) -> np.ndarray:
        """Descriptor (K, F) of poses (N, 4, 4) already at equidistant progress of this
        descriptor's type (and L) with step ``ds`` [m or rad].

        ``arclength`` is the total arclength [m] of the 50 Hz trajectory the poses were resampled
        from; global descriptors normalize by it, local ones ignore it.
        """

    def alignment_columns(self, n_features: int) -> slice:
        """Feature columns the distance aligns with DTW (default: all ``n_features``)."""
        return slice(0, n_features)

    def prealign(self, model: np.ndarray, query: np.ndarray) -> np.ndarray:
        """The model sequence (K, F) as the distance compares it with ``query`` (default:
        unchanged; DSRF rotates it first)."""
        return model

    def representation(
        self, poses: np.ndarray, ds: float, arclength: float | None = None
    ) -> np.ndarray:
        """The part of :meth:`from_reparameterized` that does not depend on the trained
        parameter when :attr:`shares_representation` is set (default: the descriptor itself)."""
        return self.from_reparameterized(poses, ds, arclength)

    def weight(self, representation: np.ndarray) -> np.ndarray:
        """Descriptor from a :meth:`representation` (default: unchanged)."""
        return representation

    def distance(self, model: np.ndarray, query: np.ndarray) -> float:
        """Classifier distance between a model sequence and a query sequence (both (K, F))."""
        return float(self.distance_matrix([query], [model])[0, 0])

    def distance_spec(self) -> DistanceSpec | None:
        """How :meth:`distance` is computed by :func:`~framefree.core.dtw.path_distance_kernel`,
        so that nearest-neighbour search can prune it exactly (:mod:`framefree.core.pruning`);
        None (the default) when the distance is computed otherwise: no pruning."""
        return None

    @abstractmethod
    def distance_matrix(
        self, queries: Sequence[np.ndarray], models: Sequence[np.ndarray]
    ) -> np.ndarray:
        """Distances (n_queries, n_models) between descriptor sequences."""
