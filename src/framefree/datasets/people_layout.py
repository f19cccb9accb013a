"""Recordings of several people: the layout ``<root>/<person>/<gesture>/<recording>``.

A recording is a Machete binary file (:mod:`framefree.io.machete`, no or any extension), a
framefree multi-tracker CSV (:mod:`framefree.io.multicsv`, a header row starting ``t,``), or a
framefree single-tracker CSV (8 columns, no header). Every recording becomes a
:class:`~framefree.core.multitrajectory.MultiTrajectory` (one tracker for a single-tracker CSV).
Hidden files and README/licence files are skipped; anything else that does not read is an error
naming the file.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from ..core.multitrajectory import MultiTrajectory
from ..core.posecsv import header_kind, known_non_pose
from ..core.trajectory import Trajectory
from ..errors import DatasetError, TrajectoryError
from ..io.conventions import UP, Convention
from ..io.machete import read_machete
from ..io.multicsv import read_multi_csv
from .layout import _natural_key

__all__ = ["PeopleDataset", "Recording", "is_multi_tracker_file", "load_labelled", "load_people",
           "read_recording"]

_SKIPPED = {"readme", "readme.md", "readme.txt", "license", "licence", "license.txt", "notice"}


@dataclass(frozen=True)
class Recording:
    """One performance of one person.

    Attributes
    ----------
    person, gesture, name : str
        Folder names and file name.
    path : Path
    sample : MultiTrajectory
    """

    person: str
    gesture: str
    name: str
    path: Path
    sample: MultiTrajectory = field(repr=False)


@dataclass(frozen=True)
class PeopleDataset:
    """Recordings of several people, loaded.

    Attributes
    ----------
    root : Path
    recordings : tuple of Recording
        Sorted by person, gesture and file name.
    """

    root: Path
    recordings: tuple[Recording, ...]

    @property
    def people(self) -> list[str]:
        return sorted({r.person for r in self.recordings}, key=_natural_key)

    @property
    def gestures(self) -> list[str]:
        return sorted({r.gesture for r in self.recordings})

    def __len__(self) -> int:
        return len(self.recordings)

    def __iter__(self) -> Iterator[Recording]:
        return iter(self.recordings)

    def of(self, people: set[str] | list[str]) -> list[Recording]:
        """The recordings of some people."""
        chosen = set(people)
        return [r for r in self.recordings if r.person in chosen]

    def summary(self) -> str:
        counts = Counter(r.person for r in self.recordings)
        trackers = sorted({r.sample.n_trackers for r in self.recordings})
        return (f"{len(self.recordings)} recordings of {len(counts)} people, {len(self.gestures)} "
                f"gestures, {'/'.join(map(str, trackers))} tracker(s) each")


def read_recording(path: str | Path, convention: str | Convention | None = None) -> MultiTrajectory:
    """One recording file of any supported format, as a multi-tracker sample.

    Parameters
    ----------
    path : path
    convention : str or Convention, optional
        Coordinate convention of the stored poses; default: the format's own (``unity`` for
        Machete files, ``framefree`` for CSV).
    """
    path = Path(path)
    if path.is_file():
        with path.open("rb") as fh:
            what = known_non_pose(fh.read(8))
        if what is not None:
            raise TrajectoryError(f"this is {what}, not a pose recording (a pose CSV file or a "
                                  "Machete recording)", path)
    multi = _has_multi_header(path)
    if path.suffix.lower() == ".csv" or multi:
        if multi:
            return read_multi_csv(path, convention or "framefree")
        if convention not in (None, "framefree"):
            raise TrajectoryError(f"{path}: a single-tracker CSV is in framefree's frame; convert it "
                                  "first or write a multi-tracker CSV with a header")
        traj = Trajectory.from_csv(path)
        return MultiTrajectory((traj,), ("tracker_0",), UP, str(path))
    return read_machete(path, convention or "unity")


def _has_multi_header(path: Path) -> bool:
    """Whether a file's header says it is framefree's multi-tracker CSV (``t,NAME.x,...``); a
    single-tracker header ``t,x,y,z,qw,qx,qy,qz`` is not one."""
    with path.open("rb") as fh:
        head = fh.read(4096)
    if not head.startswith((b"t,", b"t\r", b"t\n")):
        return False
    first = head.decode("utf-8", errors="replace").splitlines()[0]
    # a malformed multi-tracker header (a NAME.field column) still goes to its own reader, which
    # names the faulty columns
    return header_kind(first) == "multi" or "." in first


def is_multi_tracker_file(path: str | Path) -> bool:
    """Whether ``path`` holds several trackers: a Machete recording or a CSV with a ``t,...`` header."""
    path = Path(path)
    return path.is_file() and (path.suffix.lower() != ".csv" or _has_multi_header(path))


def load_labelled(
    root: str | Path, convention: str | Convention | None = None
) -> tuple[list[MultiTrajectory], list[str]]:
    """Multi-tracker recordings in ``<root>/<label>/<recording>`` folders, and their labels.

    Raises
    ------
    DatasetError
        When ``root`` holds no ``<label>/<recording>`` files.
    """
    root = Path(root)
    samples, labels = [], []
    for ldir in (p for p in _files(root) if p.is_dir()):
        for f in (f for f in _files(ldir) if f.is_file()):
            samples.append(read_recording(f, convention))
            labels.append(ldir.name)
    if not samples:
        raise DatasetError(f"{root}: no <label>/<recording> files")
    return samples, labels


def _files(folder: Path) -> list[Path]:
    out = []
    for p in sorted(folder.iterdir(), key=lambda p: _natural_key(p.name)):
        if p.name.startswith(".") or p.name.lower() in _SKIPPED or p.suffix.lower() == ".meta":
            continue
        out.append(p)
    return out


def load_people(
    root: str | Path,
    convention: str | Convention | None = None,
    progress: bool = False,
) -> PeopleDataset:
    """Load every recording below ``root`` (``<person>/<gesture>/<recording>``).

    Parameters
    ----------
    root : path
    convention : str or Convention, optional
        Coordinate convention of the stored poses (default: each format's own).
    progress : bool
        Show a progress bar.

    Raises
    ------
    DatasetError
        When the folder is missing, holds no recordings, or has a file or folder out of place.
    TrajectoryError
        When a recording does not read (naming the file and the problem).
    """
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f"{root}: not a folder (expected <person>/<gesture>/<recording>)")
    files = []
    for pdir in _files(root):
        if not pdir.is_dir():
            continue
        for gdir in _files(pdir):
            if not gdir.is_dir():
                raise DatasetError(f"{gdir}: expected a gesture folder <person>/<gesture>/<recording>")
            files += [(pdir.name, gdir.name, f) for f in _files(gdir) if f.is_file()]
    if not files:
        raise DatasetError(f"{root}: no recordings in <person>/<gesture>/<recording> folders")
    if progress:
        from tqdm import tqdm

        files = tqdm(files, desc="reading recordings", unit="file", leave=False)
    recordings = tuple(Recording(person, gesture, f.name, f, read_recording(f, convention))
                       for person, gesture, f in files)
    return PeopleDataset(root, recordings)
