"""Gesture datasets: the HPM layout and loader, the twelve contexts, a realistic synthetic replica
of the HPM dataset, and continuous labelled streams for the online recognizer.

>>> from framefree.datasets import load_dataset, replica_path   # doctest: +SKIP
>>> ds = load_dataset(replica_path())                             # doctest: +SKIP
>>> len(ds.models()), len(ds.queries("test"))                     # doctest: +SKIP
(35, 231)
"""

from .contexts import (
    BODY_FRAMES,
    COMBINATION_FRAMES,
    NOISE_POS_STD,
    NOISE_ROT_STD,
    WORLD_FRAMES,
    add_noise,
    apply_context,
)
from .gestures import plan_gesture, synthesize_gesture
from .layout import (
    CONTEXTS,
    GESTURES,
    MODEL_CONTEXT,
    STREAMS_DIR,
    Dataset,
    LayoutWarning,
    ModelSet,
    Trial,
    load_dataset,
    resolve_models,
)
from .replica import REPLICA_VERSION, cache_dir, generator_fingerprint, make_replica, replica_path
from .streams import (
    STOP,
    LivePerson,
    Segment,
    StreamItem,
    labels_path,
    load_stream,
    make_stream,
    save_stream,
)

__all__ = [
    "BODY_FRAMES",
    "COMBINATION_FRAMES",
    "CONTEXTS",
    "GESTURES",
    "MODEL_CONTEXT",
    "NOISE_POS_STD",
    "NOISE_ROT_STD",
    "REPLICA_VERSION",
    "STOP",
    "STREAMS_DIR",
    "WORLD_FRAMES",
    "Dataset",
    "LayoutWarning",
    "LivePerson",
    "ModelSet",
    "Segment",
    "StreamItem",
    "Trial",
    "add_noise",
    "apply_context",
    "cache_dir",
    "generator_fingerprint",
    "labels_path",
    "load_dataset",
    "load_stream",
    "make_replica",
    "make_stream",
    "plan_gesture",
    "replica_path",
    "resolve_models",
    "save_stream",
    "synthesize_gesture",
]
