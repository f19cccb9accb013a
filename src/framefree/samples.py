"""What an estimator accepts as samples, in one place: trajectories of one or several trackers, as
framefree objects or plain arrays."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .core.multitrajectory import MultiTrajectory
from .core.trajectory import Trajectory

__all__ = ["Sample", "as_samples", "not_fitted_error"]

#: one sample: a Trajectory, a MultiTrajectory, an (n, 8) array ``t x y z qw qx qy qz``, or a
#: tuple of such arrays (several trackers recorded together, one time column)
Sample = Trajectory | MultiTrajectory | np.ndarray | tuple

_WHAT = ("samples must be Trajectory or MultiTrajectory objects, (n, 8) arrays "
         "[t, x, y, z, qw, qx, qy, qz], or tuples of such arrays (one per tracker)")


def _one(x: Any, k: int) -> Trajectory | MultiTrajectory:
    if isinstance(x, Trajectory | MultiTrajectory):
        return x
    if isinstance(x, tuple):
        trackers = tuple(Trajectory.from_array(a, source=f"sample {k}, tracker {i}") for i, a in enumerate(x))
        return MultiTrajectory(trackers, source=f"sample {k}")
    if isinstance(x, np.ndarray) or (isinstance(x, list) and x and isinstance(x[0], list | tuple)):
        arr = np.asarray(x, dtype=np.float64)
        if arr.ndim == 2 and arr.shape[1] == 8:
            return Trajectory.from_array(arr, source=f"sample {k}")
        raise TypeError(f"sample {k}: an array of shape {arr.shape}; {_WHAT}")
    raise TypeError(f"sample {k}: {type(x).__name__}; {_WHAT}")


def as_samples(X: Any) -> list[Trajectory | MultiTrajectory]:
    """The samples of ``X``: a sequence of samples (see :data:`Sample`), or one sample alone.

    Raises
    ------
    TypeError
        For anything else, in one line that says what is accepted.
    TrajectoryError
        For an array that is no valid trajectory (naming the sample and row).
    """
    if isinstance(X, Trajectory | MultiTrajectory | tuple):
        return [_one(X, 0)]
    if isinstance(X, np.ndarray) and X.ndim == 2:
        return [_one(X, 0)]
    if isinstance(X, np.ndarray) and X.dtype == object:
        X = list(X)
    if isinstance(X, np.ndarray) and X.ndim == 3:
        X = list(X)
    if not isinstance(X, Sequence) or isinstance(X, str | bytes):
        raise TypeError(f"X is a {type(X).__name__}; {_WHAT}, in a list")
    return [_one(x, k) for k, x in enumerate(X)]


def not_fitted_error(estimator: object) -> Exception:
    """The error for a method that needs :meth:`fit` first: scikit-learn's ``NotFittedError`` when
    scikit-learn is installed (a ``ValueError`` and an ``AttributeError``), else one of those."""
    message = (f"This {type(estimator).__name__} instance is not fitted yet; call fit with models "
               "before using it")
    try:
        from sklearn.exceptions import NotFittedError
    except ImportError:  # pragma: no cover - scikit-learn is an optional extra
        class NotFittedError(ValueError, AttributeError):  # type: ignore[no-redef]
            pass
    return NotFittedError(message)
