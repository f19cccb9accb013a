"""Real-time recognition: streaming BILTS+, incremental matchers, stop detector, sources."""

from .events import Event

__all__ = ["Event"]
