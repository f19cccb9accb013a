"""1-nearest-neighbour classification of trajectories with a descriptor's distance
(docs/algorithms/dtw.md)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .descriptors.base import Descriptor, get_descriptor
from .trajectory import Trajectory

__all__ = ["RECOMMENDED", "NearestNeighborClassifier", "round_significant"]

#: The recommended offline configuration (``docs/algorithms/recommended.md``): BILTS+ with
#: screw-path progress, the 50 Hz poses Gaussian-smoothed with a 5-sample window before progress is
#: computed, and open-end alignment (an unfinished query may match the beginning of a model).
#: ``L`` [m] and ``ds_scale`` [m] are the values the benchmark's grid search selects on the
#: training trials of the HPM replica (``framefree benchmark --methods recommended``); retrain them
#: on your own data with the same command.
RECOMMENDED: dict[str, Any] = {
    "descriptor": "bilts+",
    "progress": "screw",
    "presmooth": 5,
    "open_end": True,
    "L": 0.1,
    "ds_scale": 0.06,
}


def round_significant(x: np.ndarray, digits: int) -> np.ndarray:
    """Round to ``digits`` significant digits (emulates the reference's ``csvwrite`` storage,
    docs/algorithms/dtw.md)."""
    x = np.asarray(x, dtype=np.float64)
    with np.errstate(divide="ignore"):
        mag = np.where(x == 0, 0, np.floor(np.log10(np.abs(x))))
    scale = 10.0 ** (digits - 1 - mag)
    return np.round(x * scale) / scale


class NearestNeighborClassifier:
    """1-NN classifier: a query gets the label of the model at the smallest descriptor distance.

    Parameters
    ----------
    descriptor : Descriptor or str
        A descriptor instance, or a registered name (then ``descriptor_params`` are passed on).
    round_digits : int, optional
        Round descriptors to this many significant digits before comparing them, as the reference
        does by storing them with ``csvwrite`` (5). Default: full precision.
    **descriptor_params
        Parameters for :func:`~framefree.get_descriptor` when ``descriptor`` is a name.

    Attributes
    ----------
    models_ : list of ndarray
        Descriptor sequences of the models, set by :meth:`fit`.
    labels_ : ndarray of str, shape (n_models,)
    distances_ : ndarray, shape (n_queries, n_models)
        Distances behind the latest :meth:`predict` call.

    Examples
    --------
    >>> clf = NearestNeighborClassifier("bilts+", L=0.5, ds_scale=0.09)  # doctest: +SKIP
    >>> clf.fit(model_trajectories, model_labels).predict(queries)      # doctest: +SKIP
    """

    def __init__(
        self,
        descriptor: Descriptor | str = "bilts+",
        round_digits: int | None = None,
        **descriptor_params: Any,
    ) -> None:
        if isinstance(descriptor, str):
            descriptor = get_descriptor(descriptor, **descriptor_params)
        elif descriptor_params:
            raise TypeError("descriptor parameters can only be given with a descriptor name")
        self.descriptor = descriptor
        self.round_digits = round_digits

    @classmethod
    def recommended(cls, **overrides: Any) -> NearestNeighborClassifier:
        """The recommended offline recognizer, :data:`RECOMMENDED` (any entry can be overridden).

        Examples
        --------
        >>> clf = NearestNeighborClassifier.recommended()           # doctest: +SKIP
        >>> clf.fit(model_trajectories, model_labels).predict(half_gestures)  # doctest: +SKIP
        """
        params = {**RECOMMENDED, **overrides}
        descriptor = params.pop("descriptor")
        return cls(descriptor, **params)

    def _describe(self, trajectories: Sequence[Trajectory]) -> list[np.ndarray]:
        out = []
        for traj in trajectories:
            d = self.descriptor.compute(traj)
            if self.round_digits is not None:
                d = round_significant(d, self.round_digits)
            out.append(d)
        return out

    def fit(
        self, trajectories: Sequence[Trajectory], labels: Sequence[Any]
    ) -> NearestNeighborClassifier:
        """Compute and store the model descriptors.

        Parameters
        ----------
        trajectories : sequence of Trajectory
            The models (1-NN neighbours).
        labels : sequence
            One label per model.
        """
        return self.fit_descriptors(self._describe(trajectories), labels)

    def fit_descriptors(
        self, descriptors: Sequence[np.ndarray], labels: Sequence[Any]
    ) -> NearestNeighborClassifier:
        """Like :meth:`fit` with precomputed descriptor sequences."""
        if len(descriptors) != len(labels):
            raise ValueError(f"{len(descriptors)} models but {len(labels)} labels")
        if not descriptors:
            raise ValueError("at least one model is needed")
        self.models_ = list(descriptors)
        self.labels_ = np.asarray(labels)
        return self

    def _check_fitted(self) -> None:
        if not hasattr(self, "models_"):
            raise RuntimeError("call fit() before predict()")

    def distance_matrix(self, trajectories: Sequence[Trajectory]) -> np.ndarray:
        """Distances (n_queries, n_models) from each query trajectory to each model."""
        self._check_fitted()
        return self.descriptor.distance_matrix(self._describe(trajectories), self.models_)

    def predict(self, trajectories: Sequence[Trajectory]) -> np.ndarray:
        """Labels of the nearest models (ties: the first model in fit order, as the reference)."""
        self._check_fitted()
        return self.predict_descriptors(self._describe(trajectories))

    def predict_descriptors(self, descriptors: Sequence[np.ndarray]) -> np.ndarray:
        """Like :meth:`predict` with precomputed descriptor sequences."""
        self._check_fitted()
        self.distances_ = self.descriptor.distance_matrix(list(descriptors), self.models_)
        self.nearest_ = np.argmin(self.distances_, axis=1)
        return self.labels_[self.nearest_]

    def score(self, trajectories: Sequence[Trajectory], labels: Sequence[Any]) -> float:
        """Recognition ratio (fraction of queries given their true label)."""
        pred = self.predict(trajectories)
        return float(np.mean(pred == np.asarray(labels)))
