"""The twelve HPM contexts (ALGORITHMS §1.4): how each trial of *Original 1* is augmented.

=================  =================================================================================
original_1         the recording itself (no added noise: it already carries the tracker's error)
original_2         the recording + white noise
slower / faster    time axis × 2 / × 0.5, resampled at 50 Hz by ScLERP, + noise
first_half         the first ``ceil(N/2)`` samples, + noise
body_frame_k       ``T(t) · T_B,k`` (right multiplication, :data:`BODY_FRAMES`), + noise
world_frame_k      ``T_W,k · T(t)`` (left multiplication, :data:`WORLD_FRAMES`), + noise
combination        faster → ``T_W,1 · T(t) · T_B,1`` → first half → noise
=================  =================================================================================

Noise (Ambiguity 1.4-b): positions + N(0, (1 mm)²) per coordinate; rotations right-multiplied by
``exp([n]×)``, ``n ~ N(0, (1°)² I₃)``, independently per sample. For *combination* the paper does not
say which frame changes were used (Ambiguity 1.4-c); we use Δ{b} 1 and Δ{w} 1.
"""

from __future__ import annotations

import math

import numpy as np

from .. import se3
from ..trajectory import Trajectory
from .layout import CONTEXTS
from .motion import make_pose, rot

__all__ = [
    "BODY_FRAMES",
    "COMBINATION_FRAMES",
    "NOISE_POS_STD",
    "NOISE_ROT_STD",
    "RESAMPLE_PERIOD",
    "WORLD_FRAMES",
    "add_noise",
    "apply_context",
]

#: Position noise [m] per coordinate ([P2] §III).
NOISE_POS_STD = 0.001
#: Orientation noise [rad] per rotation-vector component ([P2] §III, Ambiguity 1.4-b).
NOISE_ROT_STD = math.radians(1.0)
#: Sample period of the ScLERP resampling of *slower* and *faster* [s].
RESAMPLE_PERIOD = 0.02

_RZ180 = rot([0, 0, 1], math.pi)
_RX90 = rot([1, 0, 0], math.pi / 2)
_RYm90 = rot([0, 1, 0], -math.pi / 2)

#: Δ{b} 1–3: constant poses right-multiplied, ``[R_a(θ), d]`` with ``d`` in the original body axes.
BODY_FRAMES = {
    "body_frame_1": make_pose(_RZ180, [0.05, 0.0, 0.0]),
    "body_frame_2": make_pose(_RX90, [0.0, 0.05, 0.0]),
    "body_frame_3": make_pose(_RYm90, [0.0, 0.0, -0.05]),
}
#: Δ{w} 1–3: constant poses left-multiplied, ``[R_a(θ), d]`` with ``d`` in the original world axes.
WORLD_FRAMES = {
    "world_frame_1": make_pose(_RZ180, [1.0, 0.0, 0.0]),
    "world_frame_2": make_pose(_RX90, [0.0, 1.0, 0.0]),
    "world_frame_3": make_pose(_RYm90, [0.0, 0.0, 1.0]),
}
#: The (world, body) changes used by *combination*.
COMBINATION_FRAMES = ("world_frame_1", "body_frame_1")

for _T in (*BODY_FRAMES.values(), *WORLD_FRAMES.values()):
    _T.flags.writeable = False


def add_noise(traj: Trajectory, rng: np.random.Generator) -> Trajectory:
    """White pose noise, independent per sample: ``p + N(0, NOISE_POS_STD²)`` per coordinate and
    ``R · exp([n]×)`` with ``n ~ N(0, NOISE_ROT_STD² I₃)``."""
    n = len(traj)
    T = traj.poses()
    T[:, :3, 3] += rng.normal(0.0, NOISE_POS_STD, (n, 3))
    T[:, :3, :3] = T[:, :3, :3] @ se3.rotation_from_vector(rng.normal(0.0, NOISE_ROT_STD, (n, 3)))
    return Trajectory.from_poses(traj.t.copy(), T, source=traj.source)


def _rescaled(traj: Trajectory, factor: float) -> Trajectory:
    """Time axis × ``factor`` (about the first sample), ScLERP-resampled at 50 Hz."""
    return traj.time_scaled(factor).resampled(RESAMPLE_PERIOD)


def _half(traj: Trajectory) -> Trajectory:
    return traj.head(0.5)


def apply_context(traj: Trajectory, context: str, rng: np.random.Generator) -> Trajectory:
    """The trial of ``context`` made from an *Original 1* recording ``traj``.

    Parameters
    ----------
    traj : Trajectory
        The original recording.
    context : str
        One of :data:`~framefree.datasets.CONTEXTS`.
    rng : numpy.random.Generator
        Source of the added noise.

    Returns
    -------
    Trajectory
    """
    if context == "original_1":
        return traj
    if context == "original_2":
        out = traj
    elif context == "slower":
        out = _rescaled(traj, 2.0)
    elif context == "faster":
        out = _rescaled(traj, 0.5)
    elif context == "first_half":
        out = _half(traj)
    elif context in BODY_FRAMES:
        out = traj.transformed(body=BODY_FRAMES[context])
    elif context in WORLD_FRAMES:
        out = traj.transformed(world=WORLD_FRAMES[context])
    elif context == "combination":
        w, b = COMBINATION_FRAMES
        out = _half(_rescaled(traj, 0.5).transformed(world=WORLD_FRAMES[w], body=BODY_FRAMES[b]))
    else:
        raise ValueError(f"unknown context {context!r}; expected one of {', '.join(CONTEXTS)}")
    return add_noise(out, rng)
