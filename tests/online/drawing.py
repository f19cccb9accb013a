"""Hand paths drawn in the air for the geometry tests: polylines stroke by stroke (minimum-jerk
strokes, the hand slowing down at every corner) and circles, as tracker poses in any world frame."""

from __future__ import annotations

import itertools
import math

import numpy as np

from framefree.core.trajectory import Trajectory
from framefree.online.segmentation import SpeedLevels

DT = 0.02
LEVELS = SpeedLevels(rest=0.03, move=0.045)


def min_jerk(n: int) -> np.ndarray:
    x = np.linspace(0.0, 1.0, n)
    return x**3 * (10 - 15 * x + 6 * x**2)


def drawn_positions(points: np.ndarray, stroke_s: float = 0.6, hold_s: float = 0.0) -> np.ndarray:
    """Positions (n, 3) of a polyline through ``points`` (k, 3), one minimum-jerk stroke per side
    with ``hold_s`` of stillness at each inner corner, and a second of rest at either end."""
    parts = [np.repeat(points[:1], round(1.0 / DT), axis=0)]
    for a, b in itertools.pairwise(points):
        parts.append(a + min_jerk(round(stroke_s / DT))[:, None] * (b - a))
        parts.append(np.repeat(b[None], round(hold_s / DT), axis=0))
    parts.append(np.repeat(points[-1:], round(1.0 / DT), axis=0))
    return np.concatenate(parts)


def fluent_positions(points: np.ndarray, overlap: float, stroke_s: float = 0.6) -> np.ndarray:
    """Positions (n, 3) of a polyline through ``points`` (k, 3) drawn fluently: each side a
    minimum-jerk stroke that begins ``overlap`` × a stroke before the previous one ends, the
    displacements adding up (the hand slows at a corner without stopping), and a second of rest
    at either end."""
    n = round(stroke_s / DT)
    step = round((1.0 - overlap) * n)
    total = step * (len(points) - 2) + n
    p = np.repeat(points[:1], total, axis=0).astype(float)
    for k, (a, b) in enumerate(itertools.pairwise(points)):
        s = np.zeros(total)
        s[k * step:k * step + n] = min_jerk(n)
        s[k * step + n:] = 1.0
        p += s[:, None] * (b - a)
    rest = round(1.0 / DT)
    return np.concatenate([np.repeat(p[:1], rest, axis=0), p, np.repeat(p[-1:], rest, axis=0)])


def circle_positions(radius: float = 0.12, duration: float = 2.0, pause_at: float | None = None,
            pause_s: float = 0.4, creep: float = 0.08) -> np.ndarray:
    """Positions (n, 3) of one turn of a circle in a minimum-jerk sweep; with ``pause_at`` (a
    fraction of the turn) the hand nearly stops there for ``pause_s``, creeping on at ``creep`` of
    its speed, then goes on: a hesitation."""
    n = round(duration / DT)
    angle = 2 * math.pi * min_jerk(n)
    if pause_at is not None:
        k = int(np.searchsorted(angle, 2 * math.pi * pause_at))
        step = creep * (angle[k + 1] - angle[k])
        slow = angle[k] + step * np.arange(1, round(pause_s / DT) + 1)
        angle = np.concatenate([angle[:k + 1], slow, angle[k + 1:] + (slow[-1] - angle[k])])
        # slow down into the near-stop and speed up out of it over a fifth of a second
        w = round(0.2 / DT)
        angle = np.convolve(np.pad(angle, w, mode="edge"), np.ones(w) / w, mode="same")[w:-w]
    rest = round(1.0 / DT)
    angle = np.concatenate([np.zeros(rest), angle, np.full(rest, angle[-1])])
    return np.stack([radius * np.sin(angle), radius * (1 - np.cos(angle)), np.zeros_like(angle)], 1)


def tracker_poses(positions: np.ndarray, X: np.ndarray) -> np.ndarray:
    """Poses (n, 4, 4) of a tracker at ``positions`` (palm down, not turning), seen in world
    frame ``X`` (4, 4)."""
    P = np.repeat(np.eye(4)[None], positions.shape[0], axis=0)
    P[:, :3, 3] = positions
    return X @ P


def drawn_takes(points: np.ndarray, n: int, rng: np.random.Generator) -> list[Trajectory]:
    """``n`` takes of a polyline in the identity frame, each corner moved by up to 2 cm within
    the drawing plane and drawn at its own pace."""
    out = []
    for _ in range(n):
        P = drawn_positions(points + rng.uniform(-0.02, 0.02, points.shape) * [1, 1, 0],
                            stroke_s=rng.uniform(0.5, 0.7))
        out.append(Trajectory.from_poses(DT * np.arange(P.shape[0]), tracker_poses(P, np.eye(4))))
    return out


def swipe_and_circle_takes(seed: int, swipe: np.ndarray) -> tuple[list[Trajectory], list[str]]:
    """Six takes of a straight swipe from ``swipe[0]`` to ``swipe[1]`` (2, 3) and six of a circle,
    each with a second of rest before and after, and their labels."""
    takes = drawn_takes(swipe, 6, np.random.default_rng(seed))
    for k in range(6):
        P = circle_positions(radius=0.1 + 0.01 * k, duration=1.8 + 0.1 * k)
        takes.append(Trajectory.from_poses(DT * np.arange(len(P)), tracker_poses(P, np.eye(4))))
    return takes, ["swipe"] * 6 + ["circle"] * 6
