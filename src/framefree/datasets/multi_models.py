"""Model recordings of several trackers, in the folders every live command accepts as ``--models``.

Two layouts hold multi-tracker recordings (Machete files or framefree's multi-tracker CSV):

* a folder of people, ``<root>/<person>/<gesture>/<recording>`` (:func:`~framefree.datasets.
  people_layout.load_people`), e.g. the Machete Vive set as published: every person's recordings
  become models of their gesture;
* a folder of labels, ``<root>/<label>/<recording>`` (:func:`~framefree.datasets.people_layout.
  load_labelled`).

Which one a folder is, and whether it holds several trackers at all, is read from its first
recording: folders of single-tracker CSV files are left to :func:`~framefree.datasets.layout.
resolve_models`.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from ..core.multitrajectory import MultiTrajectory
from ..errors import DatasetError
from ..io.library_file import JSON_MEMBER
from .people_layout import _files, is_multi_tracker_file, load_people, read_recording

__all__ = ["MultiModelSet", "find_multi_models", "holds_several_trackers", "is_multi_library",
           "multi_recordings"]


@dataclass(frozen=True)
class MultiModelSet:
    """Multi-tracker model recordings found by :func:`find_multi_models`.

    Attributes
    ----------
    samples : list of MultiTrajectory
    labels : list of str
    layout : {"people", "labelled"}
    description : str
        One line for the user: what was found.
    """

    samples: list[MultiTrajectory] = field(repr=False)
    labels: list[str]
    layout: str
    description: str
    paths: list[Path] = field(default_factory=list, repr=False)


def _first_recording(root: Path) -> tuple[Path, int] | None:
    """The first file two or three folders below ``root`` and its depth (hidden files, READMEs
    and licences skipped)."""
    for a in (p for p in _files(root) if p.is_dir()):
        for b in _files(a):
            if b.is_file():
                return b, 2
            for c in _files(b):
                if c.is_file():
                    return c, 3
    return None


def is_multi_library(path: str | Path) -> bool:
    """Whether ``path`` is a gesture library file of several trackers (``framefree enroll`` of
    multi-tracker takes): its JSON member names the trackers. Only that member is read."""
    path = Path(path).expanduser()
    if not path.is_file() or not zipfile.is_zipfile(path):
        return False
    try:
        with zipfile.ZipFile(path) as zf:
            meta = json.loads(zf.read(JSON_MEMBER))
    except (OSError, KeyError, zipfile.BadZipFile, ValueError):
        return False
    return isinstance(meta, dict) and bool(meta.get("trackers"))


def holds_several_trackers(root: str | Path) -> bool:
    """Whether ``root`` is a folder of multi-tracker recordings (read from its first recording
    alone: cheap, for checking a source before the models are loaded) or a gesture library file
    of several trackers."""
    root = Path(root).expanduser()
    if root.is_file():
        return is_multi_library(root)
    if not root.is_dir():
        return False
    found = _first_recording(root)
    return found is not None and is_multi_tracker_file(found[0])


def find_multi_models(root: str | Path) -> MultiModelSet | None:
    """The multi-tracker model recordings below ``root``, or None when it holds single-tracker
    recordings (or is a file).

    Raises
    ------
    DatasetError
        When the recordings do not all have the same number of trackers.
    TrajectoryError
        When a recording does not read (naming the file).
    """
    root = Path(root).expanduser()
    if not root.is_dir() or not holds_several_trackers(root):
        return None
    return multi_recordings(root)


def multi_recordings(root: str | Path) -> MultiModelSet:
    """Every multi-tracker recording below the folder ``root`` (people or labels, see the module
    docstring), with its label and path.

    Raises
    ------
    DatasetError
        When the folder holds no multi-tracker recordings, or recordings of different numbers
        of trackers.
    TrajectoryError
        When a recording does not read (naming the file).
    """
    root = Path(root).expanduser()
    found = _first_recording(root) if root.is_dir() else None
    if found is None or not is_multi_tracker_file(found[0]):
        raise DatasetError(f"{root}: no multi-tracker recordings (expected <gesture>/<recording> "
                           "or <person>/<gesture>/<recording>, Machete files or multi-tracker CSV)")
    if found[1] == 3:
        people = load_people(root)
        samples = [r.sample for r in people]
        labels = [r.gesture for r in people]
        paths = [r.path for r in people]
        layout = "people"
        what = (f"a folder of {len(people.people)} people <person>/<gesture>/<recording>")
    else:
        paths = [f for ldir in _files(root) if ldir.is_dir() for f in _files(ldir) if f.is_file()]
        samples = [read_recording(f) for f in paths]
        labels = [f.parent.name for f in paths]
        layout = "labelled"
        what = "a folder of <label>/<recording> files"
    counts = sorted({s.n_trackers for s in samples})
    if len(counts) != 1:
        odd = next(s for s in samples if s.n_trackers != samples[0].n_trackers)
        raise DatasetError(f"{odd.source}: {odd.n_trackers} trackers, but {samples[0].source} has "
                           f"{samples[0].n_trackers}; models must all have the same trackers")
    names = ", ".join(samples[0].names)
    description = (f"models: {root} is {what}: {len(samples)} recordings of "
                   f"{len(set(labels))} gestures, {counts[0]} trackers ({names})")
    return MultiModelSet(samples, labels, layout, description, paths)
