"""Dataset layout ``<root>/<gesture>/<context>/<trial>.csv``: names and the loader.

See docs/dataset.md (*Loader*) and docs/algorithms/table1-protocol.md (*Sets*).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..core.trajectory import Trajectory
from ..errors import DatasetError, FramefreeWarning, TrajectoryError

__all__ = [
    "CONTEXTS",
    "GESTURES",
    "MODEL_CONTEXT",
    "REPLICA_CONTEXTS",
    "STREAMS_DIR",
    "STRESS_CONTEXTS",
    "Dataset",
    "LayoutWarning",
    "ModelSet",
    "Trial",
    "is_training_trial",
    "load_dataset",
    "load_model_recordings",
    "people_trials",
    "resolve_models",
]

#: The seven HPM gesture folders, in the order of the paper's Section III. A loaded dataset lists its
#: gestures sorted (the class-label order of the reference).
GESTURES = ("go_left", "go_right", "go_up", "go_down", "open_gripper", "close_gripper", "go_home")
#: The twelve HPM contexts, in the order of the paper's Section III (docs/dataset.md, *The twelve
#: contexts*).
CONTEXTS = (
    "original_1",
    "original_2",
    "slower",
    "faster",
    "first_half",
    "body_frame_1",
    "body_frame_2",
    "body_frame_3",
    "world_frame_1",
    "world_frame_2",
    "world_frame_3",
    "combination",
)
#: Stress contexts beyond the paper, after its twelve in the replica and in Table I: 3 mm / 3°
#: noise, time × 3, a random world and body frame per trial, and a second person
#: (:mod:`~framefree.replica.contexts`, ``docs/dataset.md``).
STRESS_CONTEXTS = ("heavy_noise", "slower_3x", "random_frames", "other_person")
#: Every context of the replica, in table order.
REPLICA_CONTEXTS = (*CONTEXTS, *STRESS_CONTEXTS)
#: The context whose trials are the 1-NN models.
MODEL_CONTEXT = "original_1"
#: A top-level folder of this name holds continuous streams, not a gesture; the loader skips it.
STREAMS_DIR = "streams"

_SPLITS = ("train", "test", "all")


def is_training_trial(name: str) -> bool:
    """Reference split rule: a file stem ending in ``1`` or ``2`` is a training trial.

    See docs/algorithms/table1-protocol.md, *Sets*.
    """
    return name[-1:] in ("1", "2")


def _natural_key(name: str) -> list:
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name)]


@dataclass(frozen=True)
class Trial:
    """One recording of a dataset.

    Attributes
    ----------
    gesture : str
        Gesture (class) folder name.
    context : str
        Context folder name.
    name : str
        File stem, e.g. ``"trial_3"``.
    path : Path
        The CSV file.
    trajectory : Trajectory
        The loaded poses.
    """

    gesture: str
    context: str
    name: str
    path: Path
    trajectory: Trajectory = field(repr=False)

    @property
    def is_training(self) -> bool:
        """Whether the trial belongs to the training split (stem ends in 1 or 2)."""
        return is_training_trial(self.name)


@dataclass(frozen=True)
class Dataset:
    """A loaded gesture dataset.

    Attributes
    ----------
    root : Path
    gestures : tuple of str
        Gesture folder names, sorted (class label order).
    contexts : tuple of str
        Context folder names: those of :data:`REPLICA_CONTEXTS` in table order, then any others
        sorted.
    model_context : str
    trials : list of Trial
        Every trial, by gesture, context and natural trial order.
    """

    root: Path
    gestures: tuple[str, ...]
    contexts: tuple[str, ...]
    model_context: str
    trials: list[Trial] = field(repr=False)

    def __len__(self) -> int:
        return len(self.trials)

    def select(
        self, gesture: str | Sequence[str] | None = None, context: str | Sequence[str] | None = None
    ) -> list[Trial]:
        """Trials of the given gesture(s) and context(s) (``None``: all)."""
        g = {gesture} if isinstance(gesture, str) else None if gesture is None else set(gesture)
        c = {context} if isinstance(context, str) else None if context is None else set(context)
        return [t for t in self.trials if (g is None or t.gesture in g) and (c is None or t.context in c)]

    def models(self) -> list[Trial]:
        """Trials of the model context (the 1-NN neighbours)."""
        return self.select(context=self.model_context)

    def queries(self, split: str = "all") -> list[Trial]:
        """Trials of every other context: ``"train"`` (stem ends in 1 or 2), ``"test"`` or ``"all"``."""
        if split not in _SPLITS:
            raise ValueError(f"split must be one of {_SPLITS}, got {split!r}")
        out = [t for t in self.trials if t.context != self.model_context]
        if split == "train":
            out = [t for t in out if t.is_training]
        elif split == "test":
            out = [t for t in out if not t.is_training]
        return out


class LayoutWarning(FramefreeWarning):
    """A dataset or models folder holds something that is not a recording; it is skipped."""

    def __init__(self, path: Path, folder: Path, what: str) -> None:
        self.problem = f"skipped: not a .csv recording ({folder} should contain only {what})"
        super().__init__(f"{path}: {self.problem}")


def _entries(folder: Path) -> list[Path]:
    visible = (p for p in folder.iterdir() if not p.name.startswith("."))
    return sorted(visible, key=lambda p: _natural_key(p.name))


def _is_csv(path: Path) -> bool:
    return path.suffix.lower() == ".csv"


def _without_stray_files(folder: Path, entries: list[Path], what: str) -> list[Path]:
    """``entries`` less the files that are not CSV (each skipped with a :class:`LayoutWarning`)."""
    kept = []
    for p in entries:
        if p.is_file() and not _is_csv(p):
            warnings.warn(LayoutWarning(p, folder, what), stacklevel=4)
        else:
            kept.append(p)
    return kept


def _subfolders(folder: Path, what: str, skip: tuple[str, ...] = ()) -> list[Path]:
    entries = [p for p in _entries(folder) if p.name not in skip]
    entries = _without_stray_files(folder, entries, f"{what} folders")
    stray = [p for p in entries if not p.is_dir()]
    if stray:
        raise DatasetError(
            f"{stray[0]}: unexpected file; {folder} should contain only {what} folders"
        )
    if not entries:
        raise DatasetError(f"{folder}: empty folder, expected {what} folders")
    return entries


def _trial_files(cdir: Path) -> list[Path]:
    """The .csv files of a context folder (other files skipped with a warning)."""
    files = _without_stray_files(cdir, _entries(cdir), ".csv trials")
    if not files:
        raise DatasetError(f"{cdir}: empty folder, expected trial CSV files")
    for f in files:
        if f.is_dir():
            raise DatasetError(f"{f}: unexpected folder; {cdir} should contain only .csv trials")
    return files


def _load_trial(f: Path, quat_order: str, units: str, skip_header: bool = False) -> Trajectory:
    try:
        return Trajectory.from_csv(f, quat_order=quat_order, units=units, skip_header=skip_header)
    except TrajectoryError as exc:
        raise DatasetError(f"bad trial file: {exc}") from exc


def _context_order(names: set[str]) -> tuple[str, ...]:
    known = [c for c in REPLICA_CONTEXTS if c in names]
    return (*known, *sorted(names - set(known), key=_natural_key))


def _check_root(root: Path) -> None:
    if not root.exists():
        raise DatasetError(f"{root}: no such dataset folder")
    if not root.is_dir():
        raise DatasetError(f"{root}: not a folder (expected <root>/<gesture>/<context>/<trial>.csv)")


def load_dataset(
    root: str | Path,
    model_context: str = MODEL_CONTEXT,
    quat_order: str = "wxyz",
    units: str = "m",
    skip_header: bool = False,
) -> Dataset:
    """Load a dataset laid out as ``<root>/<gesture>/<context>/<trial>.csv``.

    Names are read from disk; entries starting with ``.`` and a top-level :data:`STREAMS_DIR`
    folder are skipped, and so are files that are not ``.csv`` (with a :class:`LayoutWarning`).
    Every trial is loaded.

    Parameters
    ----------
    root : str or Path
    model_context : str
        Name of the context whose trials are the models; every gesture must have it.
    quat_order : {"wxyz", "xyzw"}
        Quaternion column order of the files.
    units : {"m", "cm", "mm"}
        Unit of the files' positions.
    skip_header : bool
        Every file starts with a header row of other names than ``t,x,y,z,qw,qx,qy,qz`` (that
        one is always read as a header).

    Returns
    -------
    Dataset

    Raises
    ------
    DatasetError
        For a missing or empty folder, a misplaced CSV file or folder, a gesture without the model
        context, or a malformed CSV file (the message names the file and row).
    """
    root = Path(root).expanduser()
    _check_root(root)
    trials: list[Trial] = []
    contexts: set[str] = set()
    gestures = _subfolders(root, "gesture", skip=(STREAMS_DIR,))
    for gdir in gestures:
        cdirs = _subfolders(gdir, "context")
        names = {c.name for c in cdirs}
        if model_context not in names:
            raise DatasetError(
                f"{gdir}: no model context folder {model_context!r} (found: {', '.join(sorted(names))})"
            )
        contexts |= names
        for cdir in sorted(cdirs, key=lambda p: _context_order(names).index(p.name)):
            for f in _trial_files(cdir):
                trials.append(
                    Trial(gdir.name, cdir.name, f.stem, f,
                          _load_trial(f, quat_order, units, skip_header))
                )
    return Dataset(
        root=root,
        gestures=tuple(sorted(g.name for g in gestures)),
        contexts=_context_order(contexts),
        model_context=model_context,
        trials=trials,
    )


@dataclass(frozen=True)
class ModelSet:
    """Labelled model recordings found in a folder by :func:`resolve_models`.

    Attributes
    ----------
    trajectories : list of Trajectory
    labels : list of str
        The label (gesture folder name) of each recording.
    layout : {"dataset", "labelled", "people"}
        ``"dataset"``: ``<root>/<gesture>/<context>/*.csv`` (the model context's recordings);
        ``"labelled"``: ``<root>/<label>/*.csv``; ``"people"``: ``<root>/<person>/<label>/*.csv``
        (:func:`people_trials`).
    description : str
        One line saying what was found, for the user.
    """

    trajectories: list[Trajectory] = field(repr=False)
    labels: list[str]
    layout: str
    description: str


def _layout_of(root: Path) -> str:
    """"dataset" when the label folders hold folders, "labelled" when they hold CSV files."""
    kinds = set()
    for sub in _entries(root):
        if sub.is_dir() and sub.name != STREAMS_DIR:
            inner = _entries(sub)
            if any(p.is_dir() for p in inner):
                kinds.add("dataset")
            if any(p.is_file() and _is_csv(p) for p in inner):
                kinds.add("labelled")
    if not kinds:
        raise DatasetError(
            f"{root}: no models found; expected a dataset root <gesture>/<context>/*.csv or a "
            "folder of <label>/*.csv recordings"
        )
    if len(kinds) > 1:
        raise DatasetError(
            f"{root}: mixes <label>/*.csv files and <gesture>/<context>/ folders; use one layout"
        )
    return kinds.pop()


def people_trials(root: str | Path, contexts: tuple[str, ...] = (MODEL_CONTEXT, "own")
                  ) -> list[tuple[str, str, Path]] | None:
    """The recordings of a folder of people ``<root>/<person>/<label>/*.csv``, as (label, person,
    file), or None when ``root`` is not one.

    Such a folder has the shape of a dataset root ``<gesture>/<context>/*.csv``. It is read as
    people when no first-level folder holds one of ``contexts`` (a dataset's model context, or
    the ``own`` folder that ``framefree record`` writes), there are several first-level folders
    and some holds several label folders of CSV files: the segmented examples of several people,
    each in their own folder. One gesture folder with two unknown contexts stays a dataset (and
    asks for ``--model-context``).
    """
    root = Path(root).expanduser()
    firsts = [p for p in _entries(root) if p.is_dir() and p.name != STREAMS_DIR]
    inner = {p: [q for q in _entries(p) if q.is_dir()] for p in firsts}
    if len(firsts) < 2 or any(q.name in contexts for qs in inner.values() for q in qs):
        return None
    if not any(len(qs) > 1 for qs in inner.values()):
        return None
    if any(not any(_is_csv(f) for f in _entries(q)) for qs in inner.values() for q in qs):
        return None
    return [(q.name, p.name, f) for p, qs in inner.items() for q in qs for f in _trial_files(q)]


def resolve_models(
    root: str | Path,
    model_context: str = MODEL_CONTEXT,
    quat_order: str = "wxyz",
    units: str = "m",
    skip_header: bool = False,
) -> ModelSet:
    """Model recordings from either layout every command accepts, and a line saying which it found.

    Parameters
    ----------
    root : str or Path
        A dataset root ``<root>/<gesture>/<context>/<trial>.csv`` (the ``model_context``
        recordings become the models), a folder of ``<root>/<label>/*.csv`` recordings, or a
        folder of people ``<root>/<person>/<label>/*.csv`` (:func:`people_trials`; only when
        ``model_context`` is the default).
    model_context : str
        Context folder of the models in a dataset root (ignored for a ``<label>/*.csv`` folder).
        When it is the default and missing, a gesture folder's only context is used (the ``own``
        folders that ``framefree record`` writes).
    quat_order : {"wxyz", "xyzw"}
        Quaternion column order of the model files.
    units : {"m", "cm", "mm"}
        Unit of the model files' positions.
    skip_header : bool
        Every model file starts with a header row of other names than ``t,x,y,z,qw,qx,qy,qz``
        (that one is always read as a header).

    Raises
    ------
    DatasetError
        If the folder has neither layout, mixes them, lacks the model context, or holds a bad CSV.
    """
    root = Path(root).expanduser()
    _check_root(root)
    trajs: list[Trajectory] = []
    labels: list[str] = []
    layout = _layout_of(root)
    asked = model_context
    people = people_trials(root) if layout == "dataset" and asked == MODEL_CONTEXT else None
    if people is not None:
        return _people_models(root, people, quat_order, units, skip_header)
    for gdir in _subfolders(root, "gesture" if layout == "dataset" else "label", skip=(STREAMS_DIR,)):
        if layout == "dataset":
            names = [c.name for c in _subfolders(gdir, "context")]
            if asked == MODEL_CONTEXT and model_context not in names and len(names) == 1:
                model_context = names[0]  # a library folder (framefree record writes "own")
            if model_context not in names:
                raise DatasetError(
                    f"{gdir}: no model context folder {model_context!r} (found: "
                    f"{', '.join(sorted(names))}); choose one with --model-context"
                )
            files = _trial_files(gdir / model_context)
        else:
            files = _trial_files(gdir)
        for f in files:
            trajs.append(_load_trial(f, quat_order, units, skip_header))
            labels.append(gdir.name)
    n_labels = len(set(labels))
    if layout == "dataset":
        what = f"dataset root, context {model_context!r} (<gesture>/{model_context}/*.csv)"
        if model_context != asked:
            what += f", the only context (no {asked!r})"
    else:
        what = "folder of <label>/*.csv recordings"
    description = f"models: {root} is a {what}: {len(trajs)} recordings of {n_labels} labels"
    return ModelSet(trajs, labels, layout, description)


def _people_models(root: Path, people: list[tuple[str, str, Path]], quat_order: str, units: str,
                   skip_header: bool) -> ModelSet:
    """:func:`resolve_models` for a folder of people (:func:`people_trials`): every person's
    recordings are models of their label."""
    from .gesture_level import oriented

    trajs = [_load_trial(f, quat_order, units, skip_header) for _, _, f in people]
    people, swapped = oriented(people, trajs)
    shape = "<label>/<person>/*.csv, as the motions group" if swapped else "<person>/<label>/*.csv"
    labels = [label for label, _, _ in people]
    n_people = len({person for _, person, _ in people})
    description = (f"models: {root} is a folder of people {shape} (no context "
                   f"folder {MODEL_CONTEXT!r}): {len(trajs)} recordings of {len(set(labels))} "
                   f"labels ({', '.join(sorted(set(labels)))}) from {n_people} people")
    return ModelSet(trajs, labels, "people", description)


def load_model_recordings(
    root: str | Path, model_context: str = MODEL_CONTEXT
) -> tuple[list[Trajectory], list[str]]:
    """The model recordings of a dataset folder (one context) and their gesture labels.

    Parameters
    ----------
    root : path
        A dataset root ``<root>/<gesture>/<context>/*.csv``.
    model_context : str
        The context whose recordings are the models.

    Returns
    -------
    trajectories : list of Trajectory
    labels : list of str
        The gesture of each recording.
    """
    trials = list(load_dataset(root, model_context=model_context).models())
    return [tr.trajectory for tr in trials], [tr.gesture for tr in trials]
