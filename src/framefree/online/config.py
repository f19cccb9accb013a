"""Parameters of framefree's live recognizer (segment spotting), in one frozen dataclass.

Every value that can be derived from the model recordings is ``None`` by default and derived when
the recognizer is built (:meth:`framefree.online.Recognizer.from_trajectories`); the derived values
are reported by :meth:`~framefree.online.Recognizer.describe` and stored with a gesture library.
Parameters that are about people in general (how far to look back, how long to wait) are
constants documented here. See ``docs/online.md``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from ..descriptors.bilts import ALIGNMENTS
from .vertical import VERTICAL_MARGIN, up_vector

__all__ = ["RecognizerConfig"]


@dataclass(frozen=True)
class RecognizerConfig:
    """Configuration of the segment-spotting recognizer.

    Attributes
    ----------
    L : float
        Scale length [m] of the screw path: progress and descriptor of the classifier, motion speed
        and closure of the segmenter (0.1).
    ds_scale : float
        BILTS+ window scale [m] of the classifier (0.06; development people: 0.03 and 0.09 missed
        more straight-line and elbow gestures, F1 0.945 and 0.944 against 0.955).
    presmooth : int
        Gaussian pre-smoothing window [samples at 50 Hz] of the classifier (5).
    axis_prior : float
        Weight κ of the BILTS+ axis prior of the classifier (1.0, as the recommended offline
        method; 0: the reference's frame origin). See docs/algorithms/bilts.md#axis-prior.
    align : {"gram", "singular"}
        What the classifier's DTW aligns on: the 21 dot products of the six vectors of each BILTS+
        sample ("gram", v13) or its six singular values ("singular", the reference and the
        offline default). See docs/algorithms/bilts.md#gram-alignment.
    n_samples : int
        Progress samples of the classifier's descriptor (50, as offline).
    relative_window : bool
        Give the classifier's BILTS+ windows a fixed spacing in samples, so they cover the same
        fraction of a small and of a large performance of a gesture (True), instead of a fixed
        progress ``ds_scale`` (False, the reference). See docs/algorithms/bilts.md#fixed-spacing.
    window_spacing : int or None
        That spacing [samples]; ``None``: ``ds_scale`` over the median progress step of the model
        recordings, rounded (the spacing the reference gives a typical model).
    dt : float
        Step of the uniform time grid [s] (0.02: the classifier's own 50 Hz grid).
    speed_lag : int
        Grid samples over which the motion speed is measured (5: 0.1 s).
    noise_factor, peak_fraction : float
        Rest level = max(noise_factor × the models' noise floor, peak_fraction × their smallest
        stroke peak) (:func:`~framefree.online.segmentation.speed_levels`).
    move_factor : float
        Move level = move_factor × rest level (1.5; 2 before v8). The rest level already lies
        three times above the noise floor, so a narrower hysteresis starts no unit on noise, and
        a small, slow person's stroke (peak speed 0.12 m/s where the slowest demonstration
        peaks at 0.31) still becomes a unit.
    valley_ratio : float
        A speed minimum below this fraction of the stroke's peak splits two strokes (0.5).
    max_units, max_duration, max_pause, pause_ratio : int, float, float, float or None
        Candidate limits: units per candidate, duration [s], longest rest inside [s], longest rest
        inside relative to the mean duration of the candidate's units. ``None``: from the
        models — twice the most units of any model recording plus one (a hesitation may cut each
        stroke in two); ``span_factor`` × the
        longest model gesture; ``span_factor`` × the longest rest inside a model gesture;
        ``pause_factor`` × the largest such rest-to-stroke ratio of a model gesture.
    span_factor : float
        How much slower than the model demonstrations a person may be (2.5: a tempo factor of 0.6
        with room for a long reversal pause).
    pause_factor : float
        How much longer, relative to their own strokes, than in the demonstrations a person may
        pause inside a gesture (1.5).
    min_pause : float
        A rest of this length [s] is always allowed inside a candidate (0.5).
    margin : int
        Grid samples added before and after a candidate when it is cut out (5).
    confirm : float
        Rest [s] after a pending candidate before it fires (0.2).
    max_wait : float
        Latest firing time [s] after a pending candidate's end (1.0).
    fire_on_motion : bool
        When the hand moves on before a pending candidate's ``confirm`` rest and no longer
        candidate beats it, fire it all the same (True, v6) or take it for part of a longer
        motion and drop it (False: a gesture ends in rest; 20 development people: the same 419
        true positives, false positives 6 → 5).
    rest_before : float
        Rest [s] the hand must have held before a candidate's first unit: a gesture starts from
        rest, not in the middle of a motion (0.2, the ``confirm`` rest a gesture ends with; 0:
        no such rule, v6). With ``fire_on_motion`` False, 20 development people: the same 419
        true positives, false positives 5 → 3; the third side of a square no longer starts a
        zigzag.
    gesture_thresholds : dict of str to float or None
        τ_g per gesture; ``None``: calibrated from the models
        (:mod:`~framefree.online.thresholds`). Overridable per gesture.
    threshold : float or None
        One τ for every gesture (overrides the calibration).
    negative_quantile : float
        Quantile of the generic non-gesture episodes' scores taken as ``N_g`` (0.05).
    gated_negatives : bool
        A generic episode that cannot pass a gesture's closure and size limits counts as
        infinitely far from it (True), instead of being left out of its quantile (False).
    rival_negatives : bool
        The other gestures' recordings are negatives too: ``N_g`` is at most the distance of the
        nearest pair of a recording of ``g`` and one of another gesture.
    drawn_negatives : bool
        Random shapes drawn in the air (:mod:`~framefree.online.scribbles`) are negatives too, so
        that a gesture's threshold does not hang on which other gestures are enrolled (True).
    threshold_position : float
        ``τ_g = P_g^(1-a) N_g^a`` between the worst demonstration ``P_g`` and the negatives ``N_g``
        (0.7: nearer the negatives, because other people's performances lie farther from the
        models than one person's demonstrations lie from each other; 40 development people: F1
        0.971 at 0.09 false positives per minute, against 0.966 and 0.07 with the geometric
        midpoint 0.5).
    closure : bool
        Accept a candidate only within its gesture's closure limit (True).
    closure_exponent : float
        Closure limit = (largest closure of the demonstrations) ** closure_exponent (0.65;
        development people: 0.5, the geometric midpoint between the demonstrations and a
        one-way motion, let a reposition and the approach back pass as *go up*, F1 0.961 and
        0.21 false positives per minute against 0.969 and 0.095; 0.8 gave 0.954).
    closure_pooled : bool
        Apply the exponent to the largest closure of *all* returning gestures of the vocabulary
        rather than of the gesture's own demonstrations (a gesture returns when its largest
        closure is below ½, nearer a return than a one-way motion). How precisely a hand
        comes back is the person's, not the gesture's: one gesture's five precise demonstrations
        say little about how far another person stops from the start. False (40 development
        people: a figure eight added to the HPM seven 97.4 → 99.4 %, but the seven's false
        positives 7 → 13 and F1 0.975 → 0.971; docs/library.md, "An eighth gesture, measured").
    return_error : float
        How far [m of screw path, with ``L``] from where it began a person may end a gesture that
        returns, whatever the demonstrations did: a candidate that ends this close to its start
        passes the closure limit (0.05 m, a property of people, not of the models: the replica's
        least consistent people stop up to about 4.5 cm and 13° from the start, 95 %; five precise
        demonstrations of a figure eight or a small circle otherwise give a limit that other
        people's smaller or sloppier performances miss). 0 turns it off.
    corners : bool
        Accept a candidate only with no more corners than its gesture's demonstrations have
        (True; only where they agree). A *corner* is a turn of the hand's heading of more than
        ``corner_angle`` between two movement units, or of more than half of it where the
        units' chords turn by more than ``corner_angle`` (v16,
        :func:`~framefree.online.span_shape.is_corner`): people slow down where a path bends
        sharply, so the units of a square drawn in the air meet at right angles, or, drawn
        fluently, at a speed minimum inside the rounded corner, while a hesitation on a circle
        leaves the heading nearly as it was.
    corner_angle : float
        Smallest turn [deg] that counts as a corner (60; a near-stop on a smooth path turns the
        heading by the arc it creeps along, a corner by the angle drawn. Development people,
        20 × 3 styles: 60 counted a corner in 1 of 99 figure eights, none of 96 circles, and
        missed every corner of 1 of 99 squares; 45 counted one in 7 eights).
    corner_slack : int
        Corners a candidate may have beyond the number its gesture's demonstrations agree on (2,
        v17: on six real people, ``machete_vive``, with takes cut at v17's rest level, one
        person's agreeing takes were exceeded by 25.8 % of the other people's performances with
        0, 5.2 % with 1 and 0.17 % with 2; v16's level, at which the slowest takes started no
        unit, had suggested 1). A circle still admits no square, diamond or pentagon.
    slack_corners : int or None
        Only a gesture whose demonstrations agree on at most this many corners gets
        ``corner_slack`` (``None``, v17: every gesture gets it; with takes cut at v17's rest
        level other people add corners to gestures of several too, and the v15 rule, 1, let
        12.3 % of the real people's performances exceed a limit).
    turns : bool
        Accept a candidate only if no two of its corners turn in a way its gesture's
        demonstrations never do (:func:`~framefree.online.limits.forbidden_turns`): a triangle
        or a square turns the same way at every corner, a Z turns back at its second. False
        (v17): on six real people, where one person's takes all turned one way (the golf swing,
        2 limits), 20 of the other people's 50 performances turned the other way; on the
        replica's development people it kept 3 unenrolled squares in 8 streams from firing a
        taught zigzag, a gain that does not hold for real people.
    up : str or None
        The axis of the tracking system's world that points up (``"+z"`` for framefree's own
        frame, ROS and files read with a named convention; ``"+y"`` for the OpenVR source, which
        keeps SteamVR's y up, and the replica), or ``None``: no
        vertical is known and nothing depends on one (default). When set, a candidate is
        accepted only if it moves about as vertically as its gesture's demonstrations
        (:mod:`~framefree.online.vertical`): a Z is no longer an N. A world tilted against
        this axis breaks the rule, so set it only where the vertical is known.
    vertical_margin : float
        How far another person's verticality may lie outside the demonstrations' range (0.45:
        98.3 % of the real Vive comparisons, :data:`~framefree.online.vertical.VERTICAL_MARGIN`).
    size : bool
        Accept a candidate only within its gesture's size limits (True).
    size_factor : float
        People make a gesture up to this factor smaller than the demonstrations (1.5: the
        population's ±30 % with room; development people: 2.0 accepted 9 more turns of the
        tracker in the hand as *go down*). On six real people (``machete_vive``,
        ``benchmarks/real_sizes.py``) 7.8 % of the other people's performances were smaller than
        one person's smallest take by more; ``size_reach`` lets the limit down where that is safe.
    size_growth : float
        People make a gesture up to this factor larger than the demonstrations (2.5; 1.5 before
        v10). On six real people, one person's largest take was exceeded by more than 1.5 times
        by 6.9 % of the other people's performances, by more than 2.5 times by 0.9 %
        (``benchmarks/real_sizes.py``). Development people: 2.0 and 2.5 alike took 9 more
        performances of large, sloppy people, and one reach more as *go left* in the plain and
        in the sloppy style.
    size_reach : float
        Where nothing that is no gesture looks like a gesture at smaller sizes (re-grips
        included), its lower size limit reaches down to this factor below the smallest
        demonstration instead (2.0: people make a gesture up to half the size; 1: never;
        :func:`~framefree.online.thresholds.reach_down`). A circle drawn small is still a
        circle; a forearm turned out and back by less is a re-grip.
    stop_threshold : float or None
        Stop detector threshold on the windowed angular speed [rad/s]; ``None``: ``stop_margin`` ×
        the fastest sustained rotation of any model recording, at least ``stop_floor``.
    stop_margin, stop_floor : float
        (1.3, 3.0 rad/s; development people: 1.2 fired on 6 fast forearm gestures, 1.3 on 2, with
        the same stop signals found).
    stop_window, stop_min_duration, stop_rearm, stop_refractory : float
        Windowed stop detector (:class:`~framefree.online.stop.StopDetector`): 0.08 s, 0.04 s, 0.7,
        1.5 s.
    stop_confirm, stop_sustain_ratio, stop_instant : float
        The stop detector's shape check: a candidate whose angular speed over ``stop_confirm``
        seconds reaches ``stop_sustain_ratio`` × its peak is a fast gesture stroke, not a stop;
        one faster than ``stop_instant`` × the threshold fires at once (0.3 s, 0.82, 1.6; 0 s turns
        the check off).
    rest_speed, move_speed : float or None
        Segmenter levels [m/s of screw path]; ``None``: from the models.
    closure_limits : dict of str to float or None
        Largest closure accepted per gesture; ``None``: from the models
        (:func:`~framefree.online.limits.closure_limit`).
    opening_limits : dict of str to float or None
        Smallest closure accepted per gesture (an open stroke must not come back to its start);
        ``None``: from the models (:func:`~framefree.online.limits.opening_limit`); a library
        saved before this field existed has none.
    corner_limits : dict of str to int or None
        Most corners accepted per gesture (a gesture not in it has no limit); ``None``: from the
        models, for each gesture whose demonstrations agree on their number
        (:func:`~framefree.online.limits.corner_limit`).
    forbidden_turns : dict of str to int or None
        :func:`~framefree.online.span_shape.turn_kinds` bits a candidate may not show per
        gesture (a gesture not in it has none); ``None``: from the models
        (:func:`~framefree.online.limits.forbidden_turns`; a library saved before this field
        existed gets them from its takes when it is loaded).
    vertical_limits : dict of str to (float, float) or None
        Smallest and largest verticality accepted per gesture, used only when ``up`` is set;
        ``None``: from the models (:func:`~framefree.online.vertical.vertical_limits`).
    gesture_pauses : bool
        Accept a candidate as a gesture drawn in one go (``one_go``) only if its longest rest at
        a corner (:func:`~framefree.online.span_shape.corner_rest`) lasts at most
        ``min_pause`` (True, v14; a library saved before keeps False). A Z drawn in one go then
        admits no reposition, a rest and two of a triangle's sides, while a gesture whose
        demonstrator pauses at its reversal keeps the common pause limits and a hesitation in
        mid-stroke (no corner) stays free.
    one_go : list of str or None
        The gestures drawn in one go, used with ``gesture_pauses``; ``None``: from the models
        (:func:`~framefree.online.limits.one_go_gestures`).
    size_limits : dict of str to (float, float) or None
        Smallest and largest size [m of screw path] accepted per gesture; ``None``: from the models
        (:func:`~framefree.online.limits.size_limits`).
    max_bridge : float
        Longest dropout [s] bridged by ScLERP instead of restarting (0.5).
    """

    L: float = 0.1
    ds_scale: float = 0.06
    presmooth: int = 5
    axis_prior: float = 1.0
    align: str = "gram"
    n_samples: int = 50
    relative_window: bool = True
    window_spacing: int | None = None
    dt: float = 0.02
    speed_lag: int = 5
    noise_factor: float = 3.0
    peak_fraction: float = 0.05
    valley_ratio: float = 0.5
    max_units: int | None = None
    max_duration: float | None = None
    max_pause: float | None = None
    pause_ratio: float | None = None
    span_factor: float = 2.5
    pause_factor: float = 1.5
    min_pause: float = 0.5
    margin: int = 5
    confirm: float = 0.2
    max_wait: float = 1.0
    fire_on_motion: bool = False
    rest_before: float = 0.2
    gesture_thresholds: dict[str, float] | None = None
    threshold: float | None = None
    negative_quantile: float = 0.05
    gated_negatives: bool = True
    rival_negatives: bool = True
    drawn_negatives: bool = True
    threshold_position: float = 0.7
    closure: bool = True
    closure_exponent: float = 0.65
    closure_pooled: bool = False
    return_error: float = 0.05
    corners: bool = True
    corner_angle: float = 60.0
    corner_slack: int = 2
    slack_corners: int | None = None
    turns: bool = False
    up: str | None = None
    vertical_margin: float = VERTICAL_MARGIN
    size: bool = True
    size_factor: float = 1.5
    size_growth: float = 2.5
    size_reach: float = 2.0
    stop_threshold: float | None = None
    stop_margin: float = 1.3
    stop_floor: float = 3.0
    stop_window: float = 0.08
    stop_min_duration: float = 0.04
    stop_rearm: float = 0.7
    stop_refractory: float = 1.5
    stop_confirm: float = 0.3
    stop_sustain_ratio: float = 0.82
    stop_instant: float = 1.6
    rest_speed: float | None = None
    move_speed: float | None = None
    move_factor: float = 1.5
    closure_limits: dict[str, float] | None = None
    opening_limits: dict[str, float] | None = None
    corner_limits: dict[str, int] | None = None
    forbidden_turns: dict[str, int] | None = None
    vertical_limits: dict[str, tuple[float, float]] | None = None
    gesture_pauses: bool = True
    one_go: list[str] | None = None
    size_limits: dict[str, tuple[float, float]] | None = None
    max_bridge: float = 0.5

    def __post_init__(self) -> None:
        positive = ("L", "ds_scale", "dt", "span_factor", "pause_factor", "size_factor", "size_growth",
                    "stop_margin", "stop_floor", "stop_window", "max_bridge", "max_wait")
        for name in positive:
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        for name in ("presmooth", "speed_lag"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        if not (self.return_error >= 0 and self.return_error < float("inf")):
            raise ValueError(f"return_error must be a finite number >= 0, got {self.return_error}")
        if not (self.axis_prior >= 0 and self.axis_prior < float("inf")):
            raise ValueError(f"axis_prior must be a finite number >= 0, got {self.axis_prior}")
        if self.align not in ALIGNMENTS:
            raise ValueError(f"align must be one of {', '.join(ALIGNMENTS)}, got {self.align!r}")
        if self.window_spacing is not None and not self.window_spacing >= 1:
            raise ValueError(f"window_spacing must be at least 1, got {self.window_spacing}")
        if self.n_samples < 5:
            raise ValueError(f"n_samples must be at least 5, got {self.n_samples}")
        if not 0 < self.valley_ratio < 1:
            raise ValueError(f"valley_ratio must be in (0, 1), got {self.valley_ratio}")
        if not self.move_factor > 1:
            raise ValueError(f"move_factor must be above 1 (a hysteresis), got {self.move_factor}")
        if self.threshold is not None and not self.threshold > 0:
            raise ValueError(f"threshold must be positive, got {self.threshold}")
        if self.stop_threshold is not None and not self.stop_threshold > 0:
            raise ValueError(f"stop_threshold must be positive, got {self.stop_threshold}")
        if self.max_units is not None and self.max_units < 1:
            raise ValueError(f"max_units must be at least 1, got {self.max_units}")
        if self.confirm < 0 or self.margin < 0:
            raise ValueError("confirm and margin must not be negative")
        for name in ("closure_limits", "opening_limits"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, {str(g): float(v) for g, v in getattr(self, name).items()})
        for name in ("corner_limits", "forbidden_turns"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, {str(g): int(v) for g, v in getattr(self, name).items()})
        if self.corner_slack < 0:
            raise ValueError(f"corner_slack must not be negative, got {self.corner_slack}")
        if not 0 <= self.corner_angle <= 180:
            raise ValueError(f"corner_angle must be in [0, 180] degrees, got {self.corner_angle}")
        if self.one_go is not None:
            object.__setattr__(self, "one_go", [str(g) for g in self.one_go])
        for name in ("size_limits", "vertical_limits"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, {str(g): (float(v[0]), float(v[1]))
                                                for g, v in getattr(self, name).items()})
        if self.up is not None:
            up_vector(self.up)  # names the axes it accepts
        if not 0 <= self.vertical_margin <= 1:
            raise ValueError(f"vertical_margin must be in [0, 1], got {self.vertical_margin}")
        if self.gesture_thresholds is not None:
            bad = {g: v for g, v in self.gesture_thresholds.items() if not float(v) > 0}
            if bad:
                raise ValueError(f"gesture thresholds must be positive, got {bad}")
            object.__setattr__(self, "gesture_thresholds",
                               {str(g): float(v) for g, v in self.gesture_thresholds.items()})

    def replace(self, **changes: Any) -> RecognizerConfig:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """All fields as a JSON-serializable dict."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RecognizerConfig:
        """Inverse of :meth:`to_dict`; unknown keys raise ``ValueError`` naming them."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = set(d) - names
        if unknown:
            raise ValueError(f"unknown recognizer settings {sorted(unknown)}")
        return cls(**d)
