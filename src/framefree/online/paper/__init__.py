"""The paper's real-time recognizer (Verduyn et al., arXiv 2503.11352), faithful: streaming
BILTS+ reparameterized by screw path, fixed-window matchers per model, thresholds calibrated from
the models, and the per-sample stop detector (docs/online-paper.md).

>>> from framefree.online.paper import PaperRecognizer          # doctest: +SKIP
"""

from .calibration import Calibration, calibrate_threshold
from .config import PaperConfig
from .matchers import MatcherBank
from .models import GestureModels, build_models
from .preprocess import StreamingBILTSPlus, descriptor_from_samples, replay
from .recognizer import PaperRecognizer
from .stop import SampleRateStopDetector

__all__ = [
    "Calibration",
    "GestureModels",
    "MatcherBank",
    "PaperConfig",
    "PaperRecognizer",
    "SampleRateStopDetector",
    "StreamingBILTSPlus",
    "build_models",
    "calibrate_threshold",
    "descriptor_from_samples",
    "replay",
]
