"""Real-time recognition: streaming BILTS+, incremental matchers, stop detector, sources.

Public API::

    from framefree.online import Recognizer
    rec = Recognizer.from_dataset("data/hpm", model_context="original_1")
    rec.warmup()
    for t, p, q in source:
        for event in rec.push(t, p, q):
            print(event)
"""

from .calibration import Calibration, calibrate_threshold
from .config import RecognizerConfig
from .events import STOP, Event
from .matchers import MatcherBank
from .models import GestureModels, build_models
from .preprocess import StreamingBILTSPlus, descriptor_from_samples, replay
from .recognizer import Recognizer
from .sources import CsvReplay, ZmqPublisher, ZmqSource, open_source
from .stop import StopDetector

__all__ = [
    "STOP",
    "Calibration",
    "CsvReplay",
    "Event",
    "GestureModels",
    "MatcherBank",
    "Recognizer",
    "RecognizerConfig",
    "StopDetector",
    "StreamingBILTSPlus",
    "ZmqPublisher",
    "ZmqSource",
    "build_models",
    "calibrate_threshold",
    "descriptor_from_samples",
    "open_source",
    "replay",
]
