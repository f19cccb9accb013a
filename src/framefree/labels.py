"""Labels shared by the datasets, the recognizers and the robot."""

from __future__ import annotations

__all__ = ["STOP"]

#: Label of the stop signal (a fast rotation of the hand): a labelled stream segment, a recognizer
#: event and a robot command all use it.
STOP = "stop"
