"""Motions that probe a vocabulary before it goes live.

* :func:`perturbed` — a take seen from a random world frame, held with a random grip (body frame),
  performed faster or slower, and larger or smaller (as another person would: the hand travels
  farther or less far while the wrist turns as much): the same gesture, so it must still be
  recognized;
* :func:`stop_rotations` — fast back-and-forth wrist rotations (the stop signal) starting at a
  take's start pose: no gesture should look like one;
* :func:`everyday_motions` — reaching and repositioning moves from a take's start pose (one move,
  a move out and back, and the via-point moves of the threshold calibration): no gesture should
  look like ordinary hand motion.

All of them carry the take's own sensor noise (estimated from its second differences) and are
sampled at 50 Hz.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from ..online.negatives import non_gesture_motions, sensor_noise
from ..online.scribbles import min_jerk
from ..online.stop import sustained_peak_speed

__all__ = [
    "everyday_motions",
    "perturbed",
    "random_frame",
    "slowest_stop_speed",
    "stop_rotations",
]

#: Sample period of the probe motions [s].
PERIOD = 0.02
#: Stop signal: amplitude [rad] and stroke duration [s] ranges of the three strokes (+A, −2A, +A),
#: as the simulated people make it (equal to :data:`framefree.replica.streams.STOP_SIGNAL`, tested;
#: not imported, so that loading a library does not load the dataset generator).
STOP_AMPLITUDE = (math.radians(50.0), math.radians(80.0))
STOP_STROKE = (0.2, 0.3)
#: Distance [m] from the tracker to the rotation axis of a stop signal (forearm axis, grip).
STOP_AXIS_OFFSET = (0.02, 0.08)
#: Reach of everyday moves [m] and their largest turn [rad].
REACH = 0.12
TURN = math.radians(60.0)


def _random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation matrix (3, 3) uniform on SO(3) (normalized Gaussian quaternion)."""
    q = rng.standard_normal(4)
    return se3.matrix_from_quaternion(q / np.linalg.norm(q))


def random_frame(rng: np.random.Generator, offset: float) -> np.ndarray:
    """A pose (4, 4): uniform random rotation, translation of length ``offset`` [m] in a random direction."""
    d = rng.standard_normal(3)
    T = np.eye(4)
    T[:3, :3] = _random_rotation(rng)
    T[:3, 3] = d * (offset / np.linalg.norm(d))
    return T


def perturbed(
    take: Trajectory,
    rng: np.random.Generator,
    world_offset: float = 1.0,
    body_offset: float = 0.05,
    speed_range: tuple[float, float] = (0.5, 2.0),
    size_range: tuple[float, float] = (1.0, 1.0),
) -> Trajectory:
    """The take in a random world frame, with a random grip, at a random speed and size.

    Parameters
    ----------
    take : Trajectory
    rng : numpy.random.Generator
    world_offset : float
        Distance [m] the world origin moves (any direction, any rotation).
    body_offset : float
        Distance [m] the tracker moves in the hand (any rotation): a different grip.
    speed_range : (float, float)
        Speed factor drawn log-uniformly; the time axis is divided by it and the take
        resampled at 50 Hz by ScLERP.
    size_range : (float, float)
        Size factor drawn log-uniformly: the positions are scaled about the take's first position
        (the orientations are kept), before the frames change. Default: no change.

    Returns
    -------
    Trajectory
    """
    speed = math.exp(rng.uniform(math.log(speed_range[0]), math.log(speed_range[1])))
    size = math.exp(rng.uniform(math.log(size_range[0]), math.log(size_range[1])))
    out = take.path_scaled(size).transformed(world=random_frame(rng, world_offset),
                                             body=random_frame(rng, body_offset))
    out = out.time_scaled(1.0 / speed).resampled(PERIOD)
    return Trajectory(out.t, out.p, out.q,
                      source=f"{take.source} (frames changed, speed x{speed:.2f}, size x{size:.2f})")


def _noisy(T: np.ndarray, take: Trajectory, rng: np.random.Generator, source: str) -> Trajectory:
    sp, sr = sensor_noise(take)
    n = T.shape[0]
    T = T.copy()
    T[:, :3, 3] += rng.normal(0.0, sp, (n, 3))
    T[:, :3, :3] = se3.rotation_from_vector(rng.normal(0.0, sr, (n, 3))) @ T[:, :3, :3]
    return Trajectory.from_poses(PERIOD * np.arange(n), T, source=source)


def _move(A: np.ndarray, B: np.ndarray, duration: float) -> np.ndarray:
    """Minimum-jerk screw motion (ScLERP) from pose A to pose B, without A: (n, 4, 4)."""
    x = min_jerk(np.linspace(0.0, 1.0, max(round(duration / PERIOD) + 1, 2))[1:])
    return se3.sclerp(np.broadcast_to(A, (x.size, 4, 4)), np.broadcast_to(B, (x.size, 4, 4)), x)


def _hold(A: np.ndarray, duration: float) -> np.ndarray:
    return np.repeat(A[None], max(1, round(duration / PERIOD)), axis=0)


def _stop_poses(T0: np.ndarray, axis: np.ndarray, lever: np.ndarray, amplitude: float,
                strokes: tuple[float, float, float]) -> np.ndarray:
    """Rest, three minimum-jerk strokes ``+A, −2A, +A`` of the given durations [s] about ``axis``
    through ``T0``'s origin + ``lever``, rest: poses (n, 4, 4)."""
    pieces = [_hold(T0, 0.4)]
    A = T0
    centre = T0[:3, 3] + lever
    for frac, duration in zip((1.0, -2.0, 1.0), strokes, strict=True):
        R = se3.rotation_from_vector(axis * frac * amplitude)
        B = A.copy()
        B[:3, :3] = R @ A[:3, :3]
        B[:3, 3] = centre + R @ (A[:3, 3] - centre)
        pieces.append(_move(A, B, duration))
        A = B
    pieces.append(_hold(A, 0.4))
    return np.concatenate(pieces)


def stop_rotations(take: Trajectory, rng: np.random.Generator, n: int = 2) -> list[Trajectory]:
    """``n`` stop signals starting at the take's start pose.

    Each is a rest, three minimum-jerk strokes ``+A, −2A, +A`` about a random axis passing
    :data:`STOP_AXIS_OFFSET` from the tracker (the forearm axis, seen through an unknown grip),
    and a rest; amplitudes and durations as :data:`~framefree.replica.streams.STOP_SIGNAL`.
    """
    T0 = take.poses()[0]
    out = []
    for _ in range(n):
        axis = _random_rotation(rng)[:, 0]
        lever = np.cross(axis, rng.standard_normal(3))
        lever *= rng.uniform(*STOP_AXIS_OFFSET) / np.linalg.norm(lever)
        strokes = tuple(rng.uniform(*STOP_STROKE) * f for f in (1.0, 1.6, 1.0))
        P = _stop_poses(T0, axis, lever, rng.uniform(*STOP_AMPLITUDE), strokes)
        out.append(_noisy(P, take, rng, f"stop rotation from {take.source}"))
    return out


def slowest_stop_speed(window: float = 0.08, min_duration: float = 0.04) -> float:
    """Sustained peak angular speed [rad/s] of the slowest stop signal (smallest amplitude, longest
    strokes), measured as the recognizer's stop detector measures it
    (:func:`~framefree.online.stop.sustained_peak_speed` with its ``window`` and ``min_duration``)."""
    d = STOP_STROKE[1]
    P = _stop_poses(np.eye(4), np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.05, 0.0]), STOP_AMPLITUDE[0],
                    (d, 1.6 * d, d))
    _, q = se3.pq_from_poses(P)
    return sustained_peak_speed(PERIOD * np.arange(P.shape[0]), q, window, min_duration)


def _nearby(T0: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    B = T0.copy()
    d = rng.standard_normal(3)
    B[:3, 3] += d * (rng.uniform(0.5, 1.0) * REACH * math.sqrt(3) / np.linalg.norm(d))
    axis = rng.standard_normal(3)
    B[:3, :3] = se3.rotation_from_vector(axis / np.linalg.norm(axis) * rng.uniform(0.0, TURN)) @ T0[:3, :3]
    return B


def _duration(A: np.ndarray, B: np.ndarray, rng: np.random.Generator) -> float:
    dist = float(np.linalg.norm(B[:3, 3] - A[:3, 3]))
    ang = float(np.linalg.norm(se3.vector_from_rotation(A[:3, :3].T @ B[:3, :3])))
    return float(np.clip(0.5 + dist / 0.35 + ang / 2.5, 0.6, 2.5)) * rng.uniform(0.8, 1.2)


def everyday_motions(
    take: Trajectory, rng: np.random.Generator, L: float = 0.2
) -> list[tuple[str, Trajectory]]:
    """Reaching and repositioning moves from the take's start pose, labelled by kind.

    Kinds: ``reach`` (one unhurried minimum-jerk screw move to a nearby pose: up to ≈ 20 cm and
    60°), ``reach and return`` (out, a short hold, back) and ``moves`` (the via-point moves of
    :func:`~framefree.online.negatives.non_gesture_motions`), each with rests around it.
    """
    T0 = take.poses()[0]
    out = []
    B = _nearby(T0, rng)
    reach = np.concatenate([_hold(T0, 0.4), _move(T0, B, _duration(T0, B, rng)), _hold(B, 0.4)])
    out.append(("reach", _noisy(reach, take, rng, f"reach from {take.source}")))
    B = _nearby(T0, rng)
    back = np.concatenate([_hold(T0, 0.4), _move(T0, B, _duration(T0, B, rng)),
                           _hold(B, rng.uniform(0.1, 0.4)), _move(B, T0, _duration(B, T0, rng)),
                           _hold(T0, 0.4)])
    out.append(("reach and return", _noisy(back, take, rng, f"reach and return from {take.source}")))
    seed = int(rng.integers(2**31))
    out += [(kind, tr) for kind, tr in non_gesture_motions([take], ["take"], L, ("moves",), seed=seed)]
    return out
