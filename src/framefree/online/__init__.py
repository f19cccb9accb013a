"""Real-time recognition: streaming BILTS+, incremental matchers, stop detector, sources.

Public API::

    from framefree.online import Recognizer
    rec = Recognizer.from_dataset("data/hpm", model_context="original_1")
    rec.warmup()
    for t, p, q in source:
        for event in rec.push(t, p, q):
            print(event)

The names below are imported on first use (:pep:`562`): ``framefree live`` loads the segment
recognizer without the paper's recognizer, its matchers or the pose sources it does not use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_attributes

if TYPE_CHECKING:
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

#: public name -> submodule that defines it
_LAZY = {
    "Accepted": ".acceptance",
    "SampleGate": ".acceptance",
    "Calibration": ".calibration",
    "calibrate_threshold": ".calibration",
    "RecognizerConfig": ".config",
    "STOP": ".events",
    "Event": ".events",
    "MatcherBank": ".matchers",
    "GestureModels": ".models",
    "build_models": ".models",
    "PaperRecognizer": ".paper",
    "PaperConfig": ".paper_config",
    "StreamingBILTSPlus": ".preprocess",
    "descriptor_from_samples": ".preprocess",
    "replay": ".preprocess",
    "Recognizer": ".recognizer",
    "CsvReplay": ".sources",
    "ZmqPublisher": ".sources",
    "ZmqSource": ".sources",
    "open_source": ".sources",
    "SampleRateStopDetector": ".stop",
    "StopDetector": ".stop",
    "sustained_peak_speed": ".stop",
}

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


__getattr__, __dir__ = lazy_attributes(__name__, globals(), _LAZY)
