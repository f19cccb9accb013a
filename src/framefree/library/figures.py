"""Figures of a vocabulary check: distance heat map and a gallery of the takes (matplotlib, Agg)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .check import CheckReport, CheckSettings
from .store import TakeSet

__all__ = ["plot_distance_map", "plot_take_gallery"]


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _margin_matrix(report: CheckReport) -> tuple[list[str], np.ndarray]:
    """(G, G) median over the row gesture's takes of the distance to the nearest take of the column
    gesture (own take excluded), divided by the row gesture's spread."""
    labels = np.array(report.labels)
    gestures = list(report.gestures)
    D = report.distances.astype(float).copy()
    np.fill_diagonal(D, np.inf)
    M = np.empty((len(gestures), len(gestures)))
    for i, g in enumerate(gestures):
        rows = D[labels == g]
        for j, h in enumerate(gestures):
            M[i, j] = np.median(rows[:, labels == h].min(axis=1)) / report.gestures[g].spread
    return gestures, M


def _draw_margins(ax, gestures: list[str], M: np.ndarray, s: CheckSettings) -> None:
    """The gesture-by-gesture margin matrix, annotated, problems red and warnings orange."""
    n = len(gestures)
    shown = np.where(np.eye(n, dtype=bool), np.nan, np.log10(np.clip(M, 0.1, 100.0)))
    ax.imshow(shown, cmap="RdYlGn", vmin=-1, vmax=2, interpolation="nearest")
    for i in range(n):
        for j in range(n):
            if i == j:
                continue
            bad = M[i, j] < s.fail_margin
            warn = M[i, j] < s.warn_margin
            ax.text(j, i, f"{M[i, j]:.1f}", ha="center", va="center", fontsize=6,
                    color="k", fontweight="bold" if warn else "normal",
                    bbox={"facecolor": "red" if bad else "orange", "lw": 0, "pad": 1} if warn else None)
    ax.set_xticks(range(n), gestures, rotation=60, ha="right", fontsize=7)
    ax.set_yticks(range(n), gestures, fontsize=7)
    ax.set_title(f"margin (×): row gesture vs column gesture\n(problem < {s.fail_margin}, "
                 f"warning < {s.warn_margin})", fontsize=9)


def plot_distance_map(report: CheckReport, path: str | Path, settings: CheckSettings | None = None) -> Path:
    """Two panels: take-to-take distances (log colour scale, grouped by gesture) and the margin of
    every gesture against every other (row: the gesture, column: the one it might be taken for;
    red below the problem level, orange below the warning level).

    Parameters
    ----------
    report : CheckReport
    path : str or Path
        Output image (PNG, PDF or SVG by extension).
    settings : CheckSettings, optional
        Margin levels for the colours.

    Returns
    -------
    Path
    """
    s = settings or CheckSettings()
    plt = _pyplot()
    labels = np.array(report.labels)
    gestures, M = _margin_matrix(report)
    order = np.concatenate([np.flatnonzero(labels == g) for g in gestures])
    D = report.distances[np.ix_(order, order)]
    n = len(gestures)
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(7 + 0.5 * n, 4 + 0.25 * n),
                                   gridspec_kw={"width_ratios": [1.15, 1]})
    off = ~np.eye(D.shape[0], dtype=bool)
    pos = D[off & (D > 0)]
    floor = pos.min() if pos.size else 1.0
    im = ax0.imshow(np.where(off, np.log10(np.maximum(D, floor)), np.nan), cmap="viridis_r",
                    interpolation="nearest")
    fig.colorbar(im, ax=ax0, fraction=0.046, label="log10 distance (BILTS+ DTW)")
    edges = np.cumsum([0] + [int((labels == g).sum()) for g in gestures])
    for e in edges[1:-1]:
        ax0.axhline(e - 0.5, color="w", lw=0.8)
        ax0.axvline(e - 0.5, color="w", lw=0.8)
    centres = 0.5 * (edges[:-1] + edges[1:]) - 0.5
    ax0.set_xticks(centres, gestures, rotation=60, ha="right", fontsize=7)
    ax0.set_yticks(centres, gestures, fontsize=7)
    ax0.set_title("take-to-take distances", fontsize=9)
    _draw_margins(ax1, gestures, M, s)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _aligned_paths(mine: list, n: int = 100) -> list[np.ndarray]:
    """Tracker paths (n, 3) of takes, each moved rigidly onto the first (least squares over ``n``
    time-normalized samples), so that the world frame does not matter."""
    paths = []
    for tr in mine:
        u = (tr.t - tr.t[0]) / max(tr.duration, 1e-9)
        paths.append(np.column_stack([np.interp(np.linspace(0, 1, n), u, tr.p[:, k]) for k in range(3)]))
    ref = paths[0] - paths[0][0]
    out = [ref]
    for P in paths[1:]:
        P = P - P[0]
        U, _, Vt = np.linalg.svd(P.T @ ref)
        d = np.sign(np.linalg.det(U @ Vt))
        R = U @ np.diag([1.0, 1.0, d]) @ Vt
        out.append(P @ R)
    return out


def plot_take_gallery(takes: TakeSet, path: str | Path, max_takes: int = 8) -> Path:
    """One 3D panel per gesture with its takes' tracker paths overlaid, each rotated onto the
    first take about its start point (so the world frame does not matter); a dot marks the start.

    Parameters
    ----------
    takes : TakeSet
    path : str or Path
        Output image.
    max_takes : int
        Takes drawn per gesture.

    Returns
    -------
    Path
    """
    plt = _pyplot()
    gestures = takes.gestures
    cols = min(4, len(gestures))
    rows = -(-len(gestures) // cols)
    fig = plt.figure(figsize=(3.2 * cols, 3.2 * rows))
    for i, g in enumerate(gestures):
        ax = fig.add_subplot(rows, cols, i + 1, projection="3d")
        mine = [tr for tr, lab in zip(takes.takes, takes.labels, strict=True) if lab == g]
        pts = _aligned_paths(mine[:max_takes])
        for k, p in enumerate(pts):
            ax.plot(p[:, 0], p[:, 1], p[:, 2], lw=0.9, color=plt.get_cmap("tab10")(k % 10))
        ax.scatter([0.0], [0.0], [0.0], s=8, color="k")
        allp = np.concatenate(pts)
        half = max(float(np.ptp(allp, axis=0).max()) / 2, 0.01)
        mid = 0.5 * (allp.max(axis=0) + allp.min(axis=0))
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, strict=True):
            setter(c - half, c + half)
        ax.tick_params(labelsize=5)
        ax.set_title(f"{g} ({len(mine)} takes)", fontsize=9)
    fig.suptitle("tracker paths of the takes, rotated onto the first take [m]", fontsize=10)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
