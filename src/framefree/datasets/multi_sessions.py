"""Continuous sessions of several trackers made from separate recordings, with their labels.

Recordings of single performances (a person's takes) are played one after another on one clock:
after each, every tracker moves from where it ended to where the next recording starts
(minimum-jerk position, constant-rate slerp orientation), then rests with a little jitter. The
performances themselves are the recordings' own poses, resampled to the session's rate; only the
moves and rests between them are made up. This is how ``../shared/data/machete_streams`` was
described, and what the tests and ``benchmarks/bench_multi.py`` build their sessions with.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core import se3
from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import Trajectory
from .stream_files import Segment

__all__ = ["continuous_session"]


def _jerk(x: np.ndarray) -> np.ndarray:
    return x**3 * (10.0 - 15.0 * x + 6.0 * x**2)


def _between(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    """``n`` poses (n, 4, 4) from ``a`` to ``b`` (excluded ends), minimum-jerk in time."""
    alpha = _jerk(np.arange(1, n + 1) / (n + 1))
    return se3.sclerp(np.broadcast_to(a, (n, 4, 4)), np.broadcast_to(b, (n, 4, 4)), alpha)


def _rest(pose: np.ndarray, n: int, rng: np.random.Generator, jitter: tuple[float, float]
          ) -> np.ndarray:
    """``n`` copies of ``pose`` (4, 4) with position jitter [m] and rotation jitter [rad]."""
    out = np.repeat(pose[None], n, axis=0)
    out[:, :3, 3] += rng.normal(0.0, jitter[0], (n, 3))
    out[:, :3, :3] = se3.rotation_from_vector(rng.normal(0.0, jitter[1], (n, 3))) @ pose[:3, :3]
    return out


def continuous_session(
    samples: Sequence[MultiTrajectory],
    labels: Sequence[str],
    rate: float = 90.0,
    seed: int = 0,
    move: tuple[float, float] = (0.8, 1.5),
    rest: tuple[float, float] = (1.0, 2.5),
    jitter: tuple[float, float] = (3e-4, np.deg2rad(0.1)),
) -> tuple[MultiTrajectory, list[Segment]]:
    """One session of the recordings in the given order, and a label per recording.

    Parameters
    ----------
    samples : sequence of MultiTrajectory
        The recordings (same trackers, same order).
    labels : sequence of str
    rate : float
        Samples per second of the session [Hz].
    seed : int
        Of the move and rest durations and the jitter.
    move, rest : (float, float)
        Ranges [s] of the move after each recording and of the rest before the next.
    jitter : (float, float)
        Standard deviations of the rest's position [m] and rotation [rad] noise.

    Returns
    -------
    session : MultiTrajectory
    segments : list of Segment
        Each recording's label, first and last time [s] in the session.
    """
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    names, up = samples[0].names, samples[0].up
    parts: list[np.ndarray] = []  # (n, n_trackers, 4, 4)
    segments = []
    count = 0

    def add(block: np.ndarray) -> None:
        nonlocal count
        parts.append(block)
        count += block.shape[0]

    first = np.stack([tr.poses()[0] for tr in samples[0].trackers])
    n_rest = int(rng.uniform(*rest) / dt)
    add(np.stack([_rest(T, n_rest, rng, jitter) for T in first], axis=1))
    for k, (s, label) in enumerate(zip(samples, labels, strict=True)):
        grids = [tr.uniform_poses(dt)[1] for tr in s.trackers]
        n = min(g.shape[0] for g in grids)
        segments.append(Segment(str(label), count * dt, (count + n - 1) * dt))
        add(np.stack([g[:n] for g in grids], axis=1))
        end = parts[-1][-1]
        target = (np.stack([tr.poses()[0] for tr in samples[k + 1].trackers])
                  if k + 1 < len(samples) else end)
        m = int(rng.uniform(*move) / dt)
        add(np.stack([_between(end[j], target[j], m) for j in range(len(names))], axis=1))
        n_rest = int(rng.uniform(*rest) / dt)
        add(np.stack([_rest(target[j], n_rest, rng, jitter) for j in range(len(names))], axis=1))
    poses = np.concatenate(parts)
    t = np.arange(poses.shape[0]) * dt
    trackers = tuple(Trajectory.from_poses(t, poses[:, j], source=f"session:{names[j]}")
                     for j in range(len(names)))
    return MultiTrajectory(trackers, names, up, "session"), segments
