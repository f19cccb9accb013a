"""Early recognition: how well a trained row recognizes a gesture it has only partly seen.

Each test trial is cut to the first ``ceil(f · N)`` of its N samples (``f`` = 25, 50, 75, 100 %)
and classified against the full models with the row's trained parameters, exactly as the test
stage of the protocol does it (same resampling, pre-smoothing, reparameterization, descriptor and
distance). Contexts whose trials are already unfinished (``first_half``, ``combination``) are
left out, so that ``f`` is the fraction of the whole gesture. Nothing is retrained: the
parameters are those the grid search chose on the (complete) training trials.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..core.trajectory import Trajectory
from .protocol import (
    BenchmarkData,
    RowResult,
    TrialRecord,
    evaluate_task,
    predict_from_distances,
    reparameterize_task,
    resample_task,
)

__all__ = [
    "EARLY_FRACTIONS",
    "UNFINISHED_CONTEXTS",
    "EarlyResult",
    "early_markdown",
    "early_recognition",
    "plot_early",
    "write_early_json",
]

#: fractions of each test trial shown to the classifier
EARLY_FRACTIONS: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0)
#: contexts whose trials are already cut short; left out of the early-recognition set
UNFINISHED_CONTEXTS: frozenset[str] = frozenset({"first_half", "combination"})


@dataclass
class EarlyResult:
    """Recognition ratio [%] against the fraction of the gesture seen, per row.

    Attributes
    ----------
    fractions : tuple of float
    rows : dict
        ``{row key: {"label", "parameters", "overall": [RR per fraction],
        "per_context": {context: [RR per fraction]}}}``.
    contexts : list of str
        Contexts of the trials used.
    n_trials : int
    """

    fractions: tuple[float, ...]
    rows: dict[str, dict[str, Any]] = field(default_factory=dict)
    contexts: list[str] = field(default_factory=list)
    n_trials: int = 0


def _inputs(
    arrays: list[np.ndarray], row: RowResult, n_samples: int, presmooth: int | None
) -> list:
    """Descriptor inputs of trials (N_i, 8) as the row's test stage builds them."""
    spec, L = row.spec, row.params["L"]
    window = spec.presmooth if spec.presmooth is not None else presmooth
    poses = resample_task(arrays, presmooth=window)
    return reparameterize_task(
        poses, spec.progress, L if spec.progress == "screw" else 0.3, n_samples
    )


def _ratio(pred: Sequence[str | None], true: Sequence[str]) -> float:
    return 100.0 * float(np.mean([p == t for p, t in zip(pred, true, strict=True)]))


def early_recognition(
    data: BenchmarkData,
    rows: Sequence[RowResult],
    fractions: Sequence[float] = EARLY_FRACTIONS,
    n_samples: int = 50,
    presmooth: int | None = None,
) -> EarlyResult:
    """Recognition ratio of each trained row on test trials cut to each fraction.

    Parameters
    ----------
    data : BenchmarkData
        The data set the rows were trained on.
    rows : sequence of RowResult
        Trained rows (from :func:`~framefree.benchmark.run_benchmark`); their selected
        parameters are used unchanged.
    fractions : sequence of float
        Fractions in (0, 1].
    n_samples : int
        Progress samples per trajectory (50).
    presmooth : int, optional
        The run's pre-smoothing window, for rows without their own (as in ``run_benchmark``).

    Returns
    -------
    EarlyResult
    """
    trials: list[TrialRecord] = [r for r in data.test if r.context not in UNFINISHED_CONTEXTS]
    if not trials:
        raise ValueError("no test trials of complete gestures to cut")
    true = [r.gesture for r in trials]
    ctxs = [r.context for r in trials]
    contexts = [c for c in data.contexts if c in set(ctxs)]
    out = EarlyResult(tuple(float(f) for f in fractions), contexts=contexts, n_trials=len(trials))
    labels = [r.gesture for r in data.models]
    for row in rows:
        models = _inputs([m.data for m in data.models], row, n_samples, presmooth)
        entry: dict[str, Any] = {
            "label": row.spec.label,
            "parameters": dict(row.params),
            "overall": [],
            "per_context": {c: [] for c in contexts},
        }
        for f in out.fractions:
            cut = [Trajectory.from_array(r.data).head(f).to_array() for r in trials]
            res = evaluate_task(
                row.spec.method, [row.params], models, _inputs(cut, row, n_samples, presmooth)
            )
            pred = predict_from_distances(res[0].distances, labels)
            entry["overall"].append(_ratio(pred, true))
            for c in contexts:
                sel = [i for i, x in enumerate(ctxs) if x == c]
                entry["per_context"][c].append(
                    _ratio([pred[i] for i in sel], [true[i] for i in sel])
                )
        out.rows[row.spec.key] = entry
    return out


def write_early_json(result: EarlyResult, path: str | Path) -> Path:
    """Write the result as JSON (percentages)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    doc = {
        "fractions": list(result.fractions),
        "contexts": result.contexts,
        "n_trials": result.n_trials,
        "rows": result.rows,
    }
    path.write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
    return path


def early_markdown(result: EarlyResult) -> str:
    """A Markdown table: one line per row, one column per fraction."""
    head = ["method", *[f"{round(100 * f):d} %" for f in result.fractions]]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for entry in result.rows.values():
        cells = [entry["label"], *[f"{v:.1f}" for v in entry["overall"]]]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plot_early(result: EarlyResult, path: str | Path) -> Path:
    """Recognition ratio [%] against the fraction of the gesture seen [%], one line per row."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(5.0, 3.4), dpi=120)
    x = [100 * f for f in result.fractions]
    for entry, marker in zip(result.rows.values(), "osd^v<>", strict=False):
        ax.plot(x, entry["overall"], marker=marker, label=entry["label"])
    ax.set_xlabel("fraction of the gesture seen [%]")
    ax.set_ylabel("recognition ratio [%]")
    ax.set_xticks(x)
    ax.set_ylim(0, 102)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(f"Early recognition ({result.n_trials} test trials)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path
