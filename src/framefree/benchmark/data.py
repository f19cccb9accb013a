"""The data of the protocol: trials on disk, split into models, training and test queries.

Sets (docs/algorithms/table1-protocol.md): the **models** (1-NN neighbours) are all trials of the
model context; every other context contributes its trials whose file stem ends in ``1`` or ``2``
to the **training** set and the rest to the **test** set.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..core.trajectory import Trajectory
from ..errors import DatasetError
from .metrics import order_contexts

__all__ = [
    "DEFAULT_MODEL_CONTEXT",
    "BenchmarkData",
    "TrialRecord",
    "build_benchmark_data",
    "is_training_trial",
    "load_benchmark_data",
]

#: default model context of the HPM dataset (docs/algorithms/table1-protocol.md)
DEFAULT_MODEL_CONTEXT = "original_1"


# ------------------------------------------------------------------------------------------- sets
def is_training_trial(name: str) -> bool:
    """Split rule (docs/algorithms/table1-protocol.md): a trial is a training trial iff the last
    character of its file stem is ``1`` or ``2`` (so ``trial_11`` is a training trial, ``trial_3`` a
    test trial).

    Parameters
    ----------
    name : str
        File name (``trial_1.csv``) or stem (``trial_1``).
    """
    stem = Path(name).stem if name.lower().endswith(".csv") else name
    return stem[-1:] in ("1", "2")


@dataclass(frozen=True)
class TrialRecord:
    """One recorded trial as the benchmark needs it.

    Attributes
    ----------
    gesture : str
        Class label (gesture folder name).
    context : str
        Context folder name.
    name : str
        File stem, e.g. ``"trial_3"``.
    data : ndarray, shape (N, 8)
        ``t [s], x, y, z [m], qw, qx, qy, qz``.
    source : str
        Path of the file (for messages).
    """

    gesture: str
    context: str
    name: str
    data: np.ndarray = field(repr=False)
    source: str = ""


@dataclass
class BenchmarkData:
    """Models, training and test queries of a dataset.

    Attributes
    ----------
    root : str
        Dataset folder.
    gestures : list of str
        Class labels, sorted (the reference's label order).
    model_context : str
    contexts : list of str
        The query contexts (all contexts except the model context), in Table I order.
    models, train, test : list of TrialRecord
        Models: all trials of the model context, ordered by gesture then trial name (the 1-NN tie
        rule picks the first). Train/test: the other contexts split by :func:`is_training_trial`.
    """

    root: str
    gestures: list[str]
    model_context: str
    contexts: list[str]
    models: list[TrialRecord]
    train: list[TrialRecord]
    test: list[TrialRecord]

    @property
    def all_trials(self) -> list[TrialRecord]:
        """Models, then training trials, then test trials."""
        return [*self.models, *self.train, *self.test]

    def summary(self) -> str:
        """One line: counts of gestures, contexts and trials."""
        return (
            f"{len(self.gestures)} gestures, model context {self.model_context!r} "
            f"({len(self.models)} models), {len(self.contexts)} query contexts, "
            f"{len(self.train)} training / {len(self.test)} test trials"
        )


def _records_from_layout(root: Path) -> list[TrialRecord]:
    """Scan ``<root>/<gesture>/<context>/<trial>.csv`` (names starting with '.' skipped)."""
    out = []
    for g in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith(".")):
        # folders without context subfolders (e.g. ``streams/``) are not gestures
        for c in sorted(p for p in g.iterdir() if p.is_dir() and not p.name.startswith(".")):
            files = sorted(p for p in c.iterdir() if p.suffix.lower() == ".csv")
            for f in files:
                if f.name.startswith(".") or f.stem.endswith("_labels"):
                    continue
                traj = Trajectory.from_csv(f)
                out.append(TrialRecord(g.name, c.name, f.stem, traj.to_array(), str(f)))
    return out


def _records_from_dataset(ds: Any) -> list[TrialRecord]:
    out = []
    for tr in ds.trials:
        traj = tr.trajectory
        src = str(getattr(tr, "path", "") or getattr(traj, "source", "") or "")
        name = Path(str(tr.name)).stem
        out.append(TrialRecord(str(tr.gesture), str(tr.context), name, traj.to_array(), src))
    return out


def build_benchmark_data(
    records: Sequence[TrialRecord],
    model_context: str,
    root: str = "",
    contexts: Sequence[str] | None = None,
) -> BenchmarkData:
    """Split trial records into models, training and test queries (docs/algorithms/table1-protocol.md).

    Parameters
    ----------
    records : sequence of TrialRecord
    model_context : str
    root : str
        Dataset folder (for messages).
    contexts : sequence of str, optional
        Query contexts to keep (default: every context on disk). Both the training and the test
        queries come from these contexts only, so a subset is a smaller data set, not a filter
        on the test columns.

    Raises
    ------
    DatasetError
        If the model context has no trials, a requested context is not on disk, or there are no
        query trials.
    """
    records = list(records)
    if not records:
        raise DatasetError(f"{root}: no trials found (expected <gesture>/<context>/<trial>.csv)")
    contexts_on_disk = {r.context for r in records}
    if contexts is not None:
        unknown = [c for c in contexts if c not in contexts_on_disk]
        if unknown:
            raise DatasetError(
                f"{root}: context(s) {', '.join(unknown)} not found; contexts on disk: "
                f"{', '.join(order_contexts(sorted(contexts_on_disk)))}"
            )
        keep = {*contexts, model_context}
        records = [r for r in records if r.context in keep]
    contexts = {r.context for r in records}
    if model_context not in contexts:
        raise DatasetError(
            f"{root}: model context {model_context!r} not found; contexts on disk: "
            f"{', '.join(sorted(contexts))}"
        )
    gestures = sorted({r.gesture for r in records})
    gi = {g: i for i, g in enumerate(gestures)}
    key = lambda r: (gi[r.gesture], r.context, r.name)  # noqa: E731
    models = sorted((r for r in records if r.context == model_context), key=key)
    queries = sorted((r for r in records if r.context != model_context), key=key)
    train = [r for r in queries if is_training_trial(r.name)]
    test = [r for r in queries if not is_training_trial(r.name)]
    if not queries:
        raise DatasetError(f"{root}: no trials outside the model context {model_context!r}")
    return BenchmarkData(
        root=root,
        gestures=gestures,
        model_context=model_context,
        contexts=order_contexts(sorted(contexts - {model_context})),
        models=models,
        train=train,
        test=test,
    )


def load_benchmark_data(
    root: str | Path | None = None,
    model_context: str = DEFAULT_MODEL_CONTEXT,
    contexts: Sequence[str] | None = None,
) -> BenchmarkData:
    """Load a dataset folder laid out as ``<root>/<gesture>/<context>/<trial>.csv``.

    Parameters
    ----------
    root : str or Path, optional
        Dataset folder; default: the HPM replica (``framefree.replica.replica_path()``).
    model_context : str
        Context whose trials are the models.
    contexts : sequence of str, optional
        Query contexts to use (default: all); see :func:`build_benchmark_data`.

    Raises
    ------
    DatasetError
        If the folder is missing or has no usable layout.
    """
    if root is None:
        try:
            from ..replica import replica_path
        except ImportError as exc:
            raise DatasetError(
                "no --data given and the HPM replica is not available in this installation "
                f"({exc}); pass --data DIR"
            ) from None
        root = replica_path()
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f"{root}: dataset folder does not exist")
    try:
        from ..datasets import load_dataset
    except ImportError:
        load_dataset = None
    if load_dataset is not None:
        records = _records_from_dataset(load_dataset(root, model_context=model_context))
    else:
        records = _records_from_layout(root)
    return build_benchmark_data(records, model_context, str(root), contexts)
