"""Your own gestures: record takes, check they can be told apart, enroll a library, use it live.

::

    from framefree.library import split_takes, read_takes, check_takes, enroll, load_recognizer

    takes = split_takes(Trajectory.from_csv("wave_session.csv"))    # one recording -> takes
    vocab = read_takes("my_gestures")                                # <gesture>/<context>/*.csv
    print(check_takes(vocab).format())                               # can they be told apart?
    enroll(vocab, built_from=["my_gestures"]).save("my_gestures.npz")  # models + thresholds, once
    rec = load_recognizer("my_gestures.npz")                         # live, no recalibration

Modules: :mod:`~framefree.library.takes` (cutting a recording into takes),
:mod:`~framefree.library.take_set` (the takes of a library folder),
:mod:`~framefree.library.store` (library files), :mod:`~framefree.library.probes`
(motions that probe a vocabulary), :mod:`~framefree.library.check` (the report),
:mod:`~framefree.library.figures` (its figures).
"""

from .check import CheckReport, CheckSettings, Finding, GestureCheck, check_takes, descriptor_for
from .figures import plot_distance_map, plot_take_gallery
from .probes import everyday_motions, perturbed, random_frame, slowest_stop_speed, stop_rotations
from .recorder import TakeRecorder
from .store import (
    FORMAT_VERSION,
    GestureLibrary,
    LibraryError,
    build_recognizer,
    enroll,
    load_library,
    load_recognizer,
)
from .take_set import OWN_CONTEXT, TakeSet, read_takes
from .takes import (
    TakeSettings,
    TakeSpan,
    cut_take,
    find_takes,
    join_recordings,
    motion_speed,
    rest_level,
    split_takes,
    write_take,
)

__all__ = [
    "FORMAT_VERSION",
    "OWN_CONTEXT",
    "CheckReport",
    "CheckSettings",
    "Finding",
    "GestureCheck",
    "GestureLibrary",
    "LibraryError",
    "TakeRecorder",
    "TakeSet",
    "TakeSettings",
    "TakeSpan",
    "build_recognizer",
    "check_takes",
    "cut_take",
    "descriptor_for",
    "enroll",
    "everyday_motions",
    "find_takes",
    "join_recordings",
    "load_library",
    "load_recognizer",
    "motion_speed",
    "perturbed",
    "plot_distance_map",
    "plot_take_gallery",
    "random_frame",
    "read_takes",
    "rest_level",
    "slowest_stop_speed",
    "split_takes",
    "stop_rotations",
    "write_take",
]
