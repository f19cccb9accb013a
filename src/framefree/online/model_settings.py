"""Every setting of the live recognizer that comes from its model recordings.

:func:`resolve_config` fills each ``None`` field of a :class:`~framefree.online.config.RecognizerConfig`
from the recordings: the rest and move speeds, the candidate limits (units, duration, pauses,
the gestures drawn in one go), each gesture's geometric limits (closure, opening, size, corners,
turns, and with a known vertical its verticality), the thresholds τ_g and the stop threshold.
:func:`make_spotter` turns a resolved configuration into the spotter's per-model arrays, and
:func:`segment_descriptor` is the offline descriptor every segment is classified with. A field
that is already set is kept, so a saved library restores without recalibrating.

See ``docs/online.md`` (What comes from the models).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..core.progress import reparameterize
from ..core.trajectory import Trajectory
from ..descriptors.base import Descriptor, get_descriptor
from ..descriptors.bilts import window_spacing
from .config import RecognizerConfig
from .limits import (
    candidate_limits,
    closure_limit,
    corner_limit,
    forbidden_turns,
    gesture_geometry,
    gesture_verticality,
    one_go_gestures,
    opening_limit,
    pooled_closures,
    size_limits,
)
from .segmentation import SpeedLevels, speed_levels
from .spotting import SegmentClassifier, Spotter
from .stop import sustained_peak_speed
from .thresholds import SegmentThresholds, calibrate_segment_thresholds
from .vertical import up_vector, vertical_limits

__all__ = ["make_spotter", "model_window_spacing", "resolve_config", "segment_descriptor"]


def segment_descriptor(config: RecognizerConfig) -> Descriptor:
    """The offline descriptor the recognizer classifies segments with: BILTS+ with screw-path
    progress and the configuration's ``L``, ``ds_scale``, ``n_samples``, ``presmooth``,
    ``axis_prior``, ``align`` and, with ``relative_window``, ``window_spacing``."""
    spacing = config.window_spacing if config.relative_window else None
    return get_descriptor("bilts+", progress="screw", L=config.L, ds_scale=config.ds_scale,
                          n_samples=config.n_samples, presmooth=config.presmooth,
                          axis_prior=config.axis_prior, spacing=spacing, align=config.align)


def model_window_spacing(trajectories: Sequence[Trajectory], config: RecognizerConfig) -> int:
    """The reference's window spacing for a typical model recording: ``ds_scale`` over the median
    progress step of the recordings, rounded (at least 1)."""
    steps = [reparameterize(tr, "screw", config.L, config.n_samples, presmooth=config.presmooth).ds
             for tr in trajectories]
    return window_spacing(config.ds_scale, float(np.median(steps)))


def resolve_config(
    trajectories: Sequence[Trajectory],
    labels: Sequence[str],
    config: RecognizerConfig,
    classifier: SegmentClassifier,
) -> tuple[RecognizerConfig, SegmentThresholds | None]:
    """Fill every ``None`` field of ``config`` from the model recordings.

    Returns the resolved configuration and the threshold calibration (``None`` when the thresholds
    were given).
    """
    c = config
    gestures = list(dict.fromkeys(labels))
    if c.rest_speed is None or c.move_speed is None:
        lv = speed_levels(trajectories, c.L, c.dt, c.speed_lag, c.noise_factor, c.peak_fraction,
                          c.move_factor)
        c = c.replace(rest_speed=c.rest_speed or lv.rest, move_speed=c.move_speed or lv.move)
    levels = SpeedLevels(c.rest_speed, c.move_speed)
    c = _candidate_limits(trajectories, labels, c, levels)
    c = _geometry_limits(trajectories, labels, c, levels, classifier)
    if c.up is not None and c.vertical_limits is None:
        values = gesture_verticality(trajectories, labels, levels, c.L, up_vector(c.up), c.dt)
        limits = {g: vertical_limits(values.get(g, []), c.vertical_margin) for g in gestures}
        c = c.replace(vertical_limits={g: v for g, v in limits.items() if v is not None})
    c, calibration = _thresholds(trajectories, labels, c, levels, classifier,
                                 config.size_limits is None)
    if c.stop_threshold is None:
        peak = max(sustained_peak_speed(tr.t, tr.q, c.stop_window, c.stop_min_duration)
                   for tr in trajectories)
        c = c.replace(stop_threshold=max(c.stop_floor, c.stop_margin * peak))
    return c, calibration


def _candidate_limits(trajectories: Sequence[Trajectory], labels: Sequence[str],
                      c: RecognizerConfig, levels: SpeedLevels) -> RecognizerConfig:
    """Fill the candidate limits left ``None`` (units, duration, pauses, and with
    ``gesture_pauses`` the gestures drawn in one go) from the model recordings."""
    if None in (c.max_units, c.max_duration, c.max_pause, c.pause_ratio):
        units, duration, pause, ratio = candidate_limits(trajectories, levels, c.L, c.span_factor,
                                                         c.pause_factor, c.dt)
        c = c.replace(max_units=c.max_units or units, max_duration=c.max_duration or duration,
                      max_pause=c.max_pause or pause,
                      pause_ratio=ratio if c.pause_ratio is None else c.pause_ratio)
    if c.gesture_pauses and c.one_go is None:
        c = c.replace(one_go=one_go_gestures(trajectories, labels, levels, c.L, c.confirm, c.dt,
                                             c.corner_angle))
    return c


def _geometry_limits(trajectories: Sequence[Trajectory], labels: Sequence[str],
                     c: RecognizerConfig, levels: SpeedLevels,
                     classifier: SegmentClassifier) -> RecognizerConfig:
    """Fill the closure, opening, size, corner and turn limits left ``None`` from the geometry
    of the model recordings (:func:`~framefree.online.limits.gesture_geometry`)."""
    if None not in (c.closure_limits, c.size_limits, c.opening_limits, c.corner_limits,
                    c.forbidden_turns):
        return c
    gestures = list(dict.fromkeys(labels))
    closed, sizes, corners, turns = gesture_geometry(trajectories, labels, classifier, levels,
                                                     c.L, c.margin, c.dt, c.corner_angle)
    if c.corner_limits is None:
        limits = {g: corner_limit(corners.get(g, []), c.corner_slack, c.slack_corners)
                  for g in gestures}
        c = c.replace(corner_limits={g: k for g, k in limits.items() if k is not None})
    if c.forbidden_turns is None:
        never = {g: forbidden_turns(turns.get(g, [])) for g in gestures}
        c = c.replace(forbidden_turns={g: k for g, k in never.items() if k})
    if c.closure_limits is None:
        largest = {g: hi for g, (_, hi) in closed.items()}
        largest = pooled_closures(largest) if c.closure_pooled else largest
        c = c.replace(closure_limits={g: closure_limit(largest.get(g, 1.0), c.closure_exponent)
                                      for g in gestures})
    if c.opening_limits is None:
        c = c.replace(opening_limits={g: opening_limit(closed.get(g, (0.0, 0.0))[0],
                                                       c.closure_exponent) for g in gestures})
    if c.size_limits is None:
        c = c.replace(size_limits={g: size_limits(*sizes.get(g, (0.0, np.inf)), c.size_factor,
                                                  c.size_growth) for g in gestures})
    return c


def _thresholds(trajectories: Sequence[Trajectory], labels: Sequence[str], c: RecognizerConfig,
                levels: SpeedLevels, classifier: SegmentClassifier, sizes_derived: bool
                ) -> tuple[RecognizerConfig, SegmentThresholds | None]:
    """Fill the thresholds τ_g left ``None``: one ``threshold`` for all, or calibrated
    (:func:`~framefree.online.thresholds.calibrate_segment_thresholds`), which may also reach
    the lower size limits down where nothing else looks like the gesture (only for size limits
    derived here, ``sizes_derived``). Returns the configuration and the calibration (``None``
    when the thresholds were given)."""
    gestures = list(dict.fromkeys(labels))
    if c.threshold is not None:
        return c.replace(gesture_thresholds=dict.fromkeys(gestures, c.threshold)), None
    if c.gesture_thresholds is not None:
        return c, None
    spotter = make_spotter(classifier, np.ones(len(labels)), c, list(labels))
    calibration = calibrate_segment_thresholds(
        trajectories, labels, classifier, levels, spotter, c.L, c.negative_quantile,
        c.threshold_position, gated=c.gated_negatives, rivals=c.rival_negatives,
        drawn=c.drawn_negatives,
        reach=c.size_reach / c.size_factor if c.size and sizes_derived else 1.0)
    c = c.replace(gesture_thresholds=calibration.thresholds)
    if calibration.smallest_sizes:
        c = c.replace(size_limits={g: (calibration.smallest_sizes.get(g, lo), hi)
                                   for g, (lo, hi) in c.size_limits.items()})
    return c, calibration


def make_spotter(classifier: SegmentClassifier, model_thresholds: np.ndarray,
                 c: RecognizerConfig,
                 labels: list[str]) -> Spotter:
    """The spotter of a resolved configuration, with one threshold per model (M,): every limit
    the configuration switches on, per model in the order of ``labels``."""
    closures = openings = sizes = corners = turns = one_go = None  # None: no limit
    if c.closure and c.closure_limits is not None:
        closures = np.array([c.closure_limits.get(g, 1.0) for g in labels])
    if c.closure and c.opening_limits is not None:
        openings = np.array([c.opening_limits.get(g, 0.0) for g in labels])
    if c.size and c.size_limits is not None:
        sizes = np.array([c.size_limits.get(g, (0.0, np.inf)) for g in labels])
    if c.corners and c.corner_limits is not None:
        corners = np.array([c.corner_limits.get(g, np.inf) for g in labels], dtype=float)
    if c.turns and c.forbidden_turns is not None:
        turns = np.array([c.forbidden_turns.get(g, 0) for g in labels], dtype=np.int64)
    if c.gesture_pauses and c.one_go is not None:
        one_go = np.array([g in c.one_go for g in labels])
    up = vertical = None
    if c.up is not None and c.vertical_limits is not None:
        up = up_vector(c.up)
        vertical = np.array([c.vertical_limits.get(g, (0.0, 1.0)) for g in labels])
    return Spotter(classifier, model_thresholds, c.max_units, c.max_duration, c.max_pause,
                   c.margin, c.confirm, c.max_wait, closures, c.L, sizes,
                   math.inf if c.pause_ratio is None else c.pause_ratio, c.min_pause,
                   c.return_error if c.closure else 0.0, openings, c.fire_on_motion,
                   c.rest_before, corners, c.corner_angle, turns, up, vertical, one_go)
