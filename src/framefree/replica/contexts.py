"""The twelve HPM contexts and four stress contexts: how each trial of *Original 1* is augmented.

=================  =================================================================================
original_1         the recording itself (no added noise: it already carries the tracker's error)
original_2         the recording + white noise
slower / faster    time axis × 2 / × 0.5, resampled at 50 Hz by ScLERP, + noise
first_half         the first ``ceil(N/2)`` samples, + noise
body_frame_k       ``T(t) · T_B,k`` (right multiplication, :data:`BODY_FRAMES`), + noise
world_frame_k      ``T_W,k · T(t)`` (left multiplication, :data:`WORLD_FRAMES`), + noise
combination        faster → ``T_W,1 · T(t) · T_B,1`` → first half → noise
heavy_noise        the recording + white noise of 3 mm / 3° (three times the paper's)
slower_3x          time axis × 3, resampled at 50 Hz by ScLERP, + noise
random_frames      ``T_W · T(t) · T_B`` with a world and a body frame drawn per trial
                   (:func:`random_frames`), + noise
other_person       not an augmentation: a new recording of the same gesture by a second simulated
                   person (:data:`OTHER_PERSON`), made by :func:`~framefree.replica.make_replica`
=================  =================================================================================

The last four are framefree's stress contexts, beyond the paper; the twelve paper contexts and
their random draws do not depend on them.

Noise: positions + N(0, (1 mm)²) per coordinate; rotations right-multiplied by ``exp([n]×)``,
``n ~ N(0, (1°)² I₃)``, independently per sample. For *combination* the paper does not say which
frame changes were used; we use Δ{b} 1 and Δ{w} 1. How the replica reads the paper where it is
silent (frame-change matrices, noise model, rounding of "half", order in *combination*):
docs/dataset.md, *How the replica reads the paper's description*.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory
from ..datasets.layout import REPLICA_CONTEXTS
from .motion import make_pose, rot

__all__ = [
    "BODY_FRAMES",
    "COMBINATION_FRAMES",
    "HEAVY_NOISE_SCALE",
    "NOISE_POS_STD",
    "NOISE_ROT_STD",
    "OTHER_PERSON",
    "RANDOM_BODY_OFFSET",
    "RANDOM_WORLD_OFFSET",
    "RESAMPLE_PERIOD",
    "WORLD_FRAMES",
    "add_noise",
    "apply_context",
    "random_frames",
]

#: Position noise [m] per coordinate (the paper, Section III).
NOISE_POS_STD = 0.001
#: Orientation noise [rad] per rotation-vector component (the paper, Section III; docs/dataset.md).
NOISE_ROT_STD = math.radians(1.0)
#: Sample period of the ScLERP resampling of *slower* and *faster* [s].
RESAMPLE_PERIOD = 0.02
#: *heavy_noise*: the noise standard deviations are this many times the paper's (3 mm, 3°).
HEAVY_NOISE_SCALE = 3.0
#: *random_frames*: the world translation is uniform in a ball of this radius [m].
RANDOM_WORLD_OFFSET = 3.0
#: *random_frames*: the body offset (tracker origin moved in the body frame) is at most this [m].
RANDOM_BODY_OFFSET = 0.10
#: *other_person*: seed of the second person (:func:`~framefree.replica.people.person`), the
#: first of the held-out people (chosen before any result was seen, never tuned on).
OTHER_PERSON = 1000

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


def add_noise(traj: Trajectory, rng: np.random.Generator, scale: float = 1.0) -> Trajectory:
    """White pose noise, independent per sample: ``p + N(0, (scale·NOISE_POS_STD)²)`` per
    coordinate and ``R · exp([n]×)`` with ``n ~ N(0, (scale·NOISE_ROT_STD)² I₃)``."""
    n = len(traj)
    T = traj.poses()
    T[:, :3, 3] += rng.normal(0.0, scale * NOISE_POS_STD, (n, 3))
    rotvec = rng.normal(0.0, scale * NOISE_ROT_STD, (n, 3))
    T[:, :3, :3] = T[:, :3, :3] @ se3.rotation_from_vector(rotvec)
    return Trajectory.from_poses(traj.t.copy(), T, source=traj.source)


def _rescaled(traj: Trajectory, factor: float) -> Trajectory:
    """Time axis × ``factor`` (about the first sample), ScLERP-resampled at 50 Hz."""
    return traj.time_scaled(factor).resampled(RESAMPLE_PERIOD)


def _half(traj: Trajectory) -> Trajectory:
    return traj.head(0.5)


def _uniform_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation (3, 3) drawn uniformly from SO(3) (normalized Gaussian quaternion)."""
    q = rng.standard_normal(4)
    return se3.matrix_from_quaternion(q / np.linalg.norm(q))


def _in_ball(rng: np.random.Generator, radius: float) -> np.ndarray:
    """A point (3,) drawn uniformly in the ball of ``radius`` about the origin."""
    d = rng.standard_normal(3)
    return d / np.linalg.norm(d) * radius * rng.uniform() ** (1.0 / 3.0)


def random_frames(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """World and body frame changes (4, 4) of one *random_frames* trial.

    World: uniformly random rotation, translation uniform in a ball of
    :data:`RANDOM_WORLD_OFFSET` m. Body: uniformly random rotation, offset uniform in a ball of
    :data:`RANDOM_BODY_OFFSET` m.
    """
    world = make_pose(_uniform_rotation(rng), _in_ball(rng, RANDOM_WORLD_OFFSET))
    body = make_pose(_uniform_rotation(rng), _in_ball(rng, RANDOM_BODY_OFFSET))
    return world, body


def apply_context(traj: Trajectory, context: str, rng: np.random.Generator) -> Trajectory:
    """The trial of ``context`` made from an *Original 1* recording ``traj``.

    Parameters
    ----------
    traj : Trajectory
        The original recording.
    context : str
        One of :data:`~framefree.datasets.REPLICA_CONTEXTS` except ``other_person`` (a new
        recording, not an augmentation).
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
    elif context == "heavy_noise":
        return add_noise(traj, rng, HEAVY_NOISE_SCALE)
    elif context == "slower_3x":
        out = _rescaled(traj, 3.0)
    elif context == "random_frames":
        world, body = random_frames(rng)
        out = traj.transformed(world=world, body=body)
    else:
        known = ", ".join(c for c in REPLICA_CONTEXTS if c != "other_person")
        raise ValueError(f"unknown context {context!r}; expected one of {known}")
    return add_noise(out, rng)
