"""The live recognizer's design constants: what no user sets and no take decides.

Two frozen dataclasses hold them, both part of a :class:`~framefree.online.config.RecognizerConfig`
(its ``descriptor`` and ``constants`` fields):

* :class:`DescriptorSettings`: how a candidate and a take are described and compared (BILTS+ on
  screw progress, the same descriptor as the offline classifier);
* :class:`SpottingConstants`: facts about people in general (how much slower, smaller, larger or
  sloppier than the takes another person may be) and the fixed parts of the spotter (its grid,
  how a stop signal looks), chosen on the replica's development people and checked on real people.

Experts and benchmarks may still override any of them, by name, through
:meth:`RecognizerConfig.replace <framefree.online.config.RecognizerConfig.replace>`, the keyword
arguments of :meth:`Recognizer.from_trajectories <framefree.online.Recognizer.from_trajectories>`
or ``--set KEY=JSON`` (``framefree enroll``, the benchmarks). Each value's history and the
measurements behind it are in ``docs/online-history.md``; ``docs/online.md`` says what a user sets.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from ..descriptors.bilts import ALIGNMENTS
from .vertical import VERTICAL_MARGIN

__all__ = ["DescriptorSettings", "SpottingConstants"]


class _Group:
    """Methods shared by the frozen groups of settings."""

    def replace(self, **changes: Any) -> Any:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """Every field, JSON-serializable."""
        return dataclasses.asdict(self)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The field names."""
        return tuple(f.name for f in dataclasses.fields(cls))


def _positive(obj: Any, names: tuple[str, ...]) -> None:
    for name in names:
        if not getattr(obj, name) > 0:
            raise ValueError(f"{name} must be positive, got {getattr(obj, name)}")


@dataclass(frozen=True)
class DescriptorSettings(_Group):
    """How the live recognizer describes and compares a motion: BILTS+ on screw progress.

    Attributes
    ----------
    L : float
        Scale length [m] of the screw path, which weighs rotation against translation: the
        descriptor's progress, the motion speed [m/s of screw path] and every closure and size
        (0.1).
    ds_scale : float
        BILTS+ window [m of screw path] (0.06; on development people 0.03 and 0.09 missed more
        straight strokes and elbow gestures).
    presmooth : int
        Gaussian pre-smoothing window [samples at 50 Hz], at least 1 (5).
    axis_prior : float
        Weight κ >= 0 of the BILTS+ axis prior (1.0, as offline; 0: the reference's frame
        origin). See ``docs/algorithms/bilts.md#axis-prior``.
    align : {"gram", "singular"}
        What the DTW aligns on: the 21 dot products of each sample's six vectors (``"gram"``) or
        their six singular values (``"singular"``, the reference's).
    n_samples : int
        Progress samples of a descriptor, at least 5 (50, as offline).
    relative_window : bool
        Windows a fixed number of samples apart (True; the number is learned from the takes,
        ``LearnedSettings.window_spacing``), so a small and a large performance of a gesture are
        described alike, instead of a fixed progress ``ds_scale`` apart (False, the reference's).
    """

    L: float = 0.1
    ds_scale: float = 0.06
    presmooth: int = 5
    axis_prior: float = 1.0
    align: str = "gram"
    n_samples: int = 50
    relative_window: bool = True

    def __post_init__(self) -> None:
        _positive(self, ("L", "ds_scale"))
        if self.presmooth < 1:
            raise ValueError(f"presmooth must be at least 1, got {self.presmooth}")
        if not (self.axis_prior >= 0 and self.axis_prior < float("inf")):
            raise ValueError(f"axis_prior must be a finite number >= 0, got {self.axis_prior}")
        if self.align not in ALIGNMENTS:
            raise ValueError(f"align must be one of {', '.join(ALIGNMENTS)}, got {self.align!r}")
        if self.n_samples < 5:
            raise ValueError(f"n_samples must be at least 5, got {self.n_samples}")


@dataclass(frozen=True)
class SpottingConstants(_Group):
    """Constants of the spotter: people in general, and its fixed design.

    Each learned value (:class:`~framefree.online.learned.LearnedSettings`) is a measurement on the
    takes times one of these factors: the factor says how far another person may stray from
    the takes.

    Attributes
    ----------
    dt : float
        Step [s] of the uniform grid the poses are put on (0.02: 50 Hz, the descriptor's grid).
    speed_lag : int
        Grid samples over which the motion speed is measured, at least 1 (5: 0.1 s).
    still_speed : float
        Speed [m/s] under which a hand counts as still (0.03). A sensor whose noise (positions,
        and turns times ``L``) alone would make a still hand appear faster, over
        ``speed_lag``, is noisy: its takes and stream are smoothed by ``noisy_smoothing``
        unless the user sets ``smoothing``
        (:func:`~framefree.online.smoothing.sensor_smoothing`; 1.3 mm of noise at the defaults).
    noisy_smoothing : float
        Standard deviation [s] of the Gaussian that smooths a noisy sensor (0.067): it keeps a
        hand's gesture, which has little above 3 Hz, and gave back on 1 and 2 cm of noise what
        the noise had cost (docs/online-history.md, *Session 28*).
    noise_factor, peak_fraction : float
        Rest level = max(noise_factor × the takes' noise floor, peak_fraction × their smallest
        stroke peak) (3.0, 0.05; :func:`~framefree.online.rest_levels.speed_levels`).
    move_factor : float
        Move level = move_factor × rest level, above 1: the hysteresis of a movement unit (1.5).
    valley_ratio : float
        A speed minimum below this fraction of a stroke's peak splits two units, in (0, 1) (0.5).
    settle : float
        A stroke whose speed stays below ``valley_ratio`` × its peak this long [s] without
        resting has ended, and confirms a gesture as a rest does (0.3, v28;
        :class:`~framefree.online.segmentation.MotionSegmenter`). Chosen on SFINGE3D's
        sequences 1–18 and three Machete people: at 0.2 s the top of a golf swing settles.
        ``inf``: never.
    span_factor : float
        How much slower than the takes another person may be: the longest candidate and the
        longest rest inside one are this factor times the takes' (2.5).
    pause_factor : float
        How much longer, relative to their own strokes, than in the takes another person may
        pause inside a gesture (1.5).
    min_pause : float
        A rest [s] always allowed inside a candidate; a gesture drawn in one go may rest at most
        this long at a corner (0.5).
    margin : int
        Grid samples added before and after a candidate when it is cut out (5).
    fire_on_motion : bool
        Fire a pending candidate when the hand moves on before its confirming rest (False: a
        gesture ends in rest).
    rest_before : float
        Rest [s] the hand must have held before a candidate's first unit (0.2; 0: none).
    returns : bool
        Refuse the way back after a gesture as that gesture again
        (:mod:`~framefree.online.returns`; True).
    brief_starts : bool
        Also start candidates after a briefer rest, a dip below the rest level; a candidate
        after a full rest wins over them, and they fire only once the hand rests (True).
    valley_starts : bool
        Also start candidates where one stroke follows another without a rest, at the speed
        minimum between them (or where a stroke settled), in the tier of the brief starts
        (True since v29). SFINGE3D 31 / 3 / 12 → 35 / 3 / 8 with the cones of axes of v29
        (without them 35 / 6 / 8), the Machete right hand's eight unchanged, 3 more false
        positives on the replica's development people (docs/online-history.md, *v29*).
    negative_quantile : float
        Quantile of the non-gesture episodes' distances taken as a gesture's negative distance
        ``N_g`` (0.05).
    gated_negatives, rival_negatives, drawn_negatives : bool
        Which negatives the thresholds are calibrated on (:mod:`~framefree.online.thresholds`):
        an episode the shape limits refuse counts as infinitely far (True); the other gestures'
        takes (True); shapes drawn in the air (:mod:`~framefree.online.scribbles`, True).
    cone_takes : int
        Fewest takes of a gesture that learn its cones of hand directions and of axes (20;
        :func:`~framefree.online.hand_direction.direction_limit`): more takes than one person
        records, so that a cone stands for how many people move, not for one person's grip
        (docs/online-history.md, *v30*).
    rival_quantile : float
        Quantile, over the other gestures' takes, of their distances to a gesture's nearest
        take that bounds its ``N_g`` (0: the nearest pair). 0.05 finds more of the Machete
        right hand's gestures and fires more often on SFINGE3D's free motion
        (docs/online-history.md, *Session 27: one sensor that performs every gesture*).
    threshold_position : float
        τ_g = P_g^(1-a) N_g^a between the worst take ``P_g`` and the negatives ``N_g`` (0.7).
    unseparated_position : float
        ``a`` for a gesture whose worst take lies beyond its negatives (``P_g ≥ N_g``: no gap
        to lean into; 0.5, the geometric midpoint).
    seen_fraction : float
        A gesture at most this fraction of whose takes the spotter can find in themselves is
        not followed by the tracker and never fires (0.5: most takes must be found; 0: only a
        gesture none of whose takes is found; :func:`~framefree.online.thresholds.unseen_gestures`).
    closure_exponent : float
        Closure limit = (largest closure of the takes) ** closure_exponent (0.65).
    closure_pooled : bool
        Apply the exponent to the largest closure of every returning gesture of the vocabulary
        rather than of the gesture's own takes (False).
    return_error : float
        A candidate that ends this close [m of screw path] to its start passes the closure limit
        whatever the takes did (0.05; 0: off).
    corner_angle : float
        Smallest turn [deg] of the hand's heading, in [0, 180], that counts as a corner (60).
    corner_slack : int
        Corners a candidate may have beyond the number its gesture's takes agree on (2).
    proportion_factor, proportion_corners : float, int
        How much longer or shorter, against the next stroke, another person may draw a stroke
        between two corners than the takes (2.0), for a gesture whose takes agree on at most
        ``proportion_corners`` corners (1; :mod:`~framefree.online.proportions`; 0: none).
    slack_corners : int or None
        Only a gesture whose takes agree on at most this many corners gets ``corner_slack``
        (None: every gesture).
    vertical_margin : float
        How far, in [0, 1], another person's verticality may lie outside the takes' range (0.45;
        used only with ``RecognizerConfig.up``).
    size_factor, size_growth : float
        People make a gesture up to ``size_factor`` times smaller (1.5) and ``size_growth`` times
        larger (2.5) than the takes.
    travel_percentile : float
        The travel limit of a gesture that moves the hand is this percentile of its takes'
        travel over the factor its size range allows (:func:`~framefree.online.limits.travel_limit`;
        50: as far as a typical take, made smaller as people make it).
    moving_share : float
        A gesture moves the hand when, in the median take, the hand's path is at least this share
        of the screw path (0.5); one that turns it more than it moves it (a forearm turn) travels
        incidentally, unevenly, and its limit stays at the takes' 10th percentile
        (:func:`~framefree.online.limits.travel_percentiles`).
    size_reach : float
        Where nothing that is no gesture looks like a gesture at smaller sizes, its smallest size
        reaches down to this factor below the smallest take instead (2.0; 1: never).
    stop_margin, stop_floor : float
        Stop threshold = max(stop_floor, stop_margin × the fastest sustained rotation of any take)
        (1.3, 3.0 rad/s).
    stop_window, stop_min_duration, stop_rearm, stop_refractory : float
        The windowed stop detector (:class:`~framefree.online.stop.StopDetector`): window [s],
        shortest fast rotation [s], re-arm fraction of the threshold, refractory time [s]
        (0.08, 0.04, 0.7, 1.5).
    stop_confirm, stop_sustain_ratio, stop_instant : float
        A fast rotation that keeps ``stop_sustain_ratio`` × its peak for ``stop_confirm`` seconds
        is a gesture's stroke, not a stop; one faster than ``stop_instant`` × the threshold fires
        at once (0.3 s, 0.82, 1.6; 0 s turns the check off).
    """

    dt: float = 0.02
    speed_lag: int = 5
    still_speed: float = 0.03
    noisy_smoothing: float = 0.067
    noise_factor: float = 3.0
    peak_fraction: float = 0.05
    move_factor: float = 1.5
    valley_ratio: float = 0.5
    settle: float = 0.3
    span_factor: float = 2.5
    pause_factor: float = 1.5
    min_pause: float = 0.5
    margin: int = 5
    fire_on_motion: bool = False
    rest_before: float = 0.2
    returns: bool = True
    brief_starts: bool = True
    valley_starts: bool = True
    negative_quantile: float = 0.05
    gated_negatives: bool = True
    rival_negatives: bool = True
    rival_quantile: float = 0.0
    cone_takes: int = 20
    drawn_negatives: bool = True
    threshold_position: float = 0.7
    unseparated_position: float = 0.5
    seen_fraction: float = 0.5
    closure_exponent: float = 0.65
    closure_pooled: bool = False
    return_error: float = 0.05
    corner_angle: float = 60.0
    corner_slack: int = 2
    proportion_factor: float = 2.0
    proportion_corners: int = 1
    slack_corners: int | None = None
    vertical_margin: float = VERTICAL_MARGIN
    size_factor: float = 1.5
    travel_percentile: float = 50.0
    moving_share: float = 0.5
    size_growth: float = 2.5
    size_reach: float = 2.0
    stop_margin: float = 1.3
    stop_floor: float = 3.0
    stop_window: float = 0.08
    stop_min_duration: float = 0.04
    stop_rearm: float = 0.7
    stop_refractory: float = 1.5
    stop_confirm: float = 0.3
    stop_sustain_ratio: float = 0.82
    stop_instant: float = 1.6

    def __post_init__(self) -> None:
        if not 1 <= self.proportion_factor < float("inf"):
            raise ValueError(f"proportion_factor must be a finite number >= 1, got "
                             f"{self.proportion_factor}")
        _positive(self, ("dt", "span_factor", "pause_factor", "size_factor", "size_growth",
                         "stop_margin", "stop_floor", "stop_window"))
        for name in ("still_speed", "noisy_smoothing"):
            if not 0 <= getattr(self, name) < float("inf"):
                raise ValueError(f"{name} must be a finite number >= 0, got {getattr(self, name)}")
        if self.speed_lag < 1:
            raise ValueError(f"speed_lag must be at least 1, got {self.speed_lag}")
        if not (self.return_error >= 0 and self.return_error < float("inf")):
            raise ValueError(f"return_error must be a finite number >= 0, got {self.return_error}")
        if not 0 < self.valley_ratio < 1:
            raise ValueError(f"valley_ratio must be in (0, 1), got {self.valley_ratio}")
        if not (isinstance(self.settle, (int, float)) and self.settle > 0):
            raise ValueError(f"settle must be a positive number of seconds (Infinity: never), "
                             f"got {self.settle!r}")
        if not self.move_factor > 1:
            raise ValueError(f"move_factor must be above 1 (a hysteresis), got {self.move_factor}")
        if self.margin < 0:
            raise ValueError(f"margin must not be negative, got {self.margin}")
        if not 0 <= self.travel_percentile <= 100:
            raise ValueError(f"travel_percentile must be in [0, 100], got {self.travel_percentile}")
        if not 0 <= self.moving_share < float("inf"):
            raise ValueError(f"moving_share must be a finite number >= 0, got {self.moving_share}")
        if self.corner_slack < 0:
            raise ValueError(f"corner_slack must not be negative, got {self.corner_slack}")
        if not 0 <= self.corner_angle <= 180:
            raise ValueError(f"corner_angle must be in [0, 180] degrees, got {self.corner_angle}")
        if not 0 <= self.vertical_margin <= 1:
            raise ValueError(f"vertical_margin must be in [0, 1], got {self.vertical_margin}")
        for name in ("threshold_position", "unseparated_position"):
            if not 0 <= getattr(self, name) <= 1:
                raise ValueError(f"{name} must be in [0, 1], got {getattr(self, name)}")
        if not 0 <= self.rival_quantile <= 1:
            raise ValueError(f"rival_quantile must be in [0, 1], got {self.rival_quantile}")
        if self.cone_takes < 2:
            raise ValueError(f"cone_takes must be at least 2, got {self.cone_takes}")
        if not 0 <= self.seen_fraction <= 1:
            raise ValueError(f"seen_fraction must be in [0, 1], got {self.seen_fraction}")
