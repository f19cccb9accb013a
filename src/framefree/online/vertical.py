"""Which way is up, when the user knows it: how vertically a motion moves.

Frame-free recognition cannot tell a Z from an N: turned by a quarter turn in its plane, one is
the other. Where the tracking system's vertical is known (a SteamVR room is y-up and framefree's
OpenVR source keeps it so; a ROS world, framefree's own frame and files read with a named
convention are z-up), the recognizer may use it (``RecognizerConfig.up``, off
by default): a candidate is refused as a gesture whose demonstrations move much more or much less
vertically than it does. Only the vertical is used, never a heading: turning the base stations
about the vertical, or standing elsewhere in the room, changes nothing.

*Verticality* is the fraction of the hand's path that goes along the vertical,

    v = Σ |Δp · up| / Σ |Δp|,  in [0, 1],

over a motion's positions: 0 for a motion in a horizontal plane, 1 for one straight up and down,
about 0.3 for a Z drawn on a wall and 0.8 for an N. It does not depend on the motion's size,
pace, heading, mirror image or the tracker's place in the hand (positions only).

A gesture's limits are the range of its demonstrations' verticality widened by
:data:`VERTICAL_MARGIN` on both sides: how far another person goes beyond one person's range,
measured on the real Vive recordings of six people (``benchmarks/real_vertical.py``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["AXES", "VERTICAL_MARGIN", "up_vector", "vertical_limits", "verticality"]

#: The axis names :func:`up_vector` accepts.
AXES = ("+x", "-x", "+y", "-y", "+z", "-z")

#: How far [fraction of path] another person's verticality may lie outside one person's range of
#: takes. On the real Vive recordings' 2 974 such comparisons, with takes cut at v17's rest level,
#: 0.45 lets 98.3 % through (the 99th percentile is 0.52, the largest 0.79); a wider margin would
#: let an N through as a Z (about 0.8 against 0.3). v16's level, at which the slowest takes
#: started no unit, gave a 99th percentile of 0.30 over 2 552. ``benchmarks/real_vertical.py``.
VERTICAL_MARGIN = 0.45


def up_vector(up: str) -> np.ndarray:
    """The unit vector (3,) of an axis name (:data:`AXES`, e.g. ``"+y"``).

    Raises
    ------
    ValueError
        For any other name.
    """
    name = str(up).strip().lower()
    if name in ("x", "y", "z"):
        name = "+" + name
    if name not in AXES:
        raise ValueError(f"up must be one of {', '.join(AXES)} (the axis that points up), got {up!r}")
    out = np.zeros(3)
    out["xyz".index(name[1])] = 1.0 if name[0] == "+" else -1.0
    return out


def verticality(poses: np.ndarray, up: np.ndarray) -> float:
    """Fraction of the path of ``poses`` that goes along ``up``.

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4) or (n, 3)
        Poses (homogeneous) or positions [m].
    up : ndarray, shape (3,)
        Unit vector of the vertical.

    Returns
    -------
    float
        ``Σ |Δp · up| / Σ |Δp|`` in [0, 1]; NaN for a motion that does not move (fewer than two
        samples, or no path), which no limit refuses.
    """
    poses = np.asarray(poses, dtype=np.float64)
    positions = poses[:, :3, 3] if poses.ndim == 3 else poses
    steps = np.diff(positions, axis=0)
    path = float(np.linalg.norm(steps, axis=1).sum()) if len(steps) else 0.0
    if not path > 0.0:
        return float("nan")
    return min(1.0, float(np.abs(steps @ up).sum()) / path)


def vertical_limits(values: Sequence[float], margin: float = VERTICAL_MARGIN
                    ) -> tuple[float, float] | None:
    """Verticality a gesture may have: its demonstrations' range widened by ``margin`` on both
    sides, clipped to [0, 1]; ``None`` (no limit) when no demonstration moves."""
    finite = [float(v) for v in values if np.isfinite(v)]
    if not finite:
        return None
    return max(0.0, min(finite) - margin), min(1.0, max(finite) + margin)
