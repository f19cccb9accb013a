"""Automatic decision threshold from the model recordings alone.

The paper tuned its threshold by hand, "strict". Here it is computed from two score families, each
score being the lowest matcher output ``min_t min_j d_j(t)`` over a replayed sequence:

positives (leave-one-out)
    every model recording replayed through the streaming routine and matched against the *other*
    models of its own gesture: the score a new performance of that gesture should reach;
negatives (non-gesture motion built from the recordings)
    sequences that must not fire, matched against *all* models:

    * ``head``: the first half (by screw path) of each recording;
    * ``middle``: its central half (25 %–75 %);
    * ``tail``: its second half;
    * ``splice``: the first half of one recording followed, without a jump, by the second half of
      a recording of another gesture (rigidly moved so that the motion is continuous).

    Reversed and time-warped copies are *not* used: the progress reparameterization makes
    time-warped gestures identical to the originals, and most gestures return to their start pose,
    so a reversed gesture is a gesture.

Generic non-gesture motion (the default families, ``PaperConfig.calibration_negatives``),
measured in the recordings themselves, never in a test stream:

    * ``rest``: holding still at the recording's start and end pose, with the recording's own
      sensor noise (estimated from second differences of its poses);
    * ``moves``: a few unhurried via-point moves (minimum-jerk screw interpolation) from the
      recording's start pose to nearby random poses (±12 cm, up to 60°), with short holds and the
      same noise: repositioning, reaching, re-gripping;
    * ``cross``: the recordings of the *other* gestures (a gesture must not fire another's models).

The cut pieces above (``head``, ``middle``, ``tail``, ``splice``) are partial gestures; the dev
streams showed they are much closer to real gestures than what people do between gestures, which
made the threshold too strict (they remain available).

Rule (``per_gesture``, default): for each gesture ``g``, ``P_g`` = the ``calibration_quantile``
quantile of its leave-one-out positives and ``N_g`` = the smallest negative score against the
models of ``g``; ``τ_g = P_g^(1-a) N_g^a`` (``a = calibration_position``, 0.5: geometric midpoint;
dissimilarities are scale-like) when ``P_g < N_g``, otherwise ``τ_g = calibration_margin · N_g``
(favours rejection). ``global``: the same with all positives and all negatives pooled.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from .. import se3
from ..progress import cumulative_progress
from ..trajectory import Trajectory
from .matchers import MatcherBank
from .models import GestureModels
from .paper_config import PaperConfig
from .preprocess import replay

__all__ = [
    "Calibration",
    "calibrate_threshold",
    "non_gesture_motions",
    "sensor_noise",
    "sequence_scores",
]


@dataclass(frozen=True)
class Calibration:
    """Result of the automatic threshold calibration.

    Attributes
    ----------
    threshold : float
        The chosen τ.
    positives : ndarray, shape (M,)
        Leave-one-out same-gesture score of each model recording.
    cross : ndarray, shape (M,)
        Lowest score of each model recording against models of *other* gestures (diagnostic).
    negatives : ndarray, shape (K,)
        Score of each non-gesture sequence.
    negative_kinds : tuple of str, length K
        ``head``, ``middle``, ``tail`` or ``splice``.
    separated : bool
        True when every used positive is below every negative.
    rule : str
        The formula that produced τ, in words.
    gesture_thresholds : dict of str to float
        τ_g per gesture (all equal to ``threshold`` in ``global`` mode).
    negative_scores : ndarray, shape (K, M)
        Score of each non-gesture sequence against each model.
    """

    threshold: float
    positives: np.ndarray
    cross: np.ndarray
    negatives: np.ndarray
    negative_kinds: tuple[str, ...] = field(default=())
    separated: bool = True
    rule: str = ""
    gesture_thresholds: dict = field(default_factory=dict)
    negative_scores: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    def summary(self) -> dict:
        """JSON-friendly summary."""
        fin = self.positives[np.isfinite(self.positives)]
        return {
            "threshold": self.threshold,
            "rule": self.rule,
            "separated": self.separated,
            "positives_max": float(np.max(fin)) if fin.size else None,
            "positives_median": float(np.median(fin)) if fin.size else None,
            "negatives_min_by_kind": {
                k: float(min(v for kk, v in zip(self.negative_kinds, self.negatives, strict=True)
                             if kk == k))
                for k in dict.fromkeys(self.negative_kinds)
            } if self.negatives.size else {},
            "negatives_min": float(np.min(self.negatives)) if self.negatives.size else None,
            "negatives_median": float(np.median(self.negatives)) if self.negatives.size else None,
            "cross_min": float(np.min(self.cross)) if self.cross.size else None,
            "n_negatives": int(self.negatives.size),
            "gesture_thresholds": {k: float(v) for k, v in self.gesture_thresholds.items()},
        }


def sequence_scores(bank: MatcherBank, descriptors: np.ndarray) -> np.ndarray:
    """Lowest output of every matcher over a descriptor sequence (M,); ``inf`` if never ready.

    The bank is reset before and after.
    """
    bank.reset()
    best = np.full(bank.n_models, np.inf)
    for b in descriptors:
        np.minimum(best, bank.update(b), out=best)
    bank.reset()
    return best


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


def _min_jerk(x: np.ndarray) -> np.ndarray:
    return x**3 * (10.0 - 15.0 * x + 6.0 * x**2)


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
        x = _min_jerk(np.linspace(0.0, 1.0, max(round(dur / dt), 2))[1:])
        pieces.append(se3.sclerp(np.broadcast_to(A, (x.size, 4, 4)), np.broadcast_to(B, (x.size, 4, 4)), x))
        pieces.append(np.repeat(B[None], round(rng.uniform(0.05, 0.4) / dt) + 1, axis=0))
        A = B
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
        Families to build among ``rest``, ``moves``, ``head``, ``middle``, ``tail``, ``splice``
        (``cross`` needs no sequence: the recordings themselves are used).
    seed : int
        Seed of the random via points and noise (the calibration is deterministic).
    """
    out: list[tuple[str, Trajectory]] = []
    n = len(trajectories)
    rng = np.random.default_rng(seed)
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


def _tau(p: float, nmin: float, config: PaperConfig) -> tuple[float, str, bool]:
    a = config.calibration_position
    if not np.isfinite(p) and not np.isfinite(nmin):
        raise ValueError("cannot calibrate: no positive and no negative score")
    if not np.isfinite(nmin):
        return 2.0 * p, "no negatives: 2 × positive quantile", True
    if not np.isfinite(p):
        return config.calibration_margin * nmin, "no positives: margin × min negative", False
    if p < nmin:
        return float(p ** (1.0 - a) * nmin**a), f"P^{1 - a:g} N^{a:g} (positive quantile, min negative)", True
    return config.calibration_margin * nmin, "overlap: margin × min negative", False


def calibrate_threshold(
    models: GestureModels,
    trajectories: Sequence[Trajectory],
    config: PaperConfig,
    bank: MatcherBank | None = None,
) -> Calibration:
    """Choose τ from the model recordings alone (see the module docstring).

    Parameters
    ----------
    models : GestureModels
        The models built from ``trajectories`` (same order).
    trajectories : sequence of Trajectory
        The model recordings.
    config : PaperConfig
        ``calibration_quantile`` and ``calibration_margin`` are used.
    bank : MatcherBank, optional
        A bank over ``models.descriptors`` (built if omitted).
    """
    if bank is None:
        bank = MatcherBank(models.descriptors, config.latency_fraction, config.latency_min,
                           config.parallel_models)
    labels = np.array(models.labels)
    M = len(labels)
    pos = np.full(M, np.inf)
    cross = np.full(M, np.inf)
    cross_scores = np.full((M, M), np.inf)
    for r in range(M):
        sc = sequence_scores(bank, models.descriptors[r])
        cross_scores[r] = sc
        same = labels == labels[r]
        same[r] = False
        if same.any():
            pos[r] = sc[same].min()
        if (~(labels == labels[r])).any():
            cross[r] = sc[labels != labels[r]].min()
    kinds: list[str] = []
    rows: list[np.ndarray] = []
    for kind, tr in non_gesture_motions(trajectories, list(models.labels), config.L,
                                        config.calibration_negatives):
        d, _ = replay(tr, models.resolution, config.L, config.ds_scale, config.window,
                      config.twist_noise, config.presmooth)
        sc = sequence_scores(bank, d) if d.shape[0] else np.full(M, np.inf)
        if np.isfinite(sc).any():
            kinds.append(kind)
            rows.append(sc)
    if "cross" in config.calibration_negatives:
        for r in range(M):
            sc = cross_scores[r].copy()
            sc[labels == labels[r]] = np.inf
            if np.isfinite(sc).any():
                kinds.append("cross")
                rows.append(sc)
    neg_scores = np.array(rows).reshape(-1, M)
    negatives = neg_scores.min(axis=1) if neg_scores.size else np.zeros(0)
    q = config.calibration_quantile
    finite_pos = pos[np.isfinite(pos)]
    p = float(np.quantile(finite_pos, q)) if finite_pos.size else np.nan
    nmin = float(negatives.min()) if negatives.size else np.inf
    tau, rule, sep = _tau(p, nmin, config)
    gesture_tau = dict.fromkeys(models.gestures, tau)
    if config.threshold_mode == "per_gesture":
        rules = []
        for g in models.gestures:
            sel = labels == g
            pg = pos[sel][np.isfinite(pos[sel])]
            pq = float(np.quantile(pg, q)) if pg.size else np.nan
            ng = float(neg_scores[:, sel].min()) if neg_scores.size else np.inf
            gesture_tau[g], rule_g, sep_g = _tau(pq, ng, config)
            sep = sep and sep_g
            rules.append(rule_g)
        rule = "per gesture: " + "; ".join(sorted(set(rules)))
        tau = float(np.median(list(gesture_tau.values())))
    return Calibration(float(tau), pos, cross, negatives, tuple(kinds), sep, rule,
                       {g: float(v) for g, v in gesture_tau.items()}, neg_scores)
