"""Whether a whole recording is within the reach of a set of gesture models.

1-NN always names the nearest model, however far the query lies. A query far longer, larger or
slower than every model (a 3-hour recording, a walk across the room, a motion ten times slower
than any demonstration) is no single gesture, and its nearest model is meaningless. These checks
compare a query's duration, spatial extent and mean speed with the range of the models and say
in words how far outside it lies; :func:`framefree classify <framefree.commands.core>` answers
such a query ``no_gesture`` with a warning (``--force`` classifies it anyway).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .core.multitrajectory import MultiTrajectory
from .core.trajectory import Trajectory

__all__ = ["FAR", "ModelScope", "model_scope", "out_of_scope"]

#: how many times beyond the models' range a query must lie to be out of scope
FAR = 10.0


@dataclass(frozen=True)
class ModelScope:
    """The range of a set of models.

    Attributes
    ----------
    longest : float
        Duration of the longest model [s].
    largest : float
        Largest spatial extent of a model (diagonal of its positions' bounding box) [m].
    slowest : float
        Lowest mean speed of a model (path length / duration) [m/s].
    """

    longest: float
    largest: float
    slowest: float


def _trackers(sample: Trajectory | MultiTrajectory) -> tuple[Trajectory, ...]:
    return sample.trackers if isinstance(sample, MultiTrajectory) else (sample,)


def _measures(sample: Trajectory | MultiTrajectory) -> tuple[float, float, float]:
    """Duration [s], extent [m] and mean speed [m/s] (largest over the trackers)."""
    trackers = _trackers(sample)
    duration = float(trackers[0].t[-1] - trackers[0].t[0])
    extent = max(float(np.linalg.norm(np.ptp(tr.p, axis=0))) for tr in trackers)
    length = max(float(np.linalg.norm(np.diff(tr.p, axis=0), axis=1).sum()) for tr in trackers)
    return duration, extent, length / duration if duration > 0 else 0.0


def model_scope(models: Sequence[Trajectory | MultiTrajectory]) -> ModelScope:
    """The range of ``models`` (longest, largest, slowest)."""
    measured = np.array([_measures(m) for m in models])
    return ModelScope(float(measured[:, 0].max()), float(measured[:, 1].max()),
                      float(measured[:, 2].min()))


def _seconds(s: float) -> str:
    return f"{s / 3600:.3g} h" if s >= 3600 else f"{s / 60:.3g} min" if s >= 120 else f"{s:.3g} s"


def out_of_scope(query: Trajectory | MultiTrajectory, scope: ModelScope,
                 far: float = FAR) -> str | None:
    """Why ``query`` lies far outside the models' range, in words, or None when it does not.

    Parameters
    ----------
    query : Trajectory or MultiTrajectory
    scope : ModelScope
        From :func:`model_scope`.
    far : float
        A query is out of scope when it lasts more than ``far`` times the longest model, extends
        more than ``far`` times the largest one, or moves more than ``far`` times slower on
        average than the slowest one.
    """
    duration, extent, speed = _measures(query)
    if duration > far * scope.longest:
        return (f"it lasts {_seconds(duration)}, the longest model {_seconds(scope.longest)}: "
                "far longer than any gesture")
    if extent > far * scope.largest:
        units = (" (a factor near 100 or 1000: are the query and the models in the same units? "
                 "--units applies to both)" if extent > 50 * scope.largest else "")
        return (f"it spans {extent:.3g} m, the largest model {scope.largest:.3g} m: far larger "
                f"than any gesture{units}")
    if speed * far < scope.slowest:
        return (f"it moves at {speed:.3g} m/s on average, the slowest model at "
                f"{scope.slowest:.3g} m/s: far slower than any gesture")
    return None
