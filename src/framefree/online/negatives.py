"""Motion that must not fire, built from a vocabulary's own recordings: the negatives that
decision thresholds are placed against (by the paper's calibration,
:mod:`framefree.online.paper.calibration`, and by the segment recognizer's thresholds,
:mod:`framefree.online.thresholds`).

Families (``kinds``), all measured in the recordings themselves, never in a test stream:

``rest``
    holding still at the recording's start and end pose, with the recording's own sensor noise
    (:func:`sensor_noise`, from second differences of its poses);
``moves``
    a few unhurried via-point moves (minimum-jerk screw interpolation) from the recording's start
    pose to nearby random poses (±12 cm, up to 60°), with short holds and the same noise:
    repositioning, reaching, re-gripping;
``regrip``
    the tracker turning in the hand while the hand stays still (:func:`_regrip`): by 20–180°
    about a random axis through a point within 6 cm of it, half of the time turned back again,
    with holds and the same noise. A forearm rotation (*go down*, a gripper gesture) turns the
    tracker the same way, by a set amount: what tells them apart is how far it turns. Not part
    of ``N_g``; the calibration uses them to judge how small a gesture may be
    (:func:`~framefree.online.thresholds.reach_down`);
``drawn``
    random shapes drawn in the air from the recording's start and end pose, as large and as fast
    as the recording (:mod:`framefree.online.scribbles`), with the same noise: the unknown
    gestures nobody enrolled;
``head``, ``middle``, ``tail``
    the first half, the central half (25–75 %) and the second half (by screw path) of each recording;
``splice``
    the first half of one recording followed, without a jump, by the second half of a recording of
    another gesture (rigidly moved so that the motion is continuous).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core import se3
from ..core.progress import cumulative_progress
from ..core.trajectory import Trajectory
from .scribbles import min_jerk, scribble

__all__ = ["non_gesture_motions", "sensor_noise"]


def _split_index(traj: Trajectory, fraction: float, L: float) -> int:
    s = cumulative_progress(traj.poses(), "screw", L)
    return int(np.clip(np.searchsorted(s, fraction * s[-1]), 2, len(traj) - 2))


def _piece(traj: Trajectory, lo: int, hi: int) -> Trajectory:
    return Trajectory(traj.t[lo:hi], traj.p[lo:hi], traj.q[lo:hi], source=traj.source)


def _splice(a: Trajectory, b: Trajectory) -> Trajectory:
    """``a`` followed by ``b`` rigidly moved so that ``b`` starts where ``a`` ends."""
    Ta = a.poses()
    Tb = b.poses()
    G = Ta[-1] @ se3.transform_inverse(Tb[0])
    Tb2 = G[None] @ Tb[1:]
    dt = np.median(np.diff(a.t))
    tb = b.t[1:] - b.t[0] + a.t[-1] + dt
    T = np.concatenate([Ta, Tb2])
    t = np.concatenate([a.t, tb])
    return Trajectory.from_poses(t, T, source="splice")


def sensor_noise(traj: Trajectory) -> tuple[float, float]:
    """Per-axis position [m] and rotation [rad] noise of a recording, from its second differences.

    For white noise of standard deviation σ the second difference has standard deviation √6 σ,
    while a smooth 50 Hz motion contributes almost nothing; the median absolute deviation makes the
    estimate robust to the fast parts of the gesture.
    """
    if len(traj) < 5:
        return 0.0, 0.0
    d2p = np.diff(traj.p, n=2, axis=0).ravel()
    rv = se3.vector_from_rotation(se3.matrix_from_quaternion(traj.q))
    d2r = np.diff(rv, n=2, axis=0).ravel()
    k = 1.4826 / np.sqrt(6.0)
    return (float(k * np.median(np.abs(d2p - np.median(d2p)))),
            float(k * np.median(np.abs(d2r - np.median(d2r)))))


def _noisy(t: np.ndarray, T: np.ndarray, sp: float, sr: float, rng: np.random.Generator,
           source: str) -> Trajectory:
    n = T.shape[0]
    T = T.copy()
    T[:, :3, 3] += rng.normal(0.0, sp, (n, 3))
    T[:, :3, :3] = se3.rotation_from_vector(rng.normal(0.0, sr, (n, 3))) @ T[:, :3, :3]
    return Trajectory.from_poses(t, T, source=source)


def _random_nearby(T: np.ndarray, rng: np.random.Generator, reach: float, turn: float) -> np.ndarray:
    out = T.copy()
    out[:3, 3] += np.clip(rng.normal(0.0, reach, 3), -2.5 * reach, 2.5 * reach)
    axis = rng.standard_normal(3)
    axis /= np.linalg.norm(axis)
    out[:3, :3] = se3.rotation_from_vector(axis * rng.uniform(0.0, turn)) @ T[:3, :3]
    return out


def _via_point_moves(T0: np.ndarray, rng: np.random.Generator, dt: float, n_moves: int,
                     reach: float = 0.12, turn: float = np.radians(60.0)) -> np.ndarray:
    """Poses (n, 4, 4) of ``n_moves`` unhurried minimum-jerk screw moves with short holds."""
    pieces = [np.repeat(T0[None], round(0.5 / dt), axis=0)]
    A = T0
    for _ in range(n_moves):
        B = _random_nearby(T0, rng, reach, turn)
        dist = float(np.linalg.norm(B[:3, 3] - A[:3, 3]))
        ang = float(np.linalg.norm(se3.vector_from_rotation(A[:3, :3].T @ B[:3, :3])))
        dur = float(np.clip(0.5 + dist / 0.35 + ang / 2.5, 0.6, 2.5)) * rng.uniform(0.8, 1.2)
        x = min_jerk(np.linspace(0.0, 1.0, max(round(dur / dt), 2))[1:])
        pieces.append(se3.sclerp(np.broadcast_to(A, (x.size, 4, 4)), np.broadcast_to(B, (x.size, 4, 4)), x))
        pieces.append(np.repeat(B[None], round(rng.uniform(0.05, 0.4) / dt) + 1, axis=0))
        A = B
    return np.concatenate(pieces)


def _turn(T0: np.ndarray, pivot: np.ndarray, rotvec: np.ndarray, rng: np.random.Generator,
          dt: float) -> np.ndarray:
    """Poses (n, 4, 4) turning ``T0`` by ``rotvec`` [rad] about ``pivot`` (3,) [m]: minimum jerk,
    unhurried (about 2 rad/s on average)."""
    angle = float(np.linalg.norm(rotvec))
    dur = (0.4 + angle / 2.0) * rng.uniform(0.8, 1.25)
    x = min_jerk(np.linspace(0.0, 1.0, max(round(dur / dt), 2))[1:])
    R = se3.rotation_from_vector(x[:, None] * rotvec[None])  # (n, 3, 3)
    P = np.repeat(T0[None], x.size, axis=0)
    P[:, :3, :3] = R @ T0[:3, :3]
    P[:, :3, 3] = pivot + np.einsum("nij,j->ni", R, T0[:3, 3] - pivot)
    return P


def _regrip(T0: np.ndarray, rng: np.random.Generator, dt: float) -> np.ndarray:
    """Poses (n, 4, 4) of the tracker turning in the hand from ``T0``: by 20–180° about a random
    axis through a point within 6 cm of the tracker; half of the time it is turned back again
    (within 15°), as a person does who adjusts a grip and returns to their usual one. Holds of
    0.3–0.8 s before, between and after."""
    axis = rng.standard_normal(3)
    axis /= np.linalg.norm(axis)
    offset = rng.standard_normal(3)
    pivot = T0[:3, 3] + offset * rng.uniform(0.0, 0.06) / np.linalg.norm(offset)
    turn = axis * rng.uniform(np.radians(20.0), np.pi)
    pieces = [np.repeat(T0[None], round(rng.uniform(0.3, 0.8) / dt), axis=0)]
    pieces.append(_turn(T0, pivot, turn, rng, dt))
    if rng.random() < 0.5:
        back = -turn + rng.normal(0.0, np.radians(15.0) / np.sqrt(3.0), 3)
        pieces.append(np.repeat(pieces[-1][-1][None], round(rng.uniform(0.1, 0.5) / dt), axis=0))
        pieces.append(_turn(pieces[-1][-1], pivot, back, rng, dt))
    pieces.append(np.repeat(pieces[-1][-1][None], round(rng.uniform(0.3, 0.8) / dt), axis=0))
    return np.concatenate(pieces)


def non_gesture_motions(
    trajectories: Sequence[Trajectory],
    labels: Sequence[str],
    L: float,
    kinds: Sequence[str] = ("head", "middle", "tail", "splice"),
    seed: int = 0,
) -> list[tuple[str, Trajectory]]:
    """Non-gesture sequences built from the recordings (see the module docstring).

    Parameters
    ----------
    trajectories, labels
        The model recordings and their gesture labels.
    L : float
        Scale length [m] (to cut pieces by screw path).
    kinds : sequence of str
        Families to build among ``rest``, ``moves``, ``regrip``, ``drawn``, ``head``, ``middle``, ``tail``,
        ``splice`` (``cross`` needs no sequence: the recordings themselves are used).
    seed : int
        Seed of the random via points and noise (the calibration is deterministic).
    """
    out: list[tuple[str, Trajectory]] = []
    n = len(trajectories)
    rng = np.random.default_rng(seed)
    drawing = np.random.default_rng([seed, 1])  # its own stream: the other families stay as they were
    handling = np.random.default_rng([seed, 2])  # the same for re-grips
    for r, tr in enumerate(trajectories):
        if len(tr) < 8:
            continue
        dt = float(np.median(np.diff(tr.t)))
        sp, sr = sensor_noise(tr)
        T = tr.poses()
        if "rest" in kinds:
            for k, T0 in enumerate((T[0], T[-1])):
                nr = round(3.0 / dt)
                out.append(("rest", _noisy(dt * np.arange(nr), np.repeat(T0[None], nr, axis=0), sp, sr,
                                           rng, f"rest {k} of {tr.source}")))
        if "moves" in kinds:
            for T0 in (T[0], T[-1]):
                P = _via_point_moves(T0, rng, dt, int(rng.integers(2, 5)))
                out.append(("moves", _noisy(dt * np.arange(P.shape[0]), P, sp, sr, rng,
                                            f"moves from {tr.source}")))
        if "regrip" in kinds:
            for T0 in (T[0], T[-1]):
                P = _regrip(T0, handling, dt)
                out.append(("regrip", _noisy(dt * np.arange(P.shape[0]), P, sp, sr, handling,
                                             f"re-grip from {tr.source}")))
        if "drawn" in kinds:
            for T0 in (T[0], T[-1]):
                P = scribble(tr, drawing, T0)
                out.append(("drawn", _noisy(dt * np.arange(P.shape[0]), P, sp, sr, drawing,
                                            f"shape drawn from {tr.source}")))
        q1 = _split_index(tr, 0.25, L)
        h = _split_index(tr, 0.5, L)
        q3 = _split_index(tr, 0.75, L)
        if "head" in kinds:
            out.append(("head", _piece(tr, 0, h + 1)))
        if "middle" in kinds:
            out.append(("middle", _piece(tr, q1, q3 + 1)))
        if "tail" in kinds:
            out.append(("tail", _piece(tr, h, len(tr))))
        if "splice" in kinds:
            # partner: the next recording (cyclically) of another gesture
            for step in range(1, n):
                o = (r + step * max(1, n // max(1, len(set(labels))))) % n
                if labels[o] != labels[r] and len(trajectories[o]) >= 8:
                    other = trajectories[o]
                    ho = _split_index(other, 0.5, L)
                    out.append(("splice", _splice(_piece(tr, 0, h + 1), _piece(other, ho, len(other)))))
                    break
    return out
