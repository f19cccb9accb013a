"""Figures that help read a benchmark result.

* :func:`plot_heatmap` — recognition ratio by method/progress row × test context;
* :func:`plot_confusion` — confusion matrix of one row (rows = true gesture, normalized);
* :func:`plot_aligned_signals` — the descriptor signals of two trials, and how DTW pairs their
  samples (the warping path the classifier uses).

All functions write a PNG with matplotlib's non-interactive Agg backend and return the path.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np

from ..core.dtw import warping_path
from ..core.trajectory import Trajectory
from ..descriptors.base import Descriptor
from .protocol import BenchmarkResult, RowResult

__all__ = [
    "alignment_columns",
    "plot_aligned_signals",
    "plot_confusion",
    "plot_heatmap",
    "prealign",
]


def plot_heatmap(result: BenchmarkResult, path: str | Path) -> Path:
    """Heat map of the test recognition ratio [%]: rows = method/progress, columns = contexts.

    The last column is the mean over contexts. Cells are annotated with their value.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ctxs = list(result.contexts)
    M = np.array([[r.per_context.get(c, np.nan) for c in ctxs] + [r.mean] for r in result.rows])
    labels = [r.spec.label for r in result.rows]
    cols = [c.replace("_", " ") for c in ctxs] + ["mean"]
    fig, ax = plt.subplots(figsize=(1.0 + 0.62 * len(cols), 1.2 + 0.36 * len(labels)))
    im = ax.imshow(M, cmap="viridis", vmin=0, vmax=100, aspect="auto")
    ax.set_xticks(range(len(cols)), cols, rotation=40, ha="right", fontsize=8)
    ax.set_yticks(range(len(labels)), labels, fontsize=8)
    ax.axvline(len(ctxs) - 0.5, color="white", lw=2)
    for i in range(M.shape[0]):
        for j in range(M.shape[1]):
            v = M[i, j]
            if np.isfinite(v):
                ax.text(
                    j,
                    i,
                    f"{v:.0f}",
                    ha="center",
                    va="center",
                    fontsize=7,
                    color="black" if v > 60 else "white",
                )
    fig.colorbar(im, ax=ax, label="recognition ratio [%]", shrink=0.8)
    ax.set_title(f"Test recognition ratio, models = {result.model_context}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def plot_confusion(row: RowResult, gestures: list[str], path: str | Path) -> Path:
    """Row-normalized confusion matrix of one row on the test set (rows = true gesture).

    A last column "none" appears only if some test trial got no class.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    C = np.asarray(row.confusion, dtype=np.float64)
    cols = [*gestures, "none"]
    if C[:, -1].sum() == 0:
        C, cols = C[:, :-1], list(gestures)
    totals = C.sum(axis=1, keepdims=True)
    N = np.divide(C, totals, out=np.zeros_like(C), where=totals > 0)
    n = len(gestures)
    fig, ax = plt.subplots(figsize=(1.6 + 0.55 * len(cols), 1.4 + 0.5 * n))
    ax.imshow(N, cmap="Blues", vmin=0, vmax=1)
    ax.set_xticks(
        range(len(cols)), [c.replace("_", " ") for c in cols], rotation=40, ha="right", fontsize=8
    )
    ax.set_yticks(range(n), [g.replace("_", " ") for g in gestures], fontsize=8)
    ax.set_xlabel("recognized")
    ax.set_ylabel("true")
    for i in range(N.shape[0]):
        for j in range(N.shape[1]):
            if C[i, j]:
                ax.text(j, i, f"{int(C[i, j])}", ha="center", va="center", fontsize=7,
                        color="white" if N[i, j] > 0.5 else "black")  # fmt: skip
    ax.set_title(f"{row.spec.label}: test RR {row.overall:.1f} %", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def alignment_columns(descriptor: Descriptor, n_features: int) -> slice:
    """Feature columns the descriptor's classifier aligns with DTW (docs/algorithms/dtw.md).

    BILTS and BILTS+ align on their six singular values (columns 18–23); the others on all columns.
    Declared by the descriptor (:meth:`~framefree.descriptors.base.Descriptor.alignment_columns`).
    """
    return descriptor.alignment_columns(n_features)


def prealign(descriptor: Descriptor, model: np.ndarray, query: np.ndarray) -> np.ndarray:
    """The model sequence as the classifier compares it with the query.

    DSRF rotates the model by one global Kabsch rotation before DTW (docs/algorithms/dtw.md); every
    other descriptor compares the sequences as they are.

    Parameters
    ----------
    model, query : ndarray, shape (K, F)

    Returns
    -------
    ndarray, shape (K, F)
    """
    return descriptor.prealign(model, query)


def _feature_labels(descriptor: Descriptor, cols: slice, k: int) -> list[str]:
    """Names of the first ``k`` aligned features (the descriptor's own names where it has them)."""
    from ..descriptors import bilts

    names = list(bilts.FEATURE_NAMES) if descriptor.name.startswith("bilts") else []
    picked = names[cols][:k] if names else []
    return picked if len(picked) == k else [f"feature {cols.start + f}" for f in range(k)]


def _draw_pairs(ax, Xa: np.ndarray, Xb: np.ndarray, wp: np.ndarray, k: int, offset: float) -> None:
    """Both sequences (the query shifted down) and grey lines joining paired samples."""
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for f in range(k):
        c = colors[f % len(colors)]
        ax.plot(Xa[:, f], color=c, lw=1.5)
        ax.plot(Xb[:, f] - 2 * offset, color=c, lw=1.2, ls="--")
    for i, j in wp[:: max(1, len(wp) // 40)]:
        ax.plot([i, j], [Xa[i, 0], Xb[j, 0] - 2 * offset], color="0.6", lw=0.5, zorder=0)


def plot_aligned_signals(
    descriptor: Descriptor,
    model: Trajectory,
    query: Trajectory,
    path: str | Path,
    labels: tuple[str, str] = ("model", "query"),
    max_signals: int = 6,
) -> Path:
    """Descriptor signals of two trials and the DTW pairing of their samples.

    Top: the model's alignment signals (solid) and the query's (dashed) against their own sample
    index, with grey lines joining the samples that the warping path pairs. Bottom: the query
    warped onto the model's index (each path pair plotted at its model index), which shows what
    the classifier compares. BILTS and BILTS+ are aligned on their singular values (the signals
    shown); DSRF's model is first rotated onto the query (:func:`prealign`).

    Parameters
    ----------
    descriptor : Descriptor
        A configured descriptor (e.g. with the trained parameters of a benchmark row).
    model, query : Trajectory
    path : str or Path
        PNG file to write.
    labels : (str, str)
        Legend names of the two trials.
    max_signals : int
        Plot at most this many alignment features.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    A = np.asarray(descriptor.compute(model))
    B = np.asarray(descriptor.compute(query))
    A = prealign(descriptor, A, B)
    cols = alignment_columns(descriptor, A.shape[1])
    Xa, Xb = A[:, cols], B[:, cols]
    wp = warping_path(Xa, Xb)
    k = min(max_signals, Xa.shape[1])
    names = _feature_labels(descriptor, cols, k)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 7), sharex=False)
    offset = 1.1 * float(np.nanmax(np.abs(np.concatenate([Xa[:, :k], Xb[:, :k]])))) or 1.0
    _draw_pairs(ax1, Xa, Xb, wp, k, offset)
    ax1.set_title(f"{descriptor.label()}, {descriptor.progress} progress: the aligned features of "
                  f"both trials\n(dashed: shifted down by {2 * offset:.2g}); grey lines join the "
                  "samples DTW pairs", fontsize=9)
    ax1.set_xlabel("descriptor sample (equidistant progress)")
    ax1.set_ylabel("feature value")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for f in range(k):
        c = colors[f % len(colors)]
        ax2.plot(Xa[:, f], color=c, lw=1.5)
        ax2.plot(wp[:, 0], Xb[wp[:, 1], f], color=c, lw=1.0, ls="--", marker=".", ms=2)
    ax2.set_title(f"the dashed trial warped onto the solid one ({len(wp)} path pairs)", fontsize=9)
    ax2.set_xlabel("sample of the solid trial")
    ax2.set_ylabel("feature value")
    handles = [plt.Line2D([], [], color=colors[f % len(colors)], label=names[f]) for f in range(k)]
    handles += [plt.Line2D([], [], color="k", label=labels[0].replace("/", "/\n", 1)),
                plt.Line2D([], [], color="k", ls="--", label=labels[1].replace("/", "/\n", 1))]
    fig.legend(handles=handles, loc="center right", fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0, 0.8, 1))
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
