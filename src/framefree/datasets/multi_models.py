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

from dataclasses import dataclass, field
from pathlib import Path

from ..core.multitrajectory import MultiTrajectory
from ..errors import DatasetError
from .people_layout import _files, is_multi_tracker_file, load_labelled, load_people

__all__ = ["MultiModelSet", "find_multi_models", "holds_several_trackers"]


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


def holds_several_trackers(root: str | Path) -> bool:
    """Whether ``root`` is a folder of multi-tracker recordings (read from its first recording
    alone: cheap, for checking a source before the models are loaded)."""
    root = Path(root).expanduser()
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
    if not holds_several_trackers(root):
        return None
    found = _first_recording(root)
    if found is not None and found[1] == 3:
        people = load_people(root)
        samples = [r.sample for r in people]
        labels = [r.gesture for r in people]
        layout = "people"
        what = (f"a folder of {len(people.people)} people <person>/<gesture>/<recording>")
    else:
        samples, labels = load_labelled(root)
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
    return MultiModelSet(samples, labels, layout, description)
