"""Gesture datasets on disk: the HPM layout ``<gesture>/<context>/<trial>.csv`` and its loader, and
continuous labelled stream files. The synthetic replica that fills such a layout is
:mod:`framefree.replica`.

>>> from framefree.datasets import load_dataset                  # doctest: +SKIP
>>> from framefree.replica import replica_path                   # doctest: +SKIP
>>> ds = load_dataset(replica_path())                             # doctest: +SKIP
>>> len(ds.models()), len(ds.queries("test"))                     # doctest: +SKIP
(35, 231)
"""

from ..labels import STOP
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
from .stream_files import Segment, labels_path, load_stream, write_labels

__all__ = [
    "CONTEXTS",
    "GESTURES",
    "MODEL_CONTEXT",
    "REPLICA_CONTEXTS",
    "STOP",
    "STREAMS_DIR",
    "STRESS_CONTEXTS",
    "Dataset",
    "LayoutWarning",
    "ModelSet",
    "Segment",
    "Trial",
    "labels_path",
    "load_dataset",
    "load_stream",
    "resolve_models",
    "write_labels",
]
