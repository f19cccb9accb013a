"""Every value of the live recognizer that comes from its takes, and the parts built from them.

:func:`resolve_learned` measures on the takes every :class:`~framefree.online.learned.
LearnedSettings` value the caller did not give: the rest and move speeds, the candidate limits
(units, duration, pauses, the gestures drawn in one go), each gesture's geometric limits
(closure, opening, size, corners, turns, and with a known vertical its verticality), the
thresholds τ_g and the stop threshold, and records the rule behind each (its
:class:`~framefree.online.learned.Provenance`). A value that is given is kept, so a saved library
restores without calibrating again. :func:`make_spotter` turns the settings into the spotter's
per-model arrays, and :func:`segment_descriptor` is the offline descriptor every segment is
classified with.

See ``docs/online.md`` (What it learns from the takes).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..core.progress import reparameterize
from ..core.trajectory import Trajectory
from ..descriptors.base import Descriptor, get_descriptor
from ..descriptors.bilts import window_spacing
from .config import RecognizerConfig
from .hand_direction import cone_factor, direction_limit, fixed_frame, hand_turn
from .learned import GIVEN, LEARNED_NAMES, LearnedSettings, Provenance, rule_name, takes_digest
from .limits import (
    candidate_limits,
    closure_limit,
    corner_limit,
    forbidden_turns,
    gesture_directions,
    gesture_geometry,
    gesture_proportions,
    gesture_travels,
    gesture_verticality,
    one_go_gestures,
    opening_limit,
    pooled_closures,
    size_limits,
    travel_limit,
    travel_percentiles,
    travel_shares,
)
from .noisy_orientation import constant_orientation, unusable_orientation_advice
from .proportions import proportion_limits
from .rest_levels import restless_takes, speed_levels
from .segment_classifier import SegmentClassifier
from .segmentation import SpeedLevels
from .smoothing import GridSmoother, noise_limit, sensor_smoothing, smoothed_take
from .span_shape import ALTERNATING, SAME_SENSE
from .spotting import Spotter
from .stop import rotation_angle, sustained_peak_speed
from .thresholds import (
    SegmentThresholds,
    calibrate_segment_thresholds,
    reach_down,
    take_scores,
    unseen_gestures,
)
from .vertical import up_vector, vertical_limits

__all__ = ["STILL_ORIENTATION", "LearnedDraft", "decided_smoothing", "make_spotter",
           "model_window_spacing", "orientation_advice", "resolve_learned", "resolve_smoothing",
           "rest_advice", "segment_descriptor", "smoothing_advice", "stop_threshold_rule",
           "takes_advice", "unseen_advice"]


def segment_descriptor(config: RecognizerConfig, spacing: int | None = None) -> Descriptor:
    """The offline descriptor the recognizer classifies segments with: BILTS+ with screw-path
    progress and the configuration's descriptor settings; with ``relative_window``, windows
    ``spacing`` samples apart (the learned ``window_spacing``)."""
    d = config.descriptor
    return get_descriptor("bilts+", progress="screw", L=d.L, ds_scale=d.ds_scale,
                          n_samples=d.n_samples, presmooth=d.presmooth, axis_prior=d.axis_prior,
                          spacing=spacing if d.relative_window else None, align=d.align)


def model_window_spacing(trajectories: Sequence[Trajectory], config: RecognizerConfig) -> int:
    """The reference's window spacing for a typical model recording: ``ds_scale`` over the median
    progress step of the recordings, rounded (at least 1)."""
    d = config.descriptor
    steps = [reparameterize(tr, "screw", d.L, d.n_samples, presmooth=d.presmooth).ds
             for tr in trajectories]
    return window_spacing(d.ds_scale, float(np.median(steps)))


class LearnedDraft:
    """Learned values while they are being derived: the given ones, then each rule's.

    Parameters
    ----------
    given : dict of str to object
        Learned values fixed by the caller (kept, with the rule ``"given"``).
    """

    def __init__(self, given: dict[str, Any] | None = None) -> None:
        self.values: dict[str, Any] = dict.fromkeys(LEARNED_NAMES)
        self.rules: dict[str, str] = {}
        for k, v in (given or {}).items():
            if v is not None:
                self.values[k], self.rules[k] = v, GIVEN

    def missing(self, *names: str) -> bool:
        """Whether any of ``names`` is still unknown."""
        return any(self.values[n] is None for n in names)

    def fill(self, rule: Callable[..., Any] | str, **values: Any) -> None:
        """Set each of ``values`` that is still unknown, derived by ``rule``."""
        for k, v in values.items():
            if self.values[k] is None and v is not None:
                self.values[k] = v
                self.rules[k] = rule if isinstance(rule, str) else rule_name(rule)

    def settings(self, takes: int = 0, digest: str = "") -> LearnedSettings:
        """The values as :class:`LearnedSettings`, with their provenance."""
        rules = {k: r for k, r in self.rules.items() if self.values[k] is not None}
        return LearnedSettings(**self.values, provenance=Provenance(rules, takes, digest))


def resolve_learned(
    trajectories: Sequence[Trajectory],
    labels: Sequence[str],
    config: RecognizerConfig,
    classifier: SegmentClassifier,
    draft: LearnedDraft,
) -> tuple[LearnedSettings, SegmentThresholds | None]:
    """Derive every learned value ``draft`` does not hold yet from the takes.

    Returns the learned settings and the threshold calibration (``None`` when the thresholds
    were given).
    """
    k, L = config.constants, config.descriptor.L
    gestures = list(dict.fromkeys(labels))
    v = draft.values
    if draft.missing("rest_speed", "move_speed"):
        lv = speed_levels(trajectories, L, k.dt, k.speed_lag, k.noise_factor, k.peak_fraction,
                          k.move_factor, k.rest_before)
        draft.fill(speed_levels, rest_speed=lv.rest, move_speed=lv.move)
    levels = SpeedLevels(v["rest_speed"], v["move_speed"])
    if draft.missing("max_units", "max_duration", "max_pause", "pause_ratio"):
        units, duration, pause, ratio = candidate_limits(trajectories, levels, L, k.span_factor,
                                                         k.pause_factor, k.dt, labels, k.min_pause)
        draft.fill(candidate_limits, max_units=units, max_duration=duration, max_pause=pause,
                   pause_ratio=ratio)
    if config.gesture_pauses and draft.missing("one_go"):
        draft.fill(one_go_gestures, one_go=one_go_gestures(trajectories, labels, levels, L,
                                                           config.confirm, k.dt, k.corner_angle))
    sizes_derived = draft.missing("size_limits")
    sizes = _geometry_limits(trajectories, labels, config, levels, classifier, draft)
    if config.up is not None and draft.missing("vertical_limits"):
        values = gesture_verticality(trajectories, labels, levels, L, up_vector(config.up), k.dt)
        limits = {g: vertical_limits(values.get(g, []), k.vertical_margin) for g in gestures}
        draft.fill(vertical_limits, vertical_limits={g: x for g, x in limits.items() if x is not None})
    # a cone stands for how many people move only where the takes are more than one person's
    many = {g: n >= k.cone_takes for g, n in Counter(labels).items()}
    if config.hand_frame and draft.missing("fixed_frame"):
        draft.fill(fixed_frame, fixed_frame=fixed_frame(trajectories))
    if config.hand_frame and draft.missing("direction_limits"):
        ways = gesture_directions(trajectories, labels, levels, L, k.dt)
        cones = {g: direction_limit(ways.get(g, [])) for g in gestures if many[g]}
        draft.fill(direction_limit, direction_limits={
            g: (*cone[0].tolist(), cone[1]) for g, cone in cones.items() if cone is not None})
    if config.hand_frame and draft.missing("rotation_limits"):
        axes = gesture_directions(trajectories, labels, levels, L, k.dt, hand_turn)
        cones = {g: direction_limit(axes.get(g, [])) for g in gestures if many[g]}
        draft.fill(hand_turn, rotation_limits={
            g: (*cone[0].tolist(), cone[1]) for g, cone in cones.items() if cone is not None})
    calibration = _thresholds(trajectories, labels, config, levels, classifier, draft, sizes_derived)
    if draft.missing("travel_limits"):
        _travel_limits(trajectories, labels, config, levels, classifier, draft, sizes)
    if config.stop_threshold is not None:
        draft.fill(f"{GIVEN}: stop_threshold", stop_threshold=config.stop_threshold)
    if draft.missing("stop_threshold"):
        peak = max(sustained_peak_speed(tr.t, tr.q, k.stop_window, k.stop_min_duration)
                   for tr in trajectories)
        draft.fill(stop_threshold_rule(), stop_threshold=max(k.stop_floor, k.stop_margin * peak))
    digest = takes_digest(tr.to_array() for tr in trajectories)
    return draft.settings(len(trajectories), digest), calibration


def decided_smoothing(trajectories: Sequence[Trajectory], config: RecognizerConfig
                      ) -> tuple[float, str]:
    """The smoothing [s] for these takes and the rule that gave it: the user's
    ``config.smoothing`` when set, else decided from the takes' noise
    (:func:`~framefree.online.smoothing.sensor_smoothing`)."""
    if config.smoothing is not None:
        return config.smoothing, f"{GIVEN}: smoothing"
    k = config.constants
    lag = k.speed_lag * k.dt
    value, noise = sensor_smoothing(trajectories, k.still_speed, lag, k.noisy_smoothing)
    return value, (f"{rule_name(sensor_smoothing)} (position noise {1000 * noise:.2g} mm, "
                   f"noisy above {1000 * noise_limit(k.still_speed, lag):.2g} mm)")


def resolve_smoothing(trajectories: Sequence[Trajectory], config: RecognizerConfig,
                      draft: LearnedDraft, restoring: bool = False) -> list[Trajectory]:
    """Fill ``draft``'s ``smoothing`` and return the takes as the recognizer will see the stream:
    smoothed by it (:mod:`~framefree.online.smoothing`), or as given when it is 0.

    The user's ``config.smoothing`` when set; else a value ``draft`` holds (a library's); else
    none when ``restoring`` a library saved before the smoothing was learned (its other values
    were learned on the takes as recorded); else :func:`decided_smoothing`."""
    if config.smoothing is not None:
        draft.values["smoothing"] = None  # the user's setting wins over a library's
    elif restoring:
        draft.fill("a library saved before framefree learned its smoothing: none", smoothing=0.0)
    if draft.missing("smoothing"):
        value, rule = decided_smoothing(trajectories, config)
        draft.fill(rule, smoothing=value)
    std = draft.values["smoothing"]
    if std == 0:
        return list(trajectories)
    return [smoothed_take(tr, std, config.constants.dt) for tr in trajectories]


def smoothing_advice(trajectories: Sequence[Trajectory], config: RecognizerConfig,
                     applied: float | None) -> str | None:
    """One line when the recognizer smooths because the takes are noisy (it decided so,
    ``applied`` > 0, without the user's ``smoothing``), else ``None``."""
    if config.smoothing is not None or not applied:
        return None
    k = config.constants
    lag = k.speed_lag * k.dt
    _, noise = sensor_smoothing(trajectories, k.still_speed, lag, k.noisy_smoothing)
    return (f"the takes are noisy ({1000 * noise:.1f} mm per sample on their positions; a precise "
            f"tracker reads under {1000 * noise_limit(k.still_speed, lag):.1f} mm), so the takes "
            f"and the stream are smoothed by a Gaussian of {1000 * applied:.0f} ms and gestures "
            f"fire {GridSmoother(applied, k.dt).delay:.2f} s later (--set smoothing=0 turns it "
            "off)")


def takes_advice(trajectories: Sequence[Trajectory], config: RecognizerConfig,
                 learned: LearnedSettings, rest: bool = True) -> list[str]:
    """The one-line notes a command prints about a recognizer's takes: no rests (unless ``rest``
    is False: the user gave the speed levels), gestures the tracker does not follow, no
    orientation, a noisy sensor smoothed."""
    dropped = unusable_orientation_advice(trajectories, config, learned)
    lines = (rest_advice(trajectories, config) if rest else None, unseen_advice(learned.unseen),
             dropped or orientation_advice(trajectories),
             smoothing_advice([constant_orientation(tr) for tr in trajectories] if dropped
                              else trajectories, config, learned.smoothing))
    return [line for line in lines if line is not None]


def unseen_advice(unseen: Sequence[str] | None) -> str | None:
    """One line naming the gestures the tracker does not follow (``LearnedSettings.unseen``),
    which never fire, or ``None`` when there are none."""
    if not unseen:
        return None
    return (f"{', '.join(unseen)} will never fire: most of the takes do not move this tracker "
            "enough to be found (another limb performs it? enroll the tracker that does)")


def rest_advice(trajectories: Sequence[Trajectory], config: RecognizerConfig) -> str | None:
    """One line of advice when most takes hold no rest before or after the gesture
    (:func:`~framefree.online.rest_levels.restless_takes`), else ``None``: the sensor's rest
    level cannot be measured on them, and is guessed from their speeds, at most the speed at
    which they start or end (:func:`~framefree.online.rest_levels.rest_level`)."""
    k = config.constants
    restless = restless_takes(trajectories, config.descriptor.L, k.dt, k.speed_lag, k.peak_fraction)
    if restless.size == 0 or restless.sum() * 2 <= restless.size:
        return None
    return (f"{int(restless.sum())} of {restless.size} takes hold no rest before or after the "
            "gesture, so the sensor's rest level cannot be measured on them and is guessed from "
            "their speeds (at most the speed at which they start or end; cut tightly, recognition "
            "suffers): record each take with a short rest before and after it, or give "
            "rest_speed and move_speed (docs/online.md, Models cut without rests)")


#: How far [rad] a take's tracker may turn from its first orientation and still count as holding
#: none: a sensor of positions only (a skeleton's wrist joint, a marker) writes one quaternion
#: throughout, while a hand-held 6-DoF tracker turns by more than a degree in any gesture.
STILL_ORIENTATION = math.radians(1.0)


def orientation_advice(trajectories: Sequence[Trajectory]) -> str | None:
    """One line when no take's orientation changes by more than :data:`STILL_ORIENTATION` (a
    sensor of positions only), else ``None``.

    Without a turn of the hand the stop signal (a quick roll) cannot be made, and a planar
    gesture and its mirror image (a circle drawn clockwise and anticlockwise, the Machete
    cartwheels) differ by a rotation, so no frame-free distance tells them apart; only the way
    the path turns in the sensor's frame does, once the takes are many enough to learn it
    (:func:`~framefree.online.hand_direction.path_turn`, ``cone_takes``; docs/online-history.md,
    *A sensor without orientation*, v32). The cones of such takes lie in the sensor's frame, and
    a motion outside one is refused (:func:`~framefree.online.hand_direction.fixed_frame`, v33).
    """
    if not trajectories:
        return None
    for tr in trajectories:
        farthest = tr.q[int(np.argmin(np.abs(tr.q @ tr.q[0])))]  # from the first orientation
        if rotation_angle(tr.q[0], farthest) > STILL_ORIENTATION:
            return None
    return ("the takes hold no orientation (the quaternion never changes: a sensor of positions "
            "only?), so the stop signal, a quick roll of the hand, cannot be made, and a gesture "
            "and its mirror image (a circle drawn clockwise and anticlockwise) are told apart only "
            "by the way the path turns in the sensor's frame, learned where each has cone_takes "
            "(20) takes or more (framefree check names the gestures that lie near each other); "
            "such cones are directions of the sensor's frame, and a motion outside one is not "
            "that gesture: if the sensor has moved since the takes, use --no-hand-frame")


def stop_threshold_rule() -> str:
    """The rule of a derived stop threshold: the fastest sustained rotation of any take
    (:func:`~framefree.online.stop.sustained_peak_speed`) times ``stop_margin``, at least
    ``stop_floor``."""
    return rule_name(sustained_peak_speed) + " × stop_margin, at least stop_floor"


def _geometry_limits(trajectories: Sequence[Trajectory], labels: Sequence[str],
                     config: RecognizerConfig, levels: SpeedLevels,
                     classifier: SegmentClassifier, draft: LearnedDraft
                     ) -> dict[str, tuple[float, float]] | None:
    """Derive the closure, opening, size, corner and turn limits ``draft`` lacks from the
    geometry of the takes (:func:`~framefree.online.limits.gesture_geometry`); return each
    gesture's (smallest, largest) take size [m] it measured (``None``: nothing was missing)."""
    names = ("closure_limits", "size_limits", "opening_limits", "corner_limits", "forbidden_turns",
             "proportion_limits")
    if not draft.missing(*names):
        return None
    k = config.constants
    gestures = list(dict.fromkeys(labels))
    closed, sizes, corners, turns = gesture_geometry(trajectories, labels, classifier, levels,
                                                     config.descriptor.L, k.margin, k.dt,
                                                     k.corner_angle)
    limits = {g: corner_limit(corners.get(g, []), k.corner_slack, k.slack_corners)
              for g in gestures}
    draft.fill(corner_limit, corner_limits={g: n for g, n in limits.items() if n is not None})
    if draft.missing("proportion_limits"):
        shares = gesture_proportions(trajectories, labels, levels, config.descriptor.L, k.dt,
                                     k.corner_angle)
        kept = {g: proportion_limits(shares.get(g, []), k.proportion_factor,
                                     k.proportion_corners) for g in gestures}
        draft.fill(proportion_limits,
                   proportion_limits={g: x for g, x in kept.items() if x is not None})
    never = {g: forbidden_turns(turns.get(g, [])) for g in gestures}
    draft.fill(forbidden_turns, forbidden_turns={g: n for g, n in never.items() if n})
    largest = {g: hi for g, (_, hi) in closed.items()}
    largest = pooled_closures(largest) if k.closure_pooled else largest
    draft.fill(closure_limit, closure_limits={g: closure_limit(largest.get(g, 1.0),
                                                               k.closure_exponent)
                                              for g in gestures})
    draft.fill(opening_limit, opening_limits={g: opening_limit(closed.get(g, (0.0, 0.0))[0],
                                                               k.closure_exponent)
                                              for g in gestures})
    draft.fill(size_limits, size_limits={g: size_limits(*sizes.get(g, (0.0, np.inf)),
                                                        k.size_factor, k.size_growth)
                                         for g in gestures})
    return sizes


def _travel_limits(trajectories: Sequence[Trajectory], labels: Sequence[str],
                   config: RecognizerConfig, levels: SpeedLevels, classifier: SegmentClassifier,
                   draft: LearnedDraft, sizes: dict[str, tuple[float, float]] | None = None
                   ) -> None:
    """Derive the travel limits: a typical take's travel (``travel_percentile``; the 10th
    percentile for a gesture that turns the hand more than it moves it,
    :func:`~framefree.online.limits.travel_percentiles`) may shrink by as much as its size limit
    lets its screw path shrink (``size_factor``, or down to ``size_reach`` where the calibration
    found that safe), so that the two limits agree on how much smaller a person may be
    (:func:`~framefree.online.limits.travel_limit`). ``sizes``: the takes' size range per
    gesture, when :func:`_geometry_limits` measured it (else measured here)."""
    k, L = config.constants, config.descriptor.L
    travels = gesture_travels(trajectories, labels, levels, L, k.dt, config.descriptor.presmooth)
    if sizes is None:
        _, sizes, _, _ = gesture_geometry(trajectories, labels, classifier, levels, L, k.margin,
                                          k.dt, k.corner_angle)
    shares = travel_shares(trajectories, labels, levels, L, k.dt, config.descriptor.presmooth)
    percentiles = travel_percentiles(shares, k.travel_percentile, k.moving_share)
    limits = {}
    for g in dict.fromkeys(labels):
        smallest = sizes.get(g, (0.0, 0.0))[0]
        lowest = (draft.values["size_limits"] or {}).get(g, (0.0, np.inf))[0]
        factor = smallest / lowest if smallest > 0 and lowest > 0 else k.size_factor
        limits[g] = travel_limit(travels.get(g, []), factor,
                                 percentiles.get(g, k.travel_percentile))
    draft.fill(travel_limit, travel_limits=limits)


def _thresholds(trajectories: Sequence[Trajectory], labels: Sequence[str],
                config: RecognizerConfig, levels: SpeedLevels, classifier: SegmentClassifier,
                draft: LearnedDraft, sizes_derived: bool) -> SegmentThresholds | None:
    """Derive the thresholds τ_g ``draft`` lacks: one ``threshold`` for all, the user's
    ``gesture_thresholds``, or calibrated (:func:`~framefree.online.thresholds.
    calibrate_segment_thresholds`), which may also reach the lower size limits down where
    nothing else looks like the gesture (only for size limits derived here, ``sizes_derived``).
    Returns the calibration (``None`` when the thresholds were given)."""
    gestures = list(dict.fromkeys(labels))
    if config.threshold is not None:
        draft.fill(f"{GIVEN}: threshold",
                   gesture_thresholds=dict.fromkeys(gestures, config.threshold))
    if config.gesture_thresholds is not None:
        draft.fill(f"{GIVEN}: gesture_thresholds", gesture_thresholds=config.gesture_thresholds)
    k = config.constants
    spotter = make_spotter(classifier, np.ones(len(labels)), config,
                           draft.settings(), list(labels))
    if not draft.missing("gesture_thresholds"):
        if draft.missing("unseen"):
            scores = take_scores(trajectories, labels, classifier, levels, spotter,
                                 config.descriptor.L)
            draft.fill(unseen_gestures, unseen=unseen_gestures(scores, k.seen_fraction))
        return None
    calibration = calibrate_segment_thresholds(
        trajectories, labels, classifier, levels, spotter, config.descriptor.L,
        k.negative_quantile, k.threshold_position, gated=k.gated_negatives,
        rivals=k.rival_negatives, drawn=k.drawn_negatives,
        reach=k.size_reach / k.size_factor if config.size and sizes_derived else 1.0,
        unseparated_position=k.unseparated_position, rival_quantile=k.rival_quantile)
    draft.fill(calibrate_segment_thresholds, gesture_thresholds=calibration.thresholds)
    if draft.missing("unseen"):
        draft.fill(unseen_gestures,
                   unseen=unseen_gestures(calibration.positives, k.seen_fraction))
    if calibration.smallest_sizes:
        sizes = draft.values["size_limits"]
        draft.values["size_limits"] = {g: (calibration.smallest_sizes.get(g, lo), hi)
                                       for g, (lo, hi) in sizes.items()}
        draft.rules["size_limits"] += " and " + rule_name(reach_down)
    return calibration


def make_spotter(classifier: SegmentClassifier, model_thresholds: np.ndarray,
                 config: RecognizerConfig, learned: LearnedSettings,
                 labels: list[str]) -> Spotter:
    """The spotter of the given settings, with one threshold per model (M,): every limit the
    configuration switches on, per model in the order of ``labels``."""
    c, s, k = config, learned, config.constants
    closures = openings = sizes = corners = turns = one_go = travels = None  # None: no limit
    if c.closure and s.closure_limits is not None:
        closures = np.array([s.closure_limits.get(g, 1.0) for g in labels])
    if c.closure and s.opening_limits is not None:
        openings = np.array([s.opening_limits.get(g, 0.0) for g in labels])
    if c.size and s.size_limits is not None:
        sizes = np.array([s.size_limits.get(g, (0.0, np.inf)) for g in labels])
    if c.size and s.travel_limits is not None:
        travels = np.array([s.travel_limits.get(g, 0.0) for g in labels])
    if c.corners and s.corner_limits is not None:
        corners = np.array([s.corner_limits.get(g, np.inf) for g in labels], dtype=float)
    shares = None
    if c.corners and s.proportion_limits:
        shares = [s.proportion_limits.get(g) for g in labels]
    if s.forbidden_turns is not None and (c.turns or c.corners):
        # with ``corners``, a gesture that always turns back (a Z) refuses corners that turn
        # the same way; the other way (takes that always turn one way) only with ``turns``:
        # real people's swings break it (v25)
        kept = (ALTERNATING | SAME_SENSE if c.turns else 0) | (SAME_SENSE if c.corners else 0)
        turns = np.array([s.forbidden_turns.get(g, 0) & kept for g in labels], dtype=np.int64)
    if c.gesture_pauses and s.one_go is not None:
        one_go = np.array([g in s.one_go for g in labels])
    unseen = None if not s.unseen else np.array([g in s.unseen for g in labels])
    up = vertical = None
    if c.up is not None and s.vertical_limits is not None:
        up = up_vector(c.up)
        vertical = np.array([s.vertical_limits.get(g, (0.0, 1.0)) for g in labels])
    directions = rotations = None
    if c.hand_frame and s.direction_limits:
        directions = np.array([s.direction_limits.get(g, (0.0, 0.0, 0.0, np.nan))
                               for g in labels])
    if c.hand_frame and s.rotation_limits:
        rotations = np.array([s.rotation_limits.get(g, (0.0, 0.0, 0.0, np.nan))
                              for g in labels])
    return Spotter(classifier, model_thresholds, s.max_units, s.max_duration, s.max_pause,
                   k.margin, c.confirm, c.max_wait, closures, c.descriptor.L, sizes,
                   math.inf if s.pause_ratio is None else s.pause_ratio, k.min_pause,
                   k.return_error if c.closure else 0.0, openings, k.fire_on_motion,
                   k.rest_before, corners, k.corner_angle, turns, up, vertical, one_go,
                   travels, c.descriptor.presmooth, labels, unseen, k.returns, k.brief_starts,
                   shares, directions, k.valley_starts, rotations, cone_factor(s.fixed_frame))
