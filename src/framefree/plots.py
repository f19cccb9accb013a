"""Matplotlib figures: a trajectory as a 3-D path with orientation triads, and a gallery of gestures.

Figures are built with :class:`matplotlib.figure.Figure` and the Agg canvas, so nothing here touches
pyplot's global state or needs a display.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .core.trajectory import Trajectory

if TYPE_CHECKING:
    from mpl_toolkits.mplot3d import Axes3D

    from .datasets import Dataset

__all__ = ["plot_gallery", "plot_trajectory"]

_AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")


def _new_figure(size: tuple[float, float]) -> Figure:
    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _equal_box(ax: Axes3D, pts: np.ndarray) -> None:
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    mid, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-3)
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1))


def _speeds(traj: Trajectory) -> np.ndarray:
    """Speed [m/s] of the tracker origin at each sample."""
    return np.r_[0.0, np.linalg.norm(np.diff(traj.p, axis=0), axis=1) / np.diff(traj.t)]


def _key(fig: Figure, mappable: Any) -> None:
    """What the colours and markers mean: a speed colour bar, start/end markers, triad axes."""
    from matplotlib.lines import Line2D

    fig.colorbar(mappable, ax=fig.axes, shrink=0.5, pad=0.02, label="speed [m/s]")
    handles = [Line2D([], [], marker="o", color="k", ls="", label="start"),
               Line2D([], [], marker="s", color="k", ls="", label="end")]
    handles += [Line2D([], [], color=c, label=f"tracker {a} axis")
                for a, c in zip("xyz", _AXIS_COLORS, strict=True)]
    fig.legend(handles=handles, loc="lower right", bbox_to_anchor=(0.92, 0.04), fontsize=7, ncol=1,
               frameon=False)


def _draw(ax: Axes3D, traj: Trajectory, n_frames: int, triad_length: float | None,
          vmax: float | None = None) -> Any:
    p = traj.p - traj.p[0]  # start at the origin: the world frame is arbitrary anyway
    R = traj.rotations()
    extent = float(np.ptp(p, axis=0).max()) or 0.1
    length = triad_length if triad_length is not None else max(0.15 * extent, 0.03)
    speed = _speeds(traj)
    ax.plot(*p.T, color="0.3", lw=1.0)
    dots = ax.scatter(*p.T, c=speed, cmap="viridis", s=4, depthshade=False, vmin=0.0,
                      vmax=vmax if vmax is not None else max(float(speed.max()), 1e-6))
    ax.scatter(*p[0], color="k", s=25, marker="o")
    ax.scatter(*p[-1], color="k", s=25, marker="s")
    idx = np.unique(np.linspace(0, len(traj) - 1, n_frames).round().astype(int))
    for k in idx:
        for a in range(3):
            d = R[k, :, a] * length
            ax.plot(*np.c_[p[k], p[k] + d], color=_AXIS_COLORS[a], lw=1.2)
    _equal_box(ax, np.r_[p, p[idx] + length, p[idx] - length])
    ax.set_xlabel("x [m]", fontsize=7, labelpad=-6)
    ax.set_ylabel("y [m]", fontsize=7, labelpad=-6)
    ax.set_zlabel("z [m]", fontsize=7, labelpad=-6)
    ax.tick_params(labelsize=5, pad=-2)
    return dots


def plot_trajectory(
    traj: Trajectory,
    ax: Axes3D | None = None,
    path: str | Path | None = None,
    n_frames: int = 10,
    triad_length: float | None = None,
    title: str | None = None,
) -> Figure:
    """3-D path of the tracker origin with orientation triads (x red, y green, z blue).

    Parameters
    ----------
    traj : Trajectory
    ax : mpl_toolkits.mplot3d.Axes3D, optional
        Axes to draw in (default: a new figure).
    path : str or Path, optional
        Save the figure there as PNG.
    n_frames : int
        Number of triads, evenly spaced in time.
    triad_length : float, optional
        Triad axis length [m] (default: 15 % of the path extent, at least 3 cm).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        The path is drawn relative to the first sample, points coloured by speed; circle = start,
        square = end.
    """
    if ax is None:
        fig = _new_figure((5.0, 5.0))
        ax = fig.add_subplot(projection="3d")
    else:
        fig = ax.figure
    dots = _draw(ax, traj, n_frames, triad_length)
    ax.set_title(title if title is not None else (traj.source or ""), fontsize=9)
    _key(fig, dots)
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig


def plot_gallery(
    dataset_or_root: Dataset | str | Path,
    path: str | Path | None = None,
    context: str | None = None,
    trial: str | None = None,
) -> Figure:
    """One panel per gesture: a trial of the model context.

    Parameters
    ----------
    dataset_or_root : Dataset or str or Path
        A loaded dataset or its root folder.
    path : str or Path, optional
        Save the figure there as PNG.
    context : str, optional
        Context to show (default: the model context).
    trial : str, optional
        Trial name (default: the first trial of each gesture).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from .datasets import Dataset, load_dataset

    ds = dataset_or_root if isinstance(dataset_or_root, Dataset) else load_dataset(dataset_or_root)
    context = context or ds.model_context
    gestures = ds.gestures
    cols = min(4, len(gestures))
    rows = -(-len(gestures) // cols)
    fig = _new_figure((3.2 * cols + 1.0, 3.2 * rows + 0.4))
    shown = {g: [t for t in ds.select(g, context) if trial is None or t.name == trial] for g in gestures}
    vmax = max([float(_speeds(ts[0].trajectory).max()) for ts in shown.values() if ts] or [1.0])
    dots = None
    for i, g in enumerate(gestures):
        ax = fig.add_subplot(rows, cols, i + 1, projection="3d")
        if not shown[g]:
            ax.set_title(f"{g}: no {context}/{trial}", fontsize=9)
            continue
        dots = _draw(ax, shown[g][0].trajectory, 8, None, vmax)
        ax.set_title(f"{g.replace('_', ' ')} ({shown[g][0].name})", fontsize=9)
    fig.suptitle(f"{ds.root.name}: context {context}; paths from their start, coloured by speed",
                 fontsize=10)
    if dots is not None:
        _key(fig, dots)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
