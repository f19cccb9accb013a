"""Random shapes drawn in the air: the unknown motions a gesture's threshold is placed against.

A threshold placed only between a gesture's demonstrations and the *other enrolled gestures*
depends on the company the gesture keeps: a shape enrolled alone gets a loose threshold, and any
unenrolled shape like it (a triangle for a zigzag, a square for a circle) fires. People draw
shapes of every kind, so the calibration also measures how close *random* drawn shapes come to
each gesture, whatever else is enrolled.

A scribble is built around a recording's start pose, as large and as fast as the recording:

* a random plane through the hand (any orientation: the descriptors do not see it);
* 2 to 5 strokes; every new direction turned from the last by an angle uniform in ±150° (a full
  reversal is an out-and-back move, which the ``moves`` family already covers); with probability
  ½ (three strokes or more) the last stroke returns to the start, as in a triangle or a square;
* the total length of the strokes is the recording's path length × a factor log-uniform in
  [1/1.3, 1.3] (the people's size range, :data:`framefree.online.thresholds.ONE_TAKE_SIZE`);
* half of them are polylines, each side a minimum-jerk stroke (the hand slows at every corner,
  and holds up to 80 ms at some), half are smooth curves through the same corners (corners cut
  by Chaikin's scheme) drawn in one minimum-jerk stroke;
* the pace is the recording's mean speed × a factor log-uniform in [1/1.5, 1.5];
* the hand holds its orientation, turning slowly by up to 20° about a random axis;
* half a second of rest before and after, and the recording's own sensor noise throughout.

Nothing here is fitted to a data set: every range is the people's (sizes, paces) or a property of
drawing (corners, curves), and the random stream is seeded, so a calibration is deterministic.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory

__all__ = ["min_jerk", "scribble", "scribble_poses"]

#: Largest turn [rad] between two strokes of a scribble.
MAX_TURN = math.radians(150.0)
#: Spread of the scribble's size and pace against the recording's (log-uniform factors).
SIZE_SPREAD = 1.3
PACE_SPREAD = 1.5
#: Largest slow turn [rad] of the hand while drawing.
DRIFT = math.radians(20.0)


def min_jerk(x: np.ndarray) -> np.ndarray:
    """Minimum-jerk progress (n,) in [0, 1] at normalised times ``x`` (n,) in [0, 1]."""
    return x**3 * (10.0 - 15.0 * x + 6.0 * x**2)


def _log_uniform(rng: np.random.Generator, spread: float) -> float:
    return float(math.exp(rng.uniform(-math.log(spread), math.log(spread))))


def _corners(rng: np.random.Generator, length: float) -> np.ndarray:
    """Corners (k + 1, 2) [m] of a random planar polyline of total length ``length``, from 0."""
    n = int(rng.integers(2, 6))
    closed = n >= 3 and rng.random() < 0.5
    free = n - 1 if closed else n
    weights = rng.uniform(0.5, 1.5, free)
    heading = rng.uniform(-math.pi, math.pi)
    pts = [np.zeros(2)]
    for w in weights:
        pts.append(pts[-1] + w * np.array([math.cos(heading), math.sin(heading)]))
        heading += rng.uniform(-MAX_TURN, MAX_TURN)
    if closed:
        pts.append(np.zeros(2))
    P = np.array(pts)
    total = float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())
    return P * (length / total)


def _chaikin(P: np.ndarray, rounds: int = 3) -> np.ndarray:
    """Corner cutting of an open polyline (end points kept)."""
    for _ in range(rounds):
        a, b = P[:-1], P[1:]
        inner = np.empty((2 * a.shape[0], 2))
        inner[0::2] = 0.75 * a + 0.25 * b
        inner[1::2] = 0.25 * a + 0.75 * b
        P = np.vstack([P[:1], inner, P[-1:]])
    return P


def _along(P: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points of polyline ``P`` at arc-length fractions ``s`` (n,) in [0, 1]."""
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    x = s * cum[-1]
    return np.stack([np.interp(x, cum, P[:, 0]), np.interp(x, cum, P[:, 1])], axis=1)


def _planar_path(rng: np.random.Generator, length: float, speed: float, dt: float) -> np.ndarray:
    """Planar offsets (n, 2) [m], sampled every ``dt`` [s], of one scribble."""
    P = _corners(rng, length)
    if rng.random() < 0.5:  # a smooth curve through the corners, one stroke
        C = _chaikin(P)
        dur = max(length / speed, 4 * dt)
        return _along(C, min_jerk(np.linspace(0.0, 1.0, max(round(dur / dt), 2))))
    pieces = [P[:1]]
    for a, b in itertools.pairwise(P):
        dur = max(float(np.linalg.norm(b - a)) / speed, 4 * dt)
        x = min_jerk(np.linspace(0.0, 1.0, max(round(dur / dt), 2))[1:])
        pieces.append(a + x[:, None] * (b - a))
        if rng.random() < 0.5:
            pieces.append(np.repeat(b[None], round(rng.uniform(0.0, 0.08) / dt), axis=0))
    return np.vstack(pieces)


def scribble_poses(T0: np.ndarray, rng: np.random.Generator, dt: float, length: float,
                   speed: float) -> np.ndarray:
    """Poses (n, 4, 4) of one scribble starting and ending with half a second of rest at ``T0``.

    Parameters
    ----------
    T0 : ndarray, shape (4, 4)
        Start pose.
    rng : numpy.random.Generator
    dt : float
        Sample period [s].
    length : float
        Nominal path length [m] (scaled by a factor drawn from the size spread).
    speed : float
        Nominal mean speed [m/s] along the path (scaled by a factor drawn from the pace spread).
    """
    xy = _planar_path(rng, length * _log_uniform(rng, SIZE_SPREAD),
                      max(speed, 1e-3) * _log_uniform(rng, PACE_SPREAD), dt)
    q = rng.standard_normal(4)
    plane = se3.matrix_from_quaternion(q / np.linalg.norm(q))[:, :2]  # (3, 2): a random plane
    n = xy.shape[0]
    axis = rng.standard_normal(3)
    axis *= rng.uniform(0.0, DRIFT) / np.linalg.norm(axis)
    turn = se3.rotation_from_vector(np.linspace(0.0, 1.0, n)[:, None] * axis[None])
    T = np.repeat(T0[None], n, axis=0)
    T[:, :3, 3] = T0[:3, 3] + xy @ plane.T
    T[:, :3, :3] = turn @ T0[:3, :3]
    rest = round(0.5 / dt)
    return np.concatenate([np.repeat(T[:1], rest, axis=0), T, np.repeat(T[-1:], rest, axis=0)])


def scribble(traj: Trajectory, rng: np.random.Generator, start: np.ndarray | None = None,
             ) -> np.ndarray:
    """Poses (n, 4, 4) of one scribble as large and as fast as recording ``traj``, from its start
    pose (or ``start``), sampled at the recording's median period."""
    dt = float(np.median(np.diff(traj.t)))
    steps = np.linalg.norm(np.diff(traj.p, axis=0), axis=1)
    length = float(steps.sum())
    moving = steps > 0.25 * float(steps.max(initial=0.0))
    duration = max(float(moving.sum()) * dt, dt)
    T0 = traj.poses()[0] if start is None else start
    return scribble_poses(T0, rng, dt, length, length / duration)
