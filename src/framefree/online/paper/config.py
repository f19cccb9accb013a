"""Parameters of the real-time recognizer, with every choice the paper leaves open.

All values are plain data in one frozen dataclass so that a session can be reproduced from its
JSON dump (:meth:`PaperConfig.to_dict`). Each field states which open point of the paper it
settles and why the default was chosen; docs/online-paper.md (*Choices for the paper's open
points*) collects them in one table.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

__all__ = ["NEGATIVE_KINDS", "PaperConfig"]

#: Non-gesture families the calibration knows (see :mod:`framefree.online.paper.calibration`).
NEGATIVE_KINDS = ("rest", "moves", "cross", "head", "middle", "tail", "splice")


@dataclass(frozen=True)
class PaperConfig:
    """Configuration of the streaming preprocessor, the matchers, the decision and the robustness.

    Attributes
    ----------
    L : float
        Scale length [m] of the screw path, of the BILTS+ rotational weight and clamp
        (docs/algorithms/se3.md, *The scale length L*). The paper does not publish the value it
        used online; 0.2 m gave the best calibrated precision/recall on replica models with
        synthetic streams (0.1, 0.2, 0.3, 0.5 tried; 0.5 gave F1 0.44, 0.2 gave 0.80 with no
        false positive).
    ds_scale : float
        BILTS+ window scale [m] (docs/algorithms/bilts.md). Window spacing ``m = min(23, max(1,
        round(ds_scale / resolution)))`` in geometric samples (not published by the paper).
    resolution : float or None
        Screw-path resolution Δs_res [m] of Algorithm 1, also the nominal progress step of the
        finite differences (the nominal step, not the accumulated one; the paper gives neither).
        ``None``: found by bisection so that Algorithm 1 keeps a median of ``resolution_samples``
        geometric samples per model recording (docs/online-paper.md, *Gesture models*).
    interpolate : int or None
        Poses offered to Algorithm 1 per raw pose step: ``interpolate - 1`` put by ScLERP between
        every two consecutive poses, models and live stream alike. ``None``: the fewest (1 to 8)
        with which every model recording gives two descriptor samples
        (:func:`~framefree.online.paper.models.auto_interpolation`): 1 for the paper's 50 Hz
        recordings, more for short recordings at a low frame rate (20 fps SFINGE3D examples: 4).
    resolution_samples : int
        Target number of geometric samples per model gesture for the automatic resolution (80;
        dev streams: 50 gave F1 0.857, 80 gave 0.875 with the other defaults — translations get
        few samples at a coarse resolution and were the main misses).
    window : int
        Gaussian smoothing window in geometric samples (10 for BILTS+): centred kernel, offsets
        -5..+4, so a smoothed pose is final 4 samples later (the paper does not say how it
        smoothed online; framefree smooths centrally with this delay, truncated and renormalized
        at the start of a sequence as offline: docs/online-paper.md, *Streaming preprocessing*).
    latency_fraction : float
        Largest latency searched, as a fraction of the model length: ``round(0.2 N_j)``
        (docs/online-paper.md, *Matchers: the latency search and running sums*).
    latency_min : int
        Smallest latency: 1 (literal reading of the paper) or 0 (also test the fully aligned case).
        Default 0 (dev streams: one more true positive, same false positives).
    threshold : float or None
        Decision threshold τ on the average pointwise dissimilarity. ``None``: calibrated
        automatically from the model recordings (:mod:`framefree.online.paper.calibration`).
    calibration_quantile : float
        Quantile of the leave-one-out same-class scores that must pass (0.75; with 5 recordings
        per gesture the maximum is one outlier, which on the dev streams let ``go_down`` fire on
        non-gesture motion: 32 false positives at 1.0, 22 at 0.75, same recall).
    calibration_margin : float
        When positives and negatives overlap, τ = margin × smallest negative score (favour
        rejection, as the paper tuned its threshold "strict").
    stop_threshold : float or None
        Stop detector threshold on ``|q̇|`` [1/s] (= half the angular speed; docs/online-paper.md,
        *The paper's stop detector*). ``None``:
        ``stop_margin`` × the largest debounced ``|q̇|`` seen in any model recording, at least
        ``stop_floor``.
    stop_margin : float
        Factor over the fastest model rotation for the automatic stop threshold (1.2; dev streams
        100-119: 1.0 gave 6 stop false positives on fast non-stop rotations, 1.2 none, with no
        stop signal missed; 1.1/1.3 on seeds 100-109 gave the same as 1.0/1.2).
    stop_floor : float
        Lower bound of the automatic stop threshold [1/s] (1.5 = 3 rad/s).
    stop_samples : int
        Debouncing: consecutive samples above the threshold before a stop fires (the paper
        publishes no debouncing).
    stop_rearm : float
        The stop detector re-arms once ``|q̇|`` falls below ``stop_rearm`` × threshold.
    stop_refractory : float
        After a stop fires, further stops are ignored for this long [s] (a stop signal is a
        back-and-forth rotation whose reversals would otherwise re-arm the detector).
    refractory_reset : bool
        After every event clear all matcher windows and caches so one gesture yields one event
        (the paper does not say what follows an event).
    max_gap : float
        A time step longer than this [s] is a gap: the preprocessor and matchers restart.
    jump_distance : float
        A position step longer than this [m] within one sample is a jump (tracker glitch).
    jump_angle : float
        A rotation step larger than this [rad] within one sample is a jump.
    jump_patience : int
        Jumped samples are skipped; after this many consecutive ones the tracker is assumed to
        have relocated and the recognizer restarts from the current sample.
    twist_noise : float
        Standard deviation of the deterministic perturbation added to every twist entry (1e-12,
        as the reference, to avoid exact singularities). A fixed table indexed by the twist index,
        so streaming and offline evaluation agree bit for bit.
    parallel_models : int
        Use the multi-threaded matcher kernel from this many models on (numba ``prange``).
    threshold_mode : {"per_gesture", "global"}
        ``per_gesture``: the automatic calibration gives each gesture its own τ_g from its own
        leave-one-out spread and the negatives' scores against its models; the decision compares
        ``d_j / τ_{g(j)}`` with 1. ``global``: one τ for all models (the paper). A user-given
        ``threshold`` always means one τ for all. Per-gesture thresholds were chosen on the dev
        streams (``benchmarks/online_dev.py``): the dissimilarity scale of well-rotating gestures
        is several times that of translations, so one τ misses them or admits false positives.
    calibration_negatives : tuple of str
        Non-gesture families of the calibration (:func:`~framefree.online.negatives.non_gesture_motions`):
        ``rest``, ``moves``, ``cross``, ``head``, ``middle``, ``tail``, ``splice``.
    calibration_position : float
        Where τ_g lies between the positive quantile P and the smallest negative N when P < N, on
        a log scale: ``τ = P^(1-a) N^a`` (0.3; dev streams: 0.5 gave 26 false positives, 0.3 gave
        20 with one miss more).
    decision : {"minimum", "first"}
        ``first``: fire at the first descriptor sample whose best ratio is below 1 (the paper).
        ``minimum``: wait until the best ratio stops decreasing (``decision_patience`` descriptor
        samples without a new minimum, or ``decision_wait`` seconds, or the ratio rising back
        above 1) and fire with the model of the minimum: the label is the best one over the whole
        dip, not the first to cross.
    decision_patience : int
        Descriptor samples without a new minimum before a ``minimum`` decision fires.
    decision_margin : float
        Second-best margin (1.0: off). A ``minimum`` or ``first`` decision only fires when the best
        other gesture's ratio ``d/τ`` at that moment is at least ``decision_margin`` times the
        winner's; otherwise the dip is ambiguous: no event, and the refractory reset still applies
        (counted in ``stats["ambiguous"]``). Exact with pruning for values ≤ ``prune_factor``.
    decision_wait : float
        Seconds [s] without a new minimum before a ``minimum`` decision fires (descriptor samples
        stop coming while the hand rests, because Algorithm 1 keeps no sample).
    prune_factor : float or None
        Exact pruning of the matchers (:class:`~framefree.online.paper.matchers.MatcherBank` ``cutoffs``):
        ``d_j`` is only computed exactly while it can still be below ``prune_factor × τ_g``;
        above, it reads ``inf``. Decisions are identical for any value ≥ 1; the live view and the
        timeline figure lose the values above the cutoff. ``None``: no pruning.
    presmooth : int
        Causal moving average over the last ``presmooth`` raw pose samples before Algorithm 1
        (1: off). Sensor jitter otherwise adds screw progress while the hand rests. Delay
        ``(presmooth - 1) / 2`` sample periods.
    """

    L: float = 0.2
    ds_scale: float = 0.09
    resolution: float | None = None
    interpolate: int | None = None
    resolution_samples: int = 80
    window: int = 10
    latency_fraction: float = 0.2
    latency_min: int = 0
    threshold: float | None = None
    calibration_quantile: float = 0.75
    calibration_margin: float = 0.8
    stop_threshold: float | None = None
    stop_margin: float = 1.2
    stop_floor: float = 1.5
    stop_samples: int = 2
    stop_rearm: float = 0.7
    stop_refractory: float = 1.5
    refractory_reset: bool = True
    max_gap: float = 0.25
    jump_distance: float = 0.25
    jump_angle: float = 1.0
    jump_patience: int = 3
    twist_noise: float = 1e-12
    parallel_models: int = 1000
    threshold_mode: str = "per_gesture"
    calibration_negatives: tuple[str, ...] = ("rest", "moves", "cross")
    calibration_position: float = 0.3
    decision: str = "minimum"
    decision_patience: int = 3
    decision_wait: float = 0.15
    decision_margin: float = 1.0
    presmooth: int = 1
    prune_factor: float | None = 2.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "calibration_negatives", tuple(self.calibration_negatives))
        if not self.L > 0:
            raise ValueError(f"L must be positive, got {self.L}")
        if not self.ds_scale > 0:
            raise ValueError(f"ds_scale must be positive, got {self.ds_scale}")
        if self.resolution is not None and not self.resolution > 0:
            raise ValueError(f"resolution must be positive, got {self.resolution}")
        if self.interpolate is not None and not 1 <= self.interpolate <= 64:
            raise ValueError(f"interpolate must be 1 to 64, got {self.interpolate}")
        if self.window < 1:
            raise ValueError(f"window must be at least 1, got {self.window}")
        if not 0 <= self.latency_fraction < 1:
            raise ValueError(f"latency_fraction must be in [0, 1), got {self.latency_fraction}")
        if self.latency_min not in (0, 1):
            raise ValueError(f"latency_min must be 0 or 1, got {self.latency_min}")
        if self.threshold is not None and not self.threshold > 0:
            raise ValueError(f"threshold must be positive, got {self.threshold}")
        if self.stop_samples < 1:
            raise ValueError(f"stop_samples must be at least 1, got {self.stop_samples}")
        if self.threshold_mode not in ("per_gesture", "global"):
            raise ValueError(f"threshold_mode must be 'per_gesture' or 'global', got {self.threshold_mode!r}")
        if self.decision not in ("minimum", "first"):
            raise ValueError(f"decision must be 'minimum' or 'first', got {self.decision!r}")
        if self.prune_factor is not None and not self.prune_factor >= 1.0:
            raise ValueError(f"prune_factor must be >= 1 or None, got {self.prune_factor}")
        if not self.decision_margin >= 1.0:
            raise ValueError(f"decision_margin must be >= 1, got {self.decision_margin}")
        if self.presmooth < 1:
            raise ValueError(f"presmooth must be at least 1, got {self.presmooth}")
        bad = set(self.calibration_negatives) - set(NEGATIVE_KINDS)
        if bad:
            raise ValueError(f"unknown calibration_negatives {sorted(bad)}; known: {NEGATIVE_KINDS}")
        if not self.max_gap > 0:
            raise ValueError(f"max_gap must be positive, got {self.max_gap}")

    def replace(self, **changes: Any) -> PaperConfig:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """All fields as a JSON-serializable dict."""
        d = dataclasses.asdict(self)
        d["calibration_negatives"] = list(self.calibration_negatives)
        return d
