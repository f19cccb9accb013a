"""Fault injection: the defects of pose streams as real trackers deliver them.

Every fault is a pure function of raw arrays ``t`` (n,) [s], ``p`` (n, 3) [m], ``q`` (n, 4)
``(w, x, y, z)`` and a :class:`numpy.random.Generator`; it returns new arrays ``(t, p, q)`` and
never modifies its inputs. The results may hold NaN, repeated or unsorted time stamps, so they are
raw arrays, not :class:`~framefree.core.trajectory.Trajectory` objects. Feed them to a recognizer (or to
:class:`~framefree.online.acceptance.SampleGate`) sample by sample::

    t, p, q = inject("dropouts", traj.t, traj.p, traj.q, rng)
    for k in range(t.shape[0]):
        events = recognizer.push(t[k], p[k], q[k])
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..core import se3

__all__ = [
    "FAULT_KINDS",
    "dropouts",
    "duplicates",
    "inject",
    "jitter",
    "nan_samples",
    "outliers",
    "rotation_outliers",
    "sign_flips",
]

Arrays = tuple[np.ndarray, np.ndarray, np.ndarray]


def _copy(t: np.ndarray, p: np.ndarray, q: np.ndarray) -> Arrays:
    t = np.array(t, dtype=np.float64, copy=True)
    p = np.array(p, dtype=np.float64, copy=True)
    q = np.array(q, dtype=np.float64, copy=True)
    if t.ndim != 1 or p.shape != (t.shape[0], 3) or q.shape != (t.shape[0], 4):
        raise ValueError(f"expected t (n,), p (n, 3), q (n, 4); got {t.shape}, {p.shape}, {q.shape}")
    return t, p, q


def _pick(rng: np.random.Generator, n: int, count: int, margin: int = 1) -> np.ndarray:
    """``count`` distinct sorted sample indices in ``[margin, n - margin)`` (fewer if n is small)."""
    lo, hi = margin, max(margin, n - margin)
    count = min(int(count), hi - lo)
    if count <= 0:
        return np.empty(0, dtype=np.int64)
    return np.sort(rng.choice(np.arange(lo, hi), size=count, replace=False))


def dropouts(
    t: np.ndarray,
    p: np.ndarray,
    q: np.ndarray,
    rng: np.random.Generator,
    count: int = 3,
    max_duration: float = 0.5,
    min_duration: float = 0.1,
    starts: Sequence[float] | None = None,
) -> Arrays:
    """Remove ``count`` stretches of samples (tracker dropouts).

    Each gap, from the last sample kept before it to the first kept after, lasts at most a
    duration drawn uniformly in ``[min_duration, max_duration]`` seconds (and at least that
    duration minus one sample period). ``starts`` [s] places the gaps after the last sample at or
    before each given time instead of at random; gaps that overlap merge.
    """
    t, p, q = _copy(t, p, q)
    if starts is None:
        before = _pick(rng, t.shape[0], count, margin=2) - 1
    else:
        before = np.searchsorted(t, np.asarray(starts, dtype=np.float64), side="right") - 1
    keep = np.ones(t.shape[0], dtype=bool)
    for k in before:
        if not 0 <= k < t.shape[0] - 1:
            continue
        last = np.searchsorted(t, t[k] + rng.uniform(min_duration, max_duration), side="right") - 1
        keep[k + 1 : min(last, t.shape[0] - 1)] = False
    return t[keep], p[keep], q[keep]


def jitter(
    t: np.ndarray,
    p: np.ndarray,
    q: np.ndarray,
    rng: np.random.Generator,
    amplitude: float = 0.008,
    distribution: str = "uniform",
) -> Arrays:
    """Time-stamp jitter: every stamp moved by up to ``amplitude`` seconds (poses unchanged).

    ``distribution`` is ``"uniform"`` on ``[-amplitude, amplitude]`` or ``"normal"`` (standard
    deviation ``amplitude / 2``, truncated at ``±amplitude``). The stamps may end up unsorted when
    ``amplitude`` exceeds half the sample period.
    """
    t, p, q = _copy(t, p, q)
    if distribution == "uniform":
        d = rng.uniform(-amplitude, amplitude, t.shape[0])
    elif distribution == "normal":
        d = rng.normal(0.0, amplitude / 2.0, t.shape[0])
        out = np.abs(d) > amplitude
        while out.any():  # truncation: redraw the values outside the range
            d[out] = rng.normal(0.0, amplitude / 2.0, int(out.sum()))
            out = np.abs(d) > amplitude
    else:
        raise ValueError(f"unknown jitter distribution {distribution!r} (uniform or normal)")
    return t + d, p, q


def duplicates(
    t: np.ndarray,
    p: np.ndarray,
    q: np.ndarray,
    rng: np.random.Generator,
    fraction: float = 0.05,
    same_pose: bool = True,
) -> Arrays:
    """Deliver a ``fraction`` of the samples twice in a row (same time stamp; with
    ``same_pose=False`` the copy carries the next sample's pose, as a stale clock would)."""
    t, p, q = _copy(t, p, q)
    n = t.shape[0]
    idx = _pick(rng, n, round(fraction * n))
    order = np.sort(np.concatenate([np.arange(n), idx]))
    tt, pp, qq = t[order], p[order], q[order]
    if not same_pose:
        first = np.flatnonzero(np.diff(order) == 0) + 1  # the inserted copies
        nxt = np.minimum(order[first] + 1, n - 1)
        pp[first], qq[first] = p[nxt], q[nxt]
    return tt, pp, qq


def sign_flips(
    t: np.ndarray, p: np.ndarray, q: np.ndarray, rng: np.random.Generator, fraction: float = 0.1
) -> Arrays:
    """Negate the quaternion of a random ``fraction`` of the samples (same rotations)."""
    t, p, q = _copy(t, p, q)
    flip = rng.random(t.shape[0]) < fraction
    q[flip] *= -1.0
    return t, p, q


def outliers(
    t: np.ndarray,
    p: np.ndarray,
    q: np.ndarray,
    rng: np.random.Generator,
    count: int = 5,
    distance: float = 0.5,
    angle: float = 0.0,
) -> Arrays:
    """Single-sample glitches: ``count`` isolated samples moved by ``distance`` [m] in a random
    direction and rotated by ``angle`` [rad] about a random axis (time stamps unchanged)."""
    t, p, q = _copy(t, p, q)
    n = t.shape[0]
    idx = _pick(rng, n, count, margin=2)
    idx = idx[np.concatenate([[True], np.diff(idx) > 2])]  # isolated: two clean samples apart
    for k in idx:
        u = rng.standard_normal(3)
        p[k] += distance * u / np.linalg.norm(u)
        if angle:
            a = rng.standard_normal(3)
            a = a / np.linalg.norm(a)
            r = np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * a])
            q[k] = se3.quaternion_multiply(r, q[k])
    return t, p, q


def rotation_outliers(
    t: np.ndarray,
    p: np.ndarray,
    q: np.ndarray,
    rng: np.random.Generator,
    count: int = 5,
    angle: float = math.pi / 2,
) -> Arrays:
    """Single-sample orientation glitches: :func:`outliers` with no displacement."""
    return outliers(t, p, q, rng, count=count, distance=0.0, angle=angle)


def nan_samples(
    t: np.ndarray, p: np.ndarray, q: np.ndarray, rng: np.random.Generator, fraction: float = 0.02
) -> Arrays:
    """Replace a ``fraction`` of the samples by NaN in one random field (time, position or
    quaternion), as a tracker that lost the target may report."""
    t, p, q = _copy(t, p, q)
    n = t.shape[0]
    for k in _pick(rng, n, round(fraction * n)):
        field = rng.integers(3)
        if field == 0:
            t[k] = math.nan
        elif field == 1:
            p[k] = math.nan
        else:
            q[k] = math.nan
    return t, p, q


_FAULTS: dict[str, Callable[..., Arrays]] = {
    "dropouts": dropouts,
    "jitter": jitter,
    "duplicates": duplicates,
    "sign_flips": sign_flips,
    "outliers": outliers,
    "rotation_outliers": rotation_outliers,
    "nan": nan_samples,
}

#: Names accepted by :func:`inject`.
FAULT_KINDS: tuple[str, ...] = tuple(_FAULTS)


def inject(
    kind: str,
    t: np.ndarray,
    p: np.ndarray,
    q: np.ndarray,
    rng: np.random.Generator,
    **params: Any,
) -> Arrays:
    """Apply the fault ``kind`` (one of :data:`FAULT_KINDS`) with its keyword ``params``.

    Returns
    -------
    t : ndarray, shape (m,)
    p : ndarray, shape (m, 3)
    q : ndarray, shape (m, 4)
        New arrays; the inputs are left unchanged.
    """
    try:
        fault = _FAULTS[kind]
    except KeyError:
        raise ValueError(f"unknown fault {kind!r}; choose from {', '.join(FAULT_KINDS)}") from None
    return fault(t, p, q, rng, **params)
