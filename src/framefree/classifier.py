"""1-nearest-neighbour classification of trajectories with a descriptor's distance
(docs/algorithms/dtw.md)."""

from __future__ import annotations

import inspect
from collections.abc import Sequence
from typing import Any

import numpy as np

from .core.multitrajectory import MultiTrajectory
from .core.pruning import ModelBank, pruned_nearest
from .core.trajectory import Trajectory
from .descriptors.base import Descriptor, get_descriptor
from .descriptors.canonical import INVARIANCES, CanonicalPath
from .rejection import REJECTED, thresholds_from_models
from .samples import as_samples, not_fitted_error

__all__ = ["PRESETS", "RECOMMENDED", "NearestNeighborClassifier", "round_significant"]

#: The recommended offline configuration (``docs/algorithms/recommended.md``): BILTS+ with
#: screw-path progress, the 50 Hz poses Gaussian-smoothed with a 5-sample window before progress is
#: computed, open-end alignment (an unfinished query may match the beginning of a model) and the
#: axis prior (a rotation about a nearly fixed axis gets a frame origin placed by the motion's
#: geometry, not by noise; docs/algorithms/bilts.md#axis-prior).
#: ``L`` [m] and ``ds_scale`` [m] are the values the benchmark's grid search selects on the
#: training trials of the HPM replica (``framefree benchmark --methods recommended``); retrain them
#: on your own data with the same command.
RECOMMENDED: dict[str, Any] = {
    "descriptor": "bilts+",
    "progress": "screw",
    "presmooth": 5,
    "open_end": True,
    "axis_prior": 1.0,
    "L": 0.1,
    "ds_scale": 0.06,
}


#: What a classifier's unset (``None``) descriptor parameters become, per ``preset``, when its
#: descriptor is given by the preset's name: ``"recommended"`` (the default) fills them from
#: :data:`RECOMMENDED`; ``"paper"`` leaves every one to the descriptor's own defaults, the settings
#: of the paper's Table I rows (screw progress, L = 0.5 m, ds_scale = 0.09 m for BILTS+).
PRESETS: dict[str, dict[str, Any]] = {"recommended": RECOMMENDED, "paper": {}}


def round_significant(x: np.ndarray, digits: int) -> np.ndarray:
    """Round to ``digits`` significant digits (emulates the reference's ``csvwrite`` storage,
    docs/algorithms/dtw.md)."""
    x = np.asarray(x, dtype=np.float64)
    with np.errstate(divide="ignore"):
        mag = np.where(x == 0, 0, np.floor(np.log10(np.abs(x))))
    scale = 10.0 ** (digits - 1 - mag)
    return np.round(x * scale) / scale


#: constructor parameters that are passed on to the descriptor when set (``None``: its default)
_DESCRIPTOR_PARAMS = ("progress", "L", "ds_scale", "lam", "presmooth", "open_end", "axis_prior")


#: what several trackers are compared by at each invariance level (:class:`CanonicalPath`
#: options), chosen with the nested leave-two-people-out protocol of
#: ``benchmarks/real_people_protocol.py`` on the six Vive people: what the inner choice took in
#: most of the 15 folds (docs/real-people.md). ``full`` adds the positions in the controllers'
#: mean starting orientation; ``gravity`` keeps positions only.
MULTI_TRACKER_PATHS: dict[str, dict[str, Any]] = {
    "full": {"start_frame": True},
    "gravity": {},
}


def canonical_comparison(
    invariance: str, samples: Sequence[Trajectory | MultiTrajectory]
) -> CanonicalPath | None:
    """The canonical-path comparison an invariance level needs for these samples, or None when
    the descriptor itself serves (``"full"`` with single trajectories). Samples of two or more
    trackers get :data:`MULTI_TRACKER_PATHS`; one tracker, positions only."""
    if invariance not in INVARIANCES:
        raise ValueError(f"unknown invariance {invariance!r}; choose one of {', '.join(INVARIANCES)}")
    if invariance == "full" and not any(isinstance(s, MultiTrajectory) for s in samples):
        return None
    several = bool(samples) and all(isinstance(s, MultiTrajectory) and s.n_trackers > 1 for s in samples)
    return CanonicalPath(invariance, **(MULTI_TRACKER_PATHS[invariance] if several else {}))


class NearestNeighborClassifier:
    """1-NN classifier: a query gets the label of the model at the smallest descriptor distance.

    A scikit-learn estimator: the constructor only stores its arguments, :meth:`fit` builds the
    descriptor from them (``descriptor_``) and stores the fitted state in attributes ending in
    ``_``; :meth:`get_params` / :meth:`set_params` make ``clone``, ``cross_val_score``,
    ``GridSearchCV`` (e.g. over ``L`` and ``ds_scale``) and ``Pipeline`` work. Samples are
    :class:`~framefree.Trajectory` objects (``X`` is a list of them), targets their labels.

    The defaults are the best general choice: the bare ``NearestNeighborClassifier()`` is
    :meth:`recommended` (BILTS+ with screw-path progress, pre-smoothing, open end and the axis
    prior; 97-100 % on the replica's test trials and on moved world frames, where the paper's
    settings score about 70 %). The paper's settings are one option away: ``preset="paper"`` or
    :meth:`paper`.

    Parameters
    ----------
    descriptor : str or Descriptor, default "bilts+"
        A registered descriptor name (see :func:`~framefree.available_descriptors`) or a
        descriptor instance; the parameters below that are set override its own.
    preset : {"recommended", "paper"}, default "recommended"
        Where the descriptor parameters left ``None`` come from when ``descriptor`` is the name
        ``"bilts+"``: ``"recommended"``, :data:`RECOMMENDED`; ``"paper"``, the descriptor's own
        defaults (the paper's Table I settings). Another descriptor, a descriptor instance, or
        another ``progress`` than the preset's always keeps the descriptor's own defaults.
    progress : {"screw", "angle", "arclength"}, optional
        Geometric progress the trajectories are resampled by (``None``: the preset's value).
    L : float, optional
        Scale length L [m] (``None``: the descriptor's default).
    ds_scale : float, optional
        BILTS window scale [m, or rad for angle progress] (``None``: the descriptor's default).
    lam : float, optional
        λ weight of DHB, eFS and ISA (``None``: the descriptor's default).
    presmooth : int, optional
        Gaussian pre-smoothing window of the 50 Hz poses [samples], for descriptors that offer it.
    open_end : bool, optional
        Open-end alignment (an unfinished query may match the beginning of a model), for
        descriptors that offer it (``supports_open_end``: BILTS, BILTS+); ``None``: their default
        (closed end). See ``docs/algorithms/dtw.md``.
    axis_prior : float, optional
        BILTS+ only: weight κ of the prior on the frame origin along a nearly fixed screw axis
        (``None``: the descriptor's default, 0, the reference). See
        ``docs/algorithms/bilts.md#axis-prior``.
    round_digits : int, optional
        Round descriptors to this many significant digits before comparing them, as the reference
        does by storing them with ``csvwrite`` (5). Default: full precision.
    descriptor_params : dict, optional
        Further constructor parameters of the descriptor (e.g. ``{"n_samples": 100}``).
    invariance : {"full", "gravity"}, default "full"
        What a change of the tracking system may not change. ``"full"``: any change of world and
        body frame — single trajectories are compared with the descriptor (the paper's
        bi-invariance), samples of several trackers
        (:class:`~framefree.core.multitrajectory.MultiTrajectory`) by their canonical paths.
        ``"gravity"``: translations and turns about the vertical only, which keeps up and down
        apart (canonical paths, :mod:`framefree.descriptors.canonical`; docs/real-people.md).
        With two or more trackers the paths carry more than positions
        (:data:`MULTI_TRACKER_PATHS`): under ``"full"`` they then also depend on how a
        controller is held, as the controllers' starting orientation is part of the frame.

    Attributes
    ----------
    descriptor_ : Descriptor
        The descriptor built by :meth:`fit` from the parameters above.
    path_ : CanonicalPath or None
        What the samples are compared by instead of the descriptor (``invariance="gravity"``, or
        samples of several trackers), else None.
    models_ : list of ndarray, each (K_j, F)
        Descriptor sequences of the models.
    labels_ : ndarray, shape (n_models,)
        Label of each model, in fit order.
    classes_ : ndarray, shape (n_classes,)
        The distinct labels, sorted.
    thresholds_ : dict of label to float or None
        The rejection threshold of each class (None without ``thresholds``).

    Notes
    -----
    Samples are :class:`~framefree.Trajectory` or
    :class:`~framefree.core.multitrajectory.MultiTrajectory` objects, ``(n, 8)`` arrays
    ``t, x, y, z, qw, qx, qy, qz``, or tuples of such arrays (several trackers): see
    :func:`framefree.samples.as_samples`. Predicting changes no state; distances come from
    :meth:`distance_matrix`, :meth:`kneighbors` and :meth:`decision_function`.

    Examples
    --------
    >>> clf = NearestNeighborClassifier("bilts+", L=0.5, ds_scale=0.09)  # doctest: +SKIP
    >>> clf.fit(model_trajectories, model_labels).predict(queries)      # doctest: +SKIP
    """

    def __init__(
        self,
        descriptor: Descriptor | str = "bilts+",
        progress: str | None = None,
        L: float | None = None,
        ds_scale: float | None = None,
        lam: float | None = None,
        presmooth: int | None = None,
        open_end: bool | None = None,
        axis_prior: float | None = None,
        round_digits: int | None = None,
        descriptor_params: dict[str, Any] | None = None,
        invariance: str = "full",
        prune: bool = False,
        thresholds: str | dict[str, float] | None = None,
        rejection_label: str = REJECTED,
        preset: str = "recommended",
    ) -> None:
        self.descriptor = descriptor
        self.preset = preset
        self.progress = progress
        self.L = L
        self.ds_scale = ds_scale
        self.lam = lam
        self.presmooth = presmooth
        self.open_end = open_end
        self.axis_prior = axis_prior
        self.round_digits = round_digits
        self.descriptor_params = descriptor_params
        self.invariance = invariance
        self.prune = prune
        self.thresholds = thresholds
        self.rejection_label = rejection_label

    # ------------------------------------------------------------------ scikit-learn protocol
    @classmethod
    def _get_param_names(cls) -> list[str]:
        sig = inspect.signature(cls.__init__)
        return [name for name in sig.parameters if name != "self"]

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The constructor parameters, as given (``deep`` is accepted for scikit-learn)."""
        return {name: getattr(self, name) for name in self._get_param_names()}

    def set_params(self, **params: Any) -> NearestNeighborClassifier:
        """Set constructor parameters (takes effect at the next :meth:`fit`); returns ``self``."""
        valid = self._get_param_names()
        for name, value in params.items():
            if name not in valid:
                raise ValueError(
                    f"invalid parameter {name!r} for NearestNeighborClassifier; "
                    f"valid: {', '.join(valid)}"
                )
            setattr(self, name, value)
        return self

    def __sklearn_tags__(self) -> Any:
        """scikit-learn's estimator tags: a classifier of non-tabular samples (trajectories)."""
        from sklearn.utils import ClassifierTags, InputTags, Tags, TargetTags

        return Tags(
            estimator_type="classifier",
            target_tags=TargetTags(required=True),
            classifier_tags=ClassifierTags(),
            input_tags=InputTags(two_d_array=False, dict=False),
            no_validation=True,
        )

    def __sklearn_is_fitted__(self) -> bool:
        """Whether :meth:`fit` has run (for scikit-learn's ``check_is_fitted``)."""
        return hasattr(self, "models_")

    def __repr__(self) -> str:
        init = inspect.signature(type(self).__init__).parameters
        changed = [
            f"{k}={v!r}"
            for k, v in self.get_params().items()
            if not (v is init[k].default or (isinstance(v, str) and v == init[k].default))
        ]
        return f"{type(self).__name__}({', '.join(changed)})"

    # ------------------------------------------------------------------------------- fitting
    def build_descriptor(self) -> Descriptor:
        """The descriptor the current parameters describe (what :meth:`fit` uses)."""
        if self.preset not in PRESETS:
            raise ValueError(f"unknown preset {self.preset!r}; choose one of {', '.join(PRESETS)}")
        preset = dict(PRESETS[self.preset])
        named = preset.pop("descriptor", None)
        same = isinstance(self.descriptor, str) and self.descriptor == named
        # the preset's values belong to its progress (ds_scale is in metres for screw progress)
        same = same and self.progress in (None, preset.get("progress"))
        params = dict(preset) if same else {}
        params.update(self.descriptor_params or {})
        params.update(
            {k: getattr(self, k) for k in _DESCRIPTOR_PARAMS if getattr(self, k) is not None}
        )
        if isinstance(self.descriptor, Descriptor):
            return self.descriptor.with_params(**params) if params else self.descriptor
        return get_descriptor(self.descriptor, **params)

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

    @classmethod
    def paper(cls, **overrides: Any) -> NearestNeighborClassifier:
        """BILTS+ with the paper's settings (``preset="paper"``: the descriptor's own defaults,
        screw progress, L = 0.5 m, ds_scale = 0.09 m); any parameter can be given.

        Examples
        --------
        >>> clf = NearestNeighborClassifier.paper(round_digits=5)   # doctest: +SKIP
        """
        return cls(**{"descriptor": "bilts+", "preset": "paper", **overrides})

    def _describe(self, trajectories: Sequence[Trajectory | MultiTrajectory]) -> list[np.ndarray]:
        out = []
        for traj in trajectories:
            d = self._comparison().compute(traj)
            if self.round_digits is not None:
                d = round_significant(d, self.round_digits)
            out.append(d)
        return out

    def fit(self, X: Any, y: Sequence[Any]) -> NearestNeighborClassifier:
        """Build the descriptor and compute and store the model descriptors.

        Parameters
        ----------
        X : sequence of samples, length n_models
            The models (1-NN neighbours): :class:`~framefree.Trajectory` or
            :class:`~framefree.core.multitrajectory.MultiTrajectory` objects, ``(n, 8)`` arrays
            ``t, x, y, z, qw, qx, qy, qz``, or tuples of such arrays (one per tracker).
        y : sequence, length n_models
            One label per model.
        """
        samples = as_samples(X)
        if len(samples) != len(y):
            raise ValueError(f"{len(samples)} models but {len(y)} labels")
        self.descriptor_ = self.build_descriptor()
        self.path_ = canonical_comparison(self.invariance, samples)
        return self._store(self._describe(samples), y)

    def fit_descriptors(
        self, descriptors: Sequence[np.ndarray], labels: Sequence[Any]
    ) -> NearestNeighborClassifier:
        """Like :meth:`fit` with precomputed descriptor sequences (of :meth:`build_descriptor`)."""
        self.descriptor_ = self.build_descriptor()
        self.path_ = None
        return self._store(list(descriptors), labels)

    def _store(self, descriptors: list[np.ndarray], labels: Sequence[Any]) -> NearestNeighborClassifier:
        if len(descriptors) != len(labels):
            raise ValueError(f"{len(descriptors)} models but {len(labels)} labels")
        if not descriptors:
            raise ValueError("at least one model is needed")
        self.models_ = descriptors
        self._bank_cache = None
        self.labels_ = np.asarray(labels)
        self.classes_ = np.unique(self.labels_)
        self.thresholds_ = self._thresholds()
        return self

    def _thresholds(self) -> dict[str, float] | None:
        if self.thresholds is None:
            return None
        if isinstance(self.thresholds, str):
            if self.thresholds != "auto":
                raise ValueError(f"thresholds must be None, 'auto' or a dict, not {self.thresholds!r}")
            return thresholds_from_models(self._distances(self.models_), self.labels_)
        missing = [c for c in self.classes_ if c not in self.thresholds]
        if missing:
            raise ValueError(f"thresholds has no value for {', '.join(map(str, missing))}")
        return {c: float(self.thresholds[c]) for c in self.classes_}

    def _check_fitted(self) -> None:
        if not hasattr(self, "models_"):
            raise not_fitted_error(self)

    def distance_matrix(self, X: Any) -> np.ndarray:
        """Distances (n_queries, n_models) from each query sample to each model."""
        self._check_fitted()
        return self._distances(self._describe(as_samples(X)))

    def predict(self, X: Any) -> np.ndarray:
        """Label of each query's nearest model, shape (n_queries,) (ties: the first model in fit
        order, as the reference); with ``thresholds``, :data:`~framefree.rejection.REJECTED` for a
        query farther from its nearest model than that class's threshold. Changes no state."""
        self._check_fitted()
        return self.predict_descriptors(self._describe(as_samples(X)))

    def predict_descriptors(self, descriptors: Sequence[np.ndarray]) -> np.ndarray:
        """Like :meth:`predict` with precomputed descriptor sequences."""
        self._check_fitted()
        index, distance = self._nearest(list(descriptors))
        labels = self.labels_[index]
        if self.thresholds_ is None:
            return labels
        keep = np.array([d < self.thresholds_[lab] for lab, d in zip(labels, distance, strict=True)])
        return np.where(keep, labels.astype(object), self.rejection_label)

    def _nearest(self, descriptors: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Index and distance of each query's nearest model (pruned when ``prune`` is set)."""
        bank = self._bank() if self.prune else None
        if bank is None:
            D = self._distances(descriptors)
            index = np.argmin(D, axis=1)
            return index, D[np.arange(len(descriptors)), index]
        found = [pruned_nearest(d, bank) for d in descriptors]
        index = np.array([f.nearest for f in found], dtype=np.int64)
        return index, np.array([f.values[f.nearest] for f in found])

    def kneighbors(
        self, X: Any, n_neighbors: int = 1, return_distance: bool = True
    ) -> tuple[np.ndarray, np.ndarray] | np.ndarray:
        """The ``n_neighbors`` nearest models of each query, nearest first.

        Returns
        -------
        distances : ndarray, shape (n_queries, n_neighbors)
            Only with ``return_distance``.
        indices : ndarray of int, shape (n_queries, n_neighbors)
            Model indices in fit order (``labels_[indices]`` are their labels).
        """
        self._check_fitted()
        if not 1 <= n_neighbors <= len(self.models_):
            raise ValueError(f"n_neighbors must be between 1 and {len(self.models_)}, got {n_neighbors}")
        D = self.distance_matrix(X)
        indices = np.argsort(D, axis=1, kind="stable")[:, :n_neighbors]
        distances = np.take_along_axis(D, indices, axis=1)
        return (distances, indices) if return_distance else indices

    def decision_function(self, X: Any) -> np.ndarray:
        """Minus the distance to the nearest model of each class, shape (n_queries, n_classes) in
        the order of ``classes_``: the larger, the more likely."""
        D = self.distance_matrix(X)
        return -np.stack([D[:, self.labels_ == c].min(axis=1) for c in self.classes_], axis=1)

    def predict_proba(self, X: Any) -> np.ndarray:
        """Class probabilities of 1-NN, shape (n_queries, n_classes): 1 for the nearest model's
        class, 0 for the others (the nearest neighbour alone decides, as in scikit-learn's
        ``KNeighborsClassifier(n_neighbors=1)``; rejection does not change them)."""
        self._check_fitted()
        index, _ = self._nearest(self._describe(as_samples(X)))
        return (self.labels_[index][:, None] == self.classes_[None, :]).astype(np.float64)

    def _bank(self) -> ModelBank | None:
        """The models packed for pruned search (built once), or None if the distance cannot be
        pruned."""
        spec = self._comparison().distance_spec()
        if spec is None:
            return None
        if getattr(self, "_bank_cache", None) is None:
            self._bank_cache = ModelBank(self.models_, spec)
        return self._bank_cache

    def _comparison(self) -> Any:
        """What samples are compared by: the canonical path, or else the descriptor."""
        return self.path_ if getattr(self, "path_", None) is not None else self.descriptor_

    def _distances(self, descriptors: list[np.ndarray]) -> np.ndarray:
        return self._comparison().distance_matrix(descriptors, self.models_)

    def score(self, X: Any, y: Sequence[Any]) -> float:
        """Recognition ratio (fraction of queries given their true label)."""
        pred = self.predict(X)
        return float(np.mean(pred == np.asarray(y)))
