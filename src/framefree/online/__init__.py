"""Real-time recognition, framefree's default: spotting whole gestures in a pose stream and
classifying each one as the offline classifier does (docs/online.md). The paper's recognizer is
:mod:`framefree.online.paper`; pose sources are :mod:`framefree.io`.

Public API::

    from framefree.online import Recognizer, open_source
    rec = Recognizer.from_dataset("data/hpm", model_context="original_1")
    rec.warmup()
    for t, p, q in open_source("session.csv"):
        for event in rec.push(t, p, q):
            print(event)

The names below are imported on first use (:pep:`562`): ``framefree live`` loads the segment
recognizer without the pose sources it does not use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_attributes

if TYPE_CHECKING:
    from ..io.sources import CsvReplay, ZmqPublisher, ZmqSource, open_source
    from .acceptance import Accepted, SampleGate
    from .config import RecognizerConfig
    from .constants import DescriptorSettings, SpottingConstants
    from .events import STOP, Event
    from .learned import LearnedSettings, Provenance
    from .recognizer import Recognizer
    from .stop import StopDetector, sustained_peak_speed

#: public name -> module that defines it (relative to this package)
_LAZY = {
    "Accepted": ".acceptance",
    "SampleGate": ".acceptance",
    "RecognizerConfig": ".config",
    "DescriptorSettings": ".constants",
    "SpottingConstants": ".constants",
    "LearnedSettings": ".learned",
    "Provenance": ".learned",
    "STOP": ".events",
    "Event": ".events",
    "Recognizer": ".recognizer",
    "CsvReplay": "..io.sources",
    "ZmqPublisher": "..io.sources",
    "ZmqSource": "..io.sources",
    "open_source": "..io.sources",
    "StopDetector": ".stop",
    "sustained_peak_speed": ".stop",
}

__all__ = [
    "STOP",
    "Accepted",
    "CsvReplay",
    "DescriptorSettings",
    "Event",
    "LearnedSettings",
    "Provenance",
    "Recognizer",
    "RecognizerConfig",
    "SampleGate",
    "SpottingConstants",
    "StopDetector",
    "ZmqPublisher",
    "ZmqSource",
    "open_source",
    "sustained_peak_speed",
]


__getattr__, __dir__ = lazy_attributes(__name__, globals(), _LAZY)
