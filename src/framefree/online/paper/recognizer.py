"""The paper's real-time recognizer (its proof of concept), kept as a selectable method.

See docs/online-paper.md.

framefree's default live recognizer is :class:`framefree.online.Recognizer` (segment spotting);
this one is ``--method paper`` on the command line.

Per pose sample ``(t, p, q)``:

1. validation (NaN, zero quaternion, repeated or backwards time stamps are skipped; a quaternion
   sign flip is undone; a time gap restarts the stream; a sudden jump is skipped, and after
   ``jump_patience`` consecutive jumps the stream restarts at the new place) — every case counted
   in :attr:`PaperRecognizer.stats`;
2. the stop detector on ``|q̇|`` of the raw stream;
3. the streaming preprocessor (Algorithm 1 + online BILTS+), which sometimes emits a descriptor
   sample;
4. for each descriptor sample, all matchers are updated at once and the minimum-dissimilarity
   searcher compares the best model with the threshold τ.

A stop takes precedence over any gesture (it is reported alone, and no gesture fires while the
hand is still rotating fast). After every event all matcher windows are cleared (refractory reset).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ...core import se3
from ...core.trajectory import Trajectory
from ..acceptance import well_formed
from ..events import STOP, Event
from ..streaming import StreamingRecognizer
from .calibration import Calibration, calibrate_threshold
from .config import PaperConfig
from .matchers import MatcherBank
from .models import GestureModels, build_models
from .preprocess import StreamingBILTSPlus
from .stop import SampleRateStopDetector, debounced_peak_rate

__all__ = ["STAT_KEYS", "PaperRecognizer"]

#: Counters of :attr:`PaperRecognizer.stats`.
STAT_KEYS = (
    "samples",  # pose samples offered
    "accepted",  # pose samples used
    "nan",  # skipped: NaN or inf in t, p or q
    "bad_quaternion",  # skipped: zero-norm quaternion
    "repeated",  # skipped: same time stamp as the previous sample
    "backwards",  # skipped: time stamp before the previous sample
    "sign_flips",  # quaternion sign flips undone
    "gaps",  # time gaps that restarted the stream
    "jumps",  # skipped: sudden position or orientation jumps
    "relocations",  # restarts after jump_patience consecutive jumps
    "geometric",  # geometric samples kept by Algorithm 1
    "descriptors",  # descriptor samples matched
    "bad_descriptors",  # non-finite descriptor samples (preprocessor restarted)
    "events",  # gesture events
    "stops",  # stop events
    "ambiguous",  # gesture decisions suppressed by decision_margin
)


class PaperRecognizer(StreamingRecognizer):
    """Streaming gesture recognizer over a fixed set of gesture models.

    Parameters
    ----------
    models : GestureModels
        Model descriptors (built by :func:`~framefree.online.paper.models.build_models`).
    config : PaperConfig
        All parameters; ``threshold`` and ``stop_threshold`` must be set (use the constructors
        :meth:`from_trajectories` / :meth:`from_dataset` for automatic calibration).
    calibration : Calibration, optional
        Kept for reporting.
    gesture_thresholds : dict of str to float, optional
        τ_g per gesture (``threshold_mode="per_gesture"``); default: ``config.threshold`` for all.

    Attributes
    ----------
    threshold : float
        Decision threshold τ on the average pointwise dissimilarity (with per-gesture thresholds:
        their median, for reporting).
    gesture_thresholds : dict of str to float
        τ_g of each gesture.
    model_thresholds : ndarray, shape (M,)
        τ of each model's gesture; a model is a candidate when ``d_j < model_thresholds[j]``.
    stop_threshold : float
        Stop detector threshold on ``|q̇|`` [1/s].
    stats : dict of str to int
        Counters (see :data:`STAT_KEYS`).
    dissimilarities : ndarray, shape (M,)
        Live view of every matcher's output (``inf`` while not ready or just reset).
    last_matched : ndarray, shape (M,)
        Copy of the matcher outputs at the latest descriptor sample, before any reset.

    Examples
    --------
    >>> rec = PaperRecognizer.from_dataset("hpm", model_context="original_1")  # doctest: +SKIP
    >>> rec.warmup()                                                        # doctest: +SKIP
    >>> for t, p, q in source:                                              # doctest: +SKIP
    ...     for event in rec.push(t, p, q):
    ...         print(event.label, event.time)
    """

    def __init__(
        self,
        models: GestureModels,
        config: PaperConfig,
        calibration: Calibration | None = None,
        gesture_thresholds: dict[str, float] | None = None,
    ) -> None:
        if config.threshold is None or config.stop_threshold is None:
            raise ValueError("config.threshold and config.stop_threshold must be set")
        self.models = models
        self.config = config.replace(resolution=models.resolution, interpolate=models.interpolate)
        self.calibration = calibration
        self.threshold = float(config.threshold)
        self.stop_threshold = float(config.stop_threshold)
        self.labels = list(models.labels)
        self.gestures = models.gestures
        self._label_index = np.array([self.gestures.index(s) for s in self.labels])
        self._other = [self._label_index != g for g in range(len(self.gestures))]
        gt = dict.fromkeys(self.gestures, self.threshold)
        if gesture_thresholds:
            missing = set(self.gestures) - set(gesture_thresholds)
            if missing:
                raise ValueError(f"gesture_thresholds lacks {sorted(missing)}")
            gt = {g: float(gesture_thresholds[g]) for g in self.gestures}
        self.gesture_thresholds = gt
        self.model_thresholds = np.array([gt[s] for s in self.labels])
        self._pending: tuple[int, float, float, float, int, float] | None = None  # j, ratio, d, t, stale, r2
        c = self.config
        self.preprocessor = StreamingBILTSPlus(models.resolution, c.L, c.ds_scale, c.window,
                                               c.twist_noise, c.presmooth, models.interpolate)
        self.bank = MatcherBank(models.descriptors, c.latency_fraction, c.latency_min,
                                c.parallel_models)
        if c.prune_factor is not None:
            self.bank.set_cutoffs(c.prune_factor * self.model_thresholds)
        self.stop = SampleRateStopDetector(self.stop_threshold, c.stop_samples, c.stop_rearm,
                                           c.stop_refractory)
        self.stats: dict[str, int] = dict.fromkeys(STAT_KEYS, 0)
        self.dissimilarities = self.bank.d
        self.last_matched = self.bank.d.copy()
        #: (time [s], distance to every model (M,)) of each descriptor sample matched by the
        #: latest :meth:`push` (for traces and figures)
        self.observations: list[tuple[float, np.ndarray]] = []
        self._t: float | None = None
        self._p = np.zeros(3)
        self._q = np.array([1.0, 0.0, 0.0, 0.0])
        self._jump_run = 0
        self._cos_jump = math.cos(0.5 * c.jump_angle)

    # ------------------------------------------------------------------------------ construction
    @classmethod
    def from_trajectories(
        cls,
        trajectories: Sequence[Trajectory],
        labels: Sequence[str],
        config: PaperConfig | None = None,
        **overrides: Any,
    ) -> PaperRecognizer:
        """Build models from recordings and calibrate what the config leaves as ``None``.

        Parameters
        ----------
        trajectories : sequence of Trajectory
            Model recordings (one gesture performance each).
        labels : sequence of str
            Gesture label of each recording.
        config : PaperConfig, optional
            Defaults to ``PaperConfig()``; keyword ``overrides`` replace its fields.
        """
        config = (config or PaperConfig()).replace(**overrides)
        models = build_models(trajectories, labels, config)
        config = config.replace(resolution=models.resolution, interpolate=models.interpolate)
        calibration = None
        gesture_thresholds = None
        if config.threshold is None:
            calibration = calibrate_threshold(models, trajectories, config)
            config = config.replace(threshold=calibration.threshold)
            if config.threshold_mode == "per_gesture":
                gesture_thresholds = calibration.gesture_thresholds
        if config.stop_threshold is None:
            peak = max(debounced_peak_rate(tr, config.stop_samples) for tr in trajectories)
            config = config.replace(stop_threshold=max(config.stop_floor, config.stop_margin * peak))
        return cls(models, config, calibration, gesture_thresholds)

    # ---------------------------------------------------------------------------------- running
    def warmup(self) -> None:
        """Compile/load every numba kernel on the live path, then reset (call before a session)."""
        rng = np.random.default_rng(0)
        t = 0.0
        p = np.zeros(3)
        for k in range(400):
            t += 0.02
            ang = 0.05 * k
            p = np.array([0.3 * math.sin(ang), 0.2 * math.cos(1.3 * ang), 0.01 * k])
            q = np.array([math.cos(0.5 * ang), 0.3 * math.sin(0.5 * ang), 0.2, 0.1])
            q = q + 1e-3 * rng.standard_normal(4)
            self.push(t, p, q / np.linalg.norm(q))
        self.reset()

    def reset(self) -> None:
        """Forget the stream (buffers, windows, stop detector, counters)."""
        self._restart()
        self.stop.armed = True
        self.stop._fired_at = -math.inf
        self._t = None
        self._jump_run = 0
        self.stats = dict.fromkeys(STAT_KEYS, 0)

    def _restart(self) -> None:
        self._pending = None
        self.preprocessor.reset()
        self.bank.reset()
        self.stop.reset()

    def gesture_dissimilarities(self) -> dict[str, float]:
        """Latest best (lowest) matcher output per gesture label."""
        d = self.bank.d
        out = dict.fromkeys(self.gestures, math.inf)
        for j, lab in enumerate(self.labels):
            if d[j] < out[lab]:
                out[lab] = float(d[j])
        return out

    def push(self, t: float, p: Sequence[float] | np.ndarray, q: Sequence[float] | np.ndarray) -> list[Event]:
        """Offer one pose sample; return the events it triggers (usually none).

        Parameters
        ----------
        t : float
            Time stamp [s] (the stream's clock).
        p : array_like, shape (3,)
            Position [m].
        q : array_like, shape (4,)
            Orientation quaternion ``(w, x, y, z)`` (normalized here).

        Returns
        -------
        list of Event
            A stop event, or a gesture event, or nothing.
        """
        self.stats["samples"] += 1
        self.observations.clear()
        accepted = self._accept(t, p, q)
        if accepted is None:
            return []
        t, p, q = accepted
        st, c = self.stats, self.config
        stop = self.stop.update(t, q)
        n_geo = self.preprocessor.n_geometric
        descriptors = self.preprocessor.push_all(p, q)
        st["geometric"] += self.preprocessor.n_geometric - n_geo
        if stop:
            st["stops"] += 1
            self._pending = None
            if c.refractory_reset:
                self.bank.reset()
            return [Event(STOP, t, -1.0, -1)]
        if not descriptors:
            pend = self._pending
            if pend is not None and t - pend[3] >= c.decision_wait and not self.stop.active:
                return self._fire(t)
            return []
        events: list[Event] = []
        for d in descriptors:
            if not np.isfinite(d).all():
                st["bad_descriptors"] += 1
                self._restart()
                return events
            events += self._on_descriptor(t, d)
        return events

    def _accept(self, t: float, p: Any, q: Any) -> tuple[float, np.ndarray, np.ndarray] | None:
        """Validate a sample (finite, non-zero quaternion, time moving on, no jump) and make its
        quaternion sign continuous; None when it is skipped (counted in :attr:`stats`)."""
        st, c = self.stats, self.config
        sample = well_formed(t, p, q, st)
        if sample is None:
            return None
        t, p, q = sample
        if self._t is not None:
            dt = t - self._t
            if dt <= 0.0:
                st["repeated" if dt == 0.0 else "backwards"] += 1
                return None
            if se3.quaternion_sign(q, self._q) < 0.0:
                q = -q
                st["sign_flips"] += 1
            if dt > c.max_gap:
                st["gaps"] += 1
                self._restart()
            elif self._is_jump(p, q):
                self._jump_run += 1
                if self._jump_run < c.jump_patience:
                    st["jumps"] += 1
                    return None
                st["relocations"] += 1
                self._restart()
            self._jump_run = 0
        self._t, self._p, self._q = t, p, q
        st["accepted"] += 1
        return t, p, q

    def _is_jump(self, p: np.ndarray, q: np.ndarray) -> bool:
        """Farther from the previous sample than a hand can move in one sample."""
        dp = p - self._p
        return float(dp @ dp) > self.config.jump_distance**2 or float(q @ self._q) < self._cos_jump

    def _on_descriptor(self, t: float, d: np.ndarray) -> list[Event]:
        """Match a new descriptor sample and decide (first crossing, or the minimum ratio)."""
        st, c = self.stats, self.config
        dj = self.bank.update(d)
        self.last_matched = dj.copy()
        self.observations.append((t, self.last_matched))
        st["descriptors"] += 1
        if self.stop.active:
            self._pending = None
            return []
        ratio = dj / self.model_thresholds
        j = int(np.argmin(ratio))
        r = float(ratio[j])
        if c.decision == "first":
            if r < 1.0:
                self._pending = (j, r, float(dj[j]), t, 0, self._second(ratio, j))
                return self._fire(t)
            return []
        pend = self._pending
        if r < 1.0 and (pend is None or r < pend[1]):
            self._pending = (j, r, float(dj[j]), t, 0, self._second(ratio, j))
            return []
        if pend is None:
            return []
        stale = pend[4] + 1
        self._pending = (*pend[:4], stale, pend[5])
        if r >= 1.0 or stale >= c.decision_patience or t - pend[3] >= c.decision_wait:
            return self._fire(t)
        return []

    def _fire(self, t: float) -> list[Event]:
        """Emit the pending candidate at time ``t`` [s] and apply the refractory reset."""
        assert self._pending is not None
        j, r, d, _, _, r2 = self._pending
        self._pending = None
        if self.config.refractory_reset:
            self.bank.reset()
        if r2 < self.config.decision_margin * r:
            self.stats["ambiguous"] += 1
            return []
        self.stats["events"] += 1
        return [Event(self.labels[j], t, d, j)]

    def _second(self, ratio: np.ndarray, j: int) -> float:
        """Lowest ratio ``d/τ`` among the models of gestures other than model ``j``'s."""
        if self.config.decision_margin <= 1.0:
            return math.inf
        other = ratio[self._other[self._label_index[j]]]
        return float(other.min()) if other.size else math.inf

    def describe(self) -> dict[str, Any]:
        """Parameters, model summary and calibration as a JSON-friendly dict."""
        return {
            "config": self.config.to_dict(),
            "threshold": self.threshold,
            "gesture_thresholds": dict(self.gesture_thresholds),
            "stop_threshold": self.stop_threshold,
            "n_models": len(self.labels),
            "gestures": self.gestures,
            "model_lengths": [int(n) for n in self.bank.lengths],
            "window_spacing": self.preprocessor.m,
            "calibration": None if self.calibration is None else self.calibration.summary(),
        }
