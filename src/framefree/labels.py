"""Labels shared by the datasets, the recognizers and the robot."""

from __future__ import annotations

__all__ = ["METHODS", "STOP"]

#: Label of the stop signal (a fast rotation of the hand): a labelled stream segment, a recognizer
#: event and a robot command all use it.
STOP = "stop"

#: Names of the live recognizers: framefree's segment spotting (the default), the paper's
#: fixed-window recognizer and a practitioner's sliding-window 1-NN baseline
#: (:class:`framefree.online.Recognizer`, :class:`~framefree.online.paper.PaperRecognizer`,
#: :class:`~framefree.online.window_baseline.WindowSpotter`).
METHODS = ("segments", "paper", "window")
