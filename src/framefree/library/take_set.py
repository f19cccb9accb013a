"""The takes of a vocabulary: the recordings of each gesture, their labels and names, read from a
library folder (``<gesture>/<context>/<trial>.csv``, a benchmark's ``<gesture>/<trial>.csv``, or
several people's ``<person>/<gesture>/<trial>.csv`` either way round), combined from several
sources, and refused where a copied take would corrupt a threshold.

:mod:`framefree.library.store` keeps them, with the settings and everything learned from them,
in a library file.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Self

import numpy as np

from ..core.trajectory import Trajectory
from ..datasets.gesture_level import oriented
from ..datasets.layout import people_trials
from ..errors import DatasetError, FramefreeError
from ..io.library_file import LibraryError

__all__ = ["OWN_CONTEXT", "LabelledTakes", "TakeSet", "combine_takes", "read_takes", "refuse_copies"]

#: Context folder that ``framefree record`` writes by default and :func:`read_takes` prefers.
OWN_CONTEXT = "own"
_PREFERRED_CONTEXTS = (OWN_CONTEXT, "original_1")


class LabelledTakes:
    """What the takes of a vocabulary share, of one tracker (:class:`TakeSet`) or several
    (:class:`~framefree.library.multi_library.MultiTakeSet`): a label and a name for each take
    (and its stored rows, where known), and the gestures they hold. For frozen dataclasses with
    the fields ``takes``, ``labels``, ``names`` and ``arrays``, and the methods ``rows`` (each
    take's rows as a library file stores them) and ``matches`` (whether a ``--remove`` pattern
    names a take of a gesture and name)."""

    takes: tuple
    labels: tuple[str, ...]
    names: tuple[str, ...]
    arrays: tuple[np.ndarray, ...]

    def __post_init__(self) -> None:
        if not len(self.takes) == len(self.labels) == len(self.names):
            raise ValueError(f"{len(self.takes)} takes, {len(self.labels)} labels, {len(self.names)} names")
        if self.arrays and len(self.arrays) != len(self.takes):
            raise ValueError(f"{len(self.takes)} takes but {len(self.arrays)} arrays")

    def __len__(self) -> int:
        return len(self.takes)

    @property
    def gestures(self) -> list[str]:
        """Distinct gesture labels in first-appearance order."""
        return list(dict.fromkeys(self.labels))

    def counts(self) -> dict[str, int]:
        """Number of takes per gesture."""
        return {g: self.labels.count(g) for g in self.gestures}

    def without(self, patterns: Iterable[str]) -> Self:
        """A copy without the takes matching any pattern (``matches``).

        Raises
        ------
        LibraryError
            For a pattern that matches no take.
        """
        drop = np.zeros(len(self), dtype=bool)
        for pat in patterns:
            hit = np.array([self.matches(pat, lab, name)
                            for lab, name in zip(self.labels, self.names, strict=True)], dtype=bool)
            if not hit.any():
                raise LibraryError(f"--remove {pat}: no such gesture or take (gestures: "
                                   f"{', '.join(self.gestures)})")
            drop |= hit
        keep = np.flatnonzero(~drop)
        rows = self.rows()
        return type(self)(tuple(self.takes[k] for k in keep), tuple(self.labels[k] for k in keep),
                          tuple(self.names[k] for k in keep), tuple(rows[k] for k in keep))


@dataclass(frozen=True)
class TakeSet(LabelledTakes):
    """Takes of a vocabulary: the recordings, their gesture labels and their names.

    Attributes
    ----------
    takes : tuple of Trajectory
        One gesture performance each.
    labels : tuple of str
        Gesture of each take.
    names : tuple of str
        ``<gesture>/<context>/<trial>`` of each take (its place in a library folder).
    arrays : tuple of ndarray, shape (N_k, 8), optional
        The rows ``t, x, y, z, qw, qx, qy, qz`` the takes were built from, when known (a library
        file stores these; see :meth:`as_stored`).
    """

    takes: tuple[Trajectory, ...]
    labels: tuple[str, ...]
    names: tuple[str, ...]
    arrays: tuple[np.ndarray, ...] = ()

    def rows(self) -> tuple[np.ndarray, ...]:
        """The rows of every take as stored in a library file, (N_k, 8) each."""
        return self.arrays or tuple(tr.to_array() for tr in self.takes)

    def as_stored(self) -> TakeSet:
        """The takes exactly as a library file gives them back.

        Building a trajectory renormalizes its quaternions, which can change their last bit (and
        does not settle: it may alternate). A library stores the rows and every reader rebuilds the
        trajectories from them, so enrolment calibrates on these, and a loaded library rebuilds
        bit-identical models.
        """
        rows = self.rows()
        takes = tuple(Trajectory.from_array(r, source=tr.source)
                      for r, tr in zip(rows, self.takes, strict=True))
        return TakeSet(takes, self.labels, self.names, rows)

    def __add__(self, other: TakeSet) -> TakeSet:
        return TakeSet(self.takes + other.takes, self.labels + other.labels, self.names + other.names,
                       self.rows() + other.rows())

    @staticmethod
    def matches(pattern: str, label: str, name: str) -> bool:
        """Whether ``pattern`` names a take of gesture ``label`` called ``name``: its gesture
        (``wave``), the take (``wave/own/trial_3``) or its gesture and trial (``wave/trial_3``)."""
        return _matches(pattern, label, name)


def _matches(pattern: str, label: str, name: str) -> bool:
    parts = pattern.strip("/").split("/")
    if len(parts) == 1:
        return parts[0] == label
    name_parts = name.split("/")
    return parts[0] == label and name_parts[-len(parts) + 1:] == parts[1:]


def _choose_context(gdir: Path, context: str | None) -> Path:
    found = sorted(p.name for p in gdir.iterdir() if p.is_dir() and not p.name.startswith("."))
    if not found and context is None and any(gdir.glob("*.csv")):
        return gdir  # <gesture>/<trial>.csv: a benchmark's dictionary of examples
    if context is not None:
        if context not in found:
            raise LibraryError(f"{gdir}: no context folder {context!r} (found: {', '.join(found) or 'none'})")
        return gdir / context
    for pref in _PREFERRED_CONTEXTS:
        if pref in found:
            return gdir / pref
    if len(found) == 1:
        return gdir / found[0]
    if not found:
        raise LibraryError(f"{gdir}: no takes (expected {gdir.name}/<context>/<trial>.csv or "
                           f"{gdir.name}/<trial>.csv)")
    raise LibraryError(f"{gdir}: several context folders ({', '.join(found)}); "
                       "choose one with --context")


def read_takes(folder: str | Path, context: str | None = None) -> TakeSet:
    """Takes of a library folder laid out as ``<folder>/<gesture>/<context>/<trial>.csv``, as
    ``<folder>/<gesture>/<trial>.csv`` (a benchmark's dictionary of examples, as every command's
    ``--models`` reads it), or as ``<folder>/<person>/<gesture>/<trial>.csv`` (several people's
    examples, :func:`~framefree.datasets.layout.people_trials`; without ``context``).

    Parameters
    ----------
    folder : str or Path
        The library folder (``framefree record`` writes it; a dataset such as the HPM replica has
        the same layout).
    context : str, optional
        Context folder to read in every gesture. Default: ``own`` if present, else ``original_1``
        if present, else the gesture's only context folder.

    Returns
    -------
    TakeSet

    Raises
    ------
    LibraryError
        For a missing folder, a gesture without takes, or ambiguous contexts.
    DatasetError
        For a malformed CSV file (naming the file and row).
    """
    root = Path(folder).expanduser()
    if not root.is_dir():
        raise LibraryError(f"{root}: no such library folder "
                           "(expected <folder>/<gesture>/<context>/<trial>.csv)")
    people = people_trials(root, _PREFERRED_CONTEXTS) if context is None else None
    if people is not None:  # <person>/<gesture>/ or <gesture>/<person>/: <gesture>/<person>/<trial>
        takes = _read([f for _, _, f in people])
        people, _ = oriented(people, takes)
        found = [(label, f"{label}/{person}/{f.stem}", f) for label, person, f in people]
    else:
        found = []
        for gdir in sorted(p for p in root.iterdir() if p.is_dir() and p.name not in ("streams",)
                           and not p.name.startswith(".")):
            cdir = _choose_context(gdir, context)
            files = sorted(cdir.glob("*.csv"), key=lambda f: _natural(f.stem))
            if not files:
                raise LibraryError(f"{cdir}: no takes (*.csv)")
            found += [(gdir.name, "/".join(f.relative_to(root).with_suffix("").parts), f)
                      for f in files]
        takes = _read([f for _, _, f in found])
    labels = [label for label, _, _ in found]
    names = [name for _, name, _ in found]
    if not takes:
        raise LibraryError(f"{root}: no gesture folders with takes")
    return TakeSet(tuple(takes), tuple(labels), tuple(names))


def _read(files: Sequence[Path]) -> list[Trajectory]:
    """The takes of ``files``, in order; a bad one raises :class:`DatasetError` naming it."""
    try:
        return [Trajectory.from_csv(f) for f in files]
    except FramefreeError as exc:
        raise DatasetError(f"bad take: {exc}") from exc


def combine_takes(parts: Sequence[tuple[str, TakeSet]], merge: Iterable[str] = ()) -> TakeSet:
    """The takes of several sources as one vocabulary, refusing what would corrupt it.

    Parameters
    ----------
    parts : sequence of (str, TakeSet)
        Each source (a folder or library file, for messages) and its takes.
    merge : iterable of str
        Gestures whose takes may come from several sources (e.g. a second person's takes of the
        same gesture); any other gesture name found in two sources is an error.

    Raises
    ------
    LibraryError
        When two sources hold a gesture of the same name that was not named in ``merge`` (two
        different gestures would silently become one).
    """
    allowed = set(merge)
    owner: dict[str, str] = {}
    for source, part in parts:
        for g in part.gestures:
            if g in owner and owner[g] != source and g not in allowed:
                raise LibraryError(
                    f"gesture {g!r} is in both {owner[g]} and {source}: rename one of the folders if "
                    f"they are different gestures, or add --merge {g} to pool their takes")
            owner.setdefault(g, source)
    takes = parts[0][1]
    for _, part in parts[1:]:
        takes = takes + part
    return takes


def refuse_copies(takes: LabelledTakes) -> None:
    """Raise :class:`LibraryError` if a take is an exact copy of another (the same samples, at any
    time offset): leave-one-out calibration would put its gesture's threshold at about zero."""
    seen: dict[bytes, str] = {}
    for name, rows in zip(takes.names, takes.rows(), strict=True):
        key = hashlib.sha256(np.ascontiguousarray(rows[:, 1:]).tobytes()).digest()
        if key in seen:
            raise LibraryError(f"take {name} is an exact copy of take {seen[key]}: remove one "
                               f"(--remove {name}); a copied take makes its gesture's threshold "
                               "meaningless")
        seen[key] = name


def _natural(name: str) -> list:
    return [int(s) if s.isdigit() else s for s in re.split(r"(\d+)", name)]
