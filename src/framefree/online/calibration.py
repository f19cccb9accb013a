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

Rule: with ``P`` the ``calibration_quantile`` quantile of the positives and ``N`` the smallest
negative, ``τ = sqrt(P · N)`` (geometric midpoint; dissimilarities are scale-like) when
``P < N``; otherwise the families overlap and ``τ = calibration_margin · N`` favours rejection.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from .. import se3
from ..progress import cumulative_progress
from ..trajectory import Trajectory
from .config import RecognizerConfig
from .matchers import MatcherBank
from .models import GestureModels
from .preprocess import replay

__all__ = ["Calibration", "calibrate_threshold", "non_gesture_motions", "sequence_scores"]


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
    """

    threshold: float
    positives: np.ndarray
    cross: np.ndarray
    negatives: np.ndarray
    negative_kinds: tuple[str, ...] = field(default=())
    separated: bool = True
    rule: str = ""

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
            },
            "negatives_min": float(np.min(self.negatives)) if self.negatives.size else None,
            "negatives_median": float(np.median(self.negatives)) if self.negatives.size else None,
            "cross_min": float(np.min(self.cross)) if self.cross.size else None,
            "n_negatives": int(self.negatives.size),
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


def non_gesture_motions(
    trajectories: Sequence[Trajectory], labels: Sequence[str], L: float
) -> list[tuple[str, Trajectory]]:
    """Non-gesture sequences built from the recordings (see the module docstring)."""
    out: list[tuple[str, Trajectory]] = []
    n = len(trajectories)
    for r, tr in enumerate(trajectories):
        if len(tr) < 8:
            continue
        q1 = _split_index(tr, 0.25, L)
        h = _split_index(tr, 0.5, L)
        q3 = _split_index(tr, 0.75, L)
        out.append(("head", _piece(tr, 0, h + 1)))
        out.append(("middle", _piece(tr, q1, q3 + 1)))
        out.append(("tail", _piece(tr, h, len(tr))))
        # partner: the next recording (cyclically) of another gesture
        for step in range(1, n):
            o = (r + step * max(1, n // max(1, len(set(labels))))) % n
            if labels[o] != labels[r] and len(trajectories[o]) >= 8:
                other = trajectories[o]
                ho = _split_index(other, 0.5, L)
                out.append(("splice", _splice(_piece(tr, 0, h + 1), _piece(other, ho, len(other)))))
                break
    return out


def calibrate_threshold(
    models: GestureModels,
    trajectories: Sequence[Trajectory],
    config: RecognizerConfig,
    bank: MatcherBank | None = None,
) -> Calibration:
    """Choose τ from the model recordings alone (see the module docstring).

    Parameters
    ----------
    models : GestureModels
        The models built from ``trajectories`` (same order).
    trajectories : sequence of Trajectory
        The model recordings.
    config : RecognizerConfig
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
    for r in range(M):
        sc = sequence_scores(bank, models.descriptors[r])
        same = labels == labels[r]
        same[r] = False
        if same.any():
            pos[r] = sc[same].min()
        if (~(labels == labels[r])).any():
            cross[r] = sc[labels != labels[r]].min()
    kinds: list[str] = []
    neg: list[float] = []
    for kind, tr in non_gesture_motions(trajectories, list(models.labels), config.L):
        d, _ = replay(tr, models.resolution, config.L, config.ds_scale, config.window,
                      config.twist_noise)
        s = float(sequence_scores(bank, d).min()) if d.shape[0] else np.inf
        if np.isfinite(s):
            kinds.append(kind)
            neg.append(s)
    negatives = np.array(neg)
    finite_pos = pos[np.isfinite(pos)]
    p = float(np.quantile(finite_pos, config.calibration_quantile)) if finite_pos.size else np.nan
    nmin = float(negatives.min()) if negatives.size else np.inf
    if not np.isfinite(p) and not np.isfinite(nmin):
        raise ValueError("cannot calibrate: no positive and no negative score")
    if not np.isfinite(nmin):
        tau, rule, sep = 2.0 * p, "no negatives: 2 × positive quantile", True
    elif not np.isfinite(p):
        tau, rule, sep = config.calibration_margin * nmin, "no positives: margin × min negative", False
    elif p < nmin:
        tau, rule, sep = float(np.sqrt(p * nmin)), "sqrt(positive quantile × min negative)", True
    else:
        tau, rule, sep = config.calibration_margin * nmin, "overlap: margin × min negative", False
    return Calibration(float(tau), pos, cross, negatives, tuple(kinds), sep, rule)
