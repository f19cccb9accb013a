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

from ...core.trajectory import Trajectory
from ..negatives import non_gesture_motions
from .config import PaperConfig
from .matchers import MatcherBank
from .models import GestureModels
from .preprocess import replay

__all__ = [
    "Calibration",
    "calibrate_threshold",
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
                      config.twist_noise, config.presmooth, models.interpolate)
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
