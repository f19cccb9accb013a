"""What every live recognizer shares: building from a dataset folder and running a recording."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..core.trajectory import Trajectory
from ..datasets.layout import load_model_recordings
from .events import Event

__all__ = ["StreamingRecognizer"]


class StreamingRecognizer:
    """Mixin of the live recognizers (:class:`~framefree.online.Recognizer`,
    :class:`~framefree.online.paper.PaperRecognizer`): a subclass provides ``from_trajectories`` and
    ``push``."""

    @classmethod
    def from_dataset(
        cls,
        root: str | Path,
        model_context: str = "original_1",
        config: Any = None,
        **overrides: Any,
    ) -> Any:
        """Models from every recording ``<root>/<gesture>/<model_context>/*.csv``; ``config`` and
        ``overrides`` as for ``from_trajectories``."""
        trajs, labels = load_model_recordings(root, model_context)
        return cls.from_trajectories(trajs, labels, config, **overrides)  # type: ignore[attr-defined]

    def run(self, traj: Trajectory) -> list[Event]:
        """Push a whole recording; return all events (the recognizer is not reset)."""
        events: list[Event] = []
        for k in range(len(traj)):
            events.extend(self.push(traj.t[k], traj.p[k], traj.q[k]))  # type: ignore[attr-defined]
        return events
