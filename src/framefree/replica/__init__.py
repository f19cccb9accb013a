"""The replica: simulated people who hold and move a tracker as people do, the HPM dataset they
record (seven gestures, twelve contexts plus four stress contexts), and continuous labelled
sessions for the live recognizer. Everything it writes is read back with :mod:`framefree.datasets`.

>>> from framefree.replica import replica_path                   # doctest: +SKIP
>>> replica_path()                                                # doctest: +SKIP
PosixPath('.../framefree/hpm_replica-v...')
"""

from .activities import PERSON_ACTIVITIES, Activity
from .build import REPLICA_VERSION, cache_dir, generator_fingerprint, make_replica, replica_path
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
from .shapes import DEV_SHAPES, DRAWN_SHAPES, FRESH_SHAPES, HELDOUT_SHAPES
from .streams import LivePerson, StreamItem, make_stream, save_stream

__all__ = [
    "BODY_FRAMES",
    "COMBINATION_FRAMES",
    "DEFAULT_PERSON",
    "DEV_PEOPLE",
    "DEV_SHAPES",
    "DRAWN_SHAPES",
    "EXTRA_SHAPES",
    "FRESH_PEOPLE",
    "FRESH_SHAPES",
    "HELDOUT_PEOPLE",
    "HELDOUT_SHAPES",
    "NOISE_POS_STD",
    "NOISE_ROT_STD",
    "PERSON_ACTIVITIES",
    "REPLICA_VERSION",
    "WORLD_FRAMES",
    "Activity",
    "LivePerson",
    "Person",
    "PersonStream",
    "StreamItem",
    "add_noise",
    "apply_context",
    "cache_dir",
    "draw_person",
    "generator_fingerprint",
    "make_person_streams",
    "make_replica",
    "make_stream",
    "person",
    "person_stream",
    "plan_gesture",
    "replica_path",
    "save_stream",
    "synthesize_gesture",
]
