"""Recognition events: what the live recognizer emits and the robot planner consumes."""

from __future__ import annotations

from dataclasses import dataclass

from ..labels import STOP

__all__ = ["STOP", "Event"]



@dataclass(frozen=True)
class Event:
    """A recognized gesture (or a stop signal).

    Attributes
    ----------
    label : str
        Gesture label (e.g. ``"go_left"``) or :data:`STOP`.
    time : float
        Time stamp of the pose sample that triggered the event [s], in the stream's clock.
    dissimilarity : float
        Average pointwise BILTS+ dissimilarity of the best model (-1 for a stop signal).
    model : int
        Index of the matched model (-1 for a stop signal).
    """

    label: str
    time: float
    dissimilarity: float
    model: int = -1

    @property
    def is_stop(self) -> bool:
        """True for a stop signal."""
        return self.label == STOP
