"""Benchmark results as a Markdown table in the layout of the paper's Table I, CSV and JSON.

The Markdown table prints, per row, our recognition ratio with the paper's number beside it in
parentheses. Its columns follow Table I: original 2, slower, faster, half, Δ{b} (pooled over the
body-frame contexts), Δ{w} (pooled over the world-frame contexts), combination, mean ± σ; contexts
that Table I does not have (a dataset with other context names) get columns of their own.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..metrics import GROUP_PATTERNS
from ..paper import PAPER_COLUMNS, PAPER_TABLE1
from ..protocol import BenchmarkResult, RowResult

__all__ = [
    "markdown_table",
    "result_to_dict",
    "table_columns",
    "write_csv",
    "write_json",
    "write_markdown",
]

_HEADERS = {
    "original_2": "original 2",
    "slower": "slower",
    "faster": "faster",
    "first_half": "half",
    "body_frame": "Δ{b}",
    "world_frame": "Δ{w}",
    "combination": "comb.",
    "heavy_noise": "noise ×3",
    "slower_3x": "slower ×3",
    "random_frames": "random frames",
    "other_person": "other person",
}


def table_columns(contexts: list[str]) -> list[str]:
    """Columns of the paper layout for these query contexts.

    Contexts of a pooled group (``body_frame_*``, ``world_frame_*``) collapse into the group's
    column, at the position of its first member; every other context is a column of its own.
    """
    cols: list[str] = []
    for c in contexts:
        group = next((g for g, pat in GROUP_PATTERNS.items() if pat.match(c)), None)
        col = group or c
        if col not in cols:
            cols.append(col)
    return cols


def _value(row: RowResult, col: str) -> float:
    if col in row.pooled:
        return row.pooled[col]
    return row.per_context.get(col, float("nan"))


def _fmt(v: float | None) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    r = round(float(v), 1)
    return "100" if r == 100.0 else f"{r:.1f}"


def _fmt_params(row: RowResult) -> str:
    """Trained parameters with units: ``λ = 0.1, L = 0.5 m``; ξ in degrees for angle progress."""
    parts = []
    for k, v in row.trained.items():
        if k == "lam":
            parts.append(f"λ = {v:g}")
        elif k == "ds_scale":
            if row.spec.progress == "angle":
                parts.append(f"ξ = {round(math.degrees(v), 6):g}°")
            else:
                parts.append(f"ξ = {v:g} m")
        elif k == "L":
            parts.append(f"L = {v:g} m")
        else:
            parts.append(f"{k} = {v:g}")
    return ", ".join(parts) or "–"


def markdown_table(result: BenchmarkResult, with_paper: bool = True) -> str:
    """Table I layout: one line per row, cells ``ours (paper)``.

    Parameters
    ----------
    result : BenchmarkResult
    with_paper : bool
        Put the paper's number in parentheses beside ours where Table I has one.

    Returns
    -------
    str
        A Markdown table followed by a table of trained parameters and run times.
    """
    cols = table_columns(result.contexts)
    head = ["method", "progress", *[_HEADERS.get(c, c) for c in cols], "mean ± σ"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in result.rows:
        paper = PAPER_TABLE1.get(row.spec.key) if with_paper else None
        cells = [row.spec.display_name, row.spec.progress_name]
        for c in cols:
            ours = _fmt(_value(row, c))
            if paper is not None and c in paper:
                ours += f" ({_fmt(paper[c])})"
            cells.append(ours)
        ms = f"{_fmt(row.mean)} ± {_fmt(row.std)}"
        if paper is not None:
            ms += f" ({_fmt(paper['mean'])} ± {_fmt(paper['std'])})"
        cells.append(ms)
        lines.append("| " + " | ".join(cells) + " |")
    out = "\n".join(lines) + "\n"
    out += "\n| method | progress | trained parameters | training RR | test RR (all) | seconds |\n"
    out += "|---|---|---|---|---|---|\n"
    for row in result.rows:
        out += (
            f"| {row.spec.display_name} | {row.spec.progress_name} | "
            f"{_fmt_params(row)} | {_fmt(row.train_ratio)} | {_fmt(row.overall)} | "
            f"{row.seconds:.1f} |\n"
        )
    return out


def _settings_lines(result: BenchmarkResult) -> list[str]:
    st = result.settings
    notes = []
    if st.get("presmooth"):
        notes.append(
            f"**framefree extension, not the paper's protocol:** the 50 Hz poses were "
            f"Gaussian-smoothed (window {st['presmooth']} samples) before progress and descriptors."
        )
    if st.get("round_digits"):
        notes.append(
            f"Descriptors rounded to {st['round_digits']} significant digits, as the reference "
            "stores them (docs/algorithms/dtw.md)."
        )
    if st.get("n_samples", 50) != 50:
        notes.append(f"{st['n_samples']} progress samples per trajectory (the paper: 50).")
    return [*(n + "\n" for n in notes)]


def write_markdown(result: BenchmarkResult, path: str | Path, title: str | None = None) -> Path:
    """Write :func:`markdown_table` with a short header (dataset, counts, timing) to ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    t = result.timing
    header = [
        f"# {title or 'Recognition results (%) — framefree benchmark'}",
        "",
        f"Dataset `{result.data_root}`; models: `{result.model_context}` "
        f"({result.counts['models']} trials); "
        f"{result.counts['train']} training and {result.counts['test']} test trials in "
        f"{len(result.contexts)} contexts. Cells: ours (paper, Table I of arXiv 2503.11352). "
        "Δ{b}, Δ{w}: pooled over the body-/world-frame contexts; mean ± σ over the individual "
        "contexts (sample σ of per-context ratios rounded to 0.1).",
        "",
        *_settings_lines(result),
        f"Run: {result.backend}; {t.get('total', float('nan')):.1f} s wall-clock "
        f"(descriptors {t.get('descriptors', float('nan')):.1f} s, matching "
        f"{t.get('matching', float('nan')):.1f} s of compute).",
        "",
        "",
    ]
    path.write_text("\n".join(header) + markdown_table(result), encoding="utf-8")
    return path


def _jsonable(v: Any) -> Any:
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.ndarray):
        return _jsonable(v.tolist())
    if isinstance(v, np.generic):
        return _jsonable(v.item())
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def row_to_dict(row: RowResult, gestures: list[str]) -> dict[str, Any]:
    """JSON-ready description of one row (percentages, parameters, seconds)."""
    return _jsonable(
        {
            "method": row.spec.method_name,
            "descriptor": row.spec.method,
            "progress": row.spec.progress,
            "label": row.spec.label,
            "presmooth": row.spec.presmooth,
            "trained_parameters": row.trained,
            "descriptor_parameters": row.params,
            "training_ratio": row.train_ratio,
            "per_context": row.per_context,
            "pooled": row.pooled,
            "mean": row.mean,
            "std": row.std,
            "overall": row.overall,
            "seconds": row.seconds,
            "descriptor_seconds": row.descriptor_seconds,
            "matching_seconds": row.matching_seconds,
            "grid": row.grid,
            "confusion": {"labels": gestures, "counts": row.confusion},
            "confusion_by_context": row.confusion_by_context,
            "failures": row.failures,
            "paper": PAPER_TABLE1.get(row.spec.key),
        }
    )


def result_to_dict(result: BenchmarkResult) -> dict[str, Any]:
    """JSON-ready description of a whole run."""
    return _jsonable(
        {
            "data": result.data_root,
            "model_context": result.model_context,
            "gestures": result.gestures,
            "contexts": result.contexts,
            "counts": result.counts,
            "backend": result.backend,
            "settings": result.settings,
            "timing_seconds": result.timing,
            "rows": [row_to_dict(r, result.gestures) for r in result.rows],
        }
    )


def write_json(result: BenchmarkResult, path: str | Path) -> Path:
    """Write :func:`result_to_dict` to ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(result_to_dict(result), indent=2, allow_nan=False)
    path.write_text(text + "\n", encoding="utf-8")
    return path


def write_csv(result: BenchmarkResult, path: str | Path) -> Path:
    """One line per row: parameters, per-context and pooled RRs [%], mean, std, seconds, and the
    paper's values."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    groups = sorted({g for r in result.rows for g in r.pooled})
    paper_cols = [*PAPER_COLUMNS, "mean", "std"]
    fields = [
        "method", "progress", "lam", "ds_scale", "L", "training_ratio",
        *result.contexts, *groups, "mean", "std", "overall", "seconds",
        *[f"paper_{c}" for c in paper_cols],
    ]  # fmt: skip
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        for r in result.rows:
            paper = PAPER_TABLE1.get(r.spec.key, {})
            rec: dict[str, Any] = {
                "method": r.spec.method_name,
                "progress": r.spec.progress,
                "lam": r.trained.get("lam", ""),
                "ds_scale": r.trained.get("ds_scale", ""),
                "L": r.trained.get("L", ""),
                "training_ratio": f"{r.train_ratio:.2f}",
                "mean": f"{r.mean:.2f}",
                "std": f"{r.std:.2f}",
                "overall": f"{r.overall:.2f}",
                "seconds": f"{r.seconds:.3f}",
            }
            for c in result.contexts:
                rec[c] = f"{r.per_context.get(c, float('nan')):.2f}"
            for g in groups:
                rec[g] = f"{r.pooled[g]:.2f}" if g in r.pooled else ""
            for c in paper_cols:
                rec[f"paper_{c}"] = paper.get(c, "")
            w.writerow(rec)
    return path
