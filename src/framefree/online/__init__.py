"""Real-time recognition: streaming BILTS+, incremental matchers, stop detector, sources.

Public API::

    from framefree.online import Recognizer
    rec = Recognizer.from_dataset("data/hpm", model_context="original_1")
    rec.warmup()
    for t, p, q in source:
        for event in rec.push(t, p, q):
            print(event)
"""

from .acceptance import Accepted, SampleGate
from .calibration import Calibration, calibrate_threshold
from .config import RecognizerConfig
from .events import STOP, Event
from .matchers import MatcherBank
from .models import GestureModels, build_models
from .paper import PaperRecognizer
from .paper_config import PaperConfig
from .preprocess import StreamingBILTSPlus, descriptor_from_samples, replay
from .recognizer import Recognizer
from .sources import CsvReplay, ZmqPublisher, ZmqSource, open_source
from .stop import SampleRateStopDetector, StopDetector, sustained_peak_speed

__all__ = [
    "STOP",
    "Accepted",
    "Calibration",
    "CsvReplay",
    "Event",
    "GestureModels",
    "MatcherBank",
    "PaperConfig",
    "PaperRecognizer",
    "Recognizer",
    "RecognizerConfig",
    "SampleGate",
    "SampleRateStopDetector",
    "StopDetector",
    "StreamingBILTSPlus",
    "ZmqPublisher",
    "ZmqSource",
    "build_models",
    "calibrate_threshold",
    "descriptor_from_samples",
    "open_source",
    "replay",
    "sustained_peak_speed",
]
