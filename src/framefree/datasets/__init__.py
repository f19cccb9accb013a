"""Gesture datasets: the HPM layout and loader, the twelve contexts, a realistic synthetic replica
of the HPM dataset, simulated people who differ as people do, and continuous labelled streams for
the online recognizer.

>>> from framefree.datasets import load_dataset, replica_path   # doctest: +SKIP
>>> ds = load_dataset(replica_path())                             # doctest: +SKIP
>>> len(ds.models()), len(ds.queries("test"))                     # doctest: +SKIP
(35, 231)
"""

from .activities import PERSON_ACTIVITIES, Activity
from .contexts import (
    BODY_FRAMES,
    COMBINATION_FRAMES,
    NOISE_POS_STD,
    NOISE_ROT_STD,
    WORLD_FRAMES,
    add_noise,
    apply_context,
)
from .gestures import EXTRA_SHAPES, plan_gesture, synthesize_gesture
from .layout import (
    CONTEXTS,
    GESTURES,
    MODEL_CONTEXT,
    REPLICA_CONTEXTS,
    STREAMS_DIR,
    STRESS_CONTEXTS,
    Dataset,
    LayoutWarning,
    ModelSet,
    Trial,
    load_dataset,
    resolve_models,
)
from .people import (
    DEFAULT_PERSON,
    DEV_PEOPLE,
    FRESH_PEOPLE,
    HELDOUT_PEOPLE,
    Person,
    draw_person,
    person,
)
from .people_streams import PersonStream, make_person_streams, person_stream
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
    "DEFAULT_PERSON",
    "DEV_PEOPLE",
    "EXTRA_SHAPES",
    "FRESH_PEOPLE",
    "GESTURES",
    "HELDOUT_PEOPLE",
    "MODEL_CONTEXT",
    "NOISE_POS_STD",
    "NOISE_ROT_STD",
    "PERSON_ACTIVITIES",
    "REPLICA_CONTEXTS",
    "REPLICA_VERSION",
    "STOP",
    "STREAMS_DIR",
    "STRESS_CONTEXTS",
    "WORLD_FRAMES",
    "Activity",
    "Dataset",
    "LayoutWarning",
    "LivePerson",
    "ModelSet",
    "Person",
    "PersonStream",
    "Segment",
    "StreamItem",
    "Trial",
    "add_noise",
    "apply_context",
    "cache_dir",
    "draw_person",
    "generator_fingerprint",
    "labels_path",
    "load_dataset",
    "load_stream",
    "make_person_streams",
    "make_replica",
    "make_stream",
    "person",
    "person_stream",
    "plan_gesture",
    "replica_path",
    "resolve_models",
    "save_stream",
    "synthesize_gesture",
]
