"""The live recognizers by name (:data:`framefree.labels.METHODS`)."""

from __future__ import annotations

from typing import Any

__all__ = ["recognizer_class"]


def recognizer_class(method: str) -> Any:
    """The class of the live recognizer called ``method``: ``"segments"``
    (:class:`~framefree.online.Recognizer`) or ``"paper"``
    (:class:`~framefree.online.paper.PaperRecognizer`)."""
    if method == "segments":
        from .recognizer import Recognizer

        return Recognizer
    if method == "paper":
        from .paper import PaperRecognizer

        return PaperRecognizer
    from ..labels import METHODS

    raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
