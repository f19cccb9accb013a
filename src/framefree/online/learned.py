"""What the live recognizer learns from its takes, with where each value came from.

:class:`LearnedSettings` is to a :class:`~framefree.online.Recognizer` what the attributes
ending in ``_`` are to a fitted scikit-learn estimator: measured on the takes when the
recognizer is built (:func:`~framefree.online.model_settings.resolve_learned`), never chosen by
a user. A gesture library file stores it, so loading a library calibrates nothing; its
:class:`Provenance` says which rule derived each value, from which takes, in which framefree.

An expert may fix a learned value instead (``Recognizer.from_trajectories(..., max_units=3)``,
``--set max_units=3``): it is then kept as given, and its provenance says so.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._version import __version__
from .config import RecognizerConfig

__all__ = ["GIVEN", "LEARNED_NAMES", "LearnedSettings", "Provenance", "rule_name",
           "split_settings", "takes_digest"]

#: The rule recorded for a value the caller fixed instead of letting the takes decide.
GIVEN = "given"


def rule_name(fn: Callable[..., Any]) -> str:
    """``module.function`` of the function that derives a value (for :class:`Provenance`)."""
    return f"{fn.__module__}.{fn.__qualname__}"


def takes_digest(arrays: Iterable[np.ndarray]) -> str:
    """SHA-256 (hex) of the takes' samples, to say which takes a value was learned from."""
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    return h.hexdigest()


@dataclass(frozen=True)
class Provenance:
    """Where the learned values came from.

    Attributes
    ----------
    rules : dict of str to str
        For each learned value, the function that derived it (``module.function``), ``"given"``
        for a value the caller fixed, or ``"given: threshold"`` and the like for one that a user
        setting decided.
    takes : int
        How many takes they were learned from.
    takes_sha256 : str
        SHA-256 of the takes' samples (``t, x, y, z, qw, qx, qy, qz`` of every take in turn, one
        tracker after the other).
    framefree : str
        The framefree version that learned them.
    note : str
        Anything else (e.g. that they were migrated from an older library file).
    """

    rules: dict[str, str] = field(default_factory=dict)
    takes: int = 0
    takes_sha256: str = ""
    framefree: str = __version__
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """As a JSON-serializable dict."""
        return dataclasses.asdict(self)


def _per_gesture(kind: type) -> Callable[[Any], Any]:
    def cast(d: Any) -> Any:
        if d is None:
            return None
        if kind is tuple:
            return {str(g): (float(v[0]), float(v[1])) for g, v in d.items()}
        return {str(g): kind(v) for g, v in d.items()}
    return cast


_CASTS: dict[str, Callable[[Any], Any]] = {
    "window_spacing": int, "rest_speed": float, "move_speed": float, "max_units": int,
    "max_duration": float, "max_pause": float, "pause_ratio": float,
    "one_go": lambda v: [str(g) for g in v], "closure_limits": _per_gesture(float),
    "opening_limits": _per_gesture(float), "size_limits": _per_gesture(tuple),
    "travel_limits": _per_gesture(float),
    "corner_limits": _per_gesture(int), "forbidden_turns": _per_gesture(int),
    "proportion_limits": lambda d: {str(g): [(float(lo), float(hi)) for lo, hi in v]
                                    for g, v in d.items()},
    "vertical_limits": _per_gesture(tuple), "gesture_thresholds": _per_gesture(float),
    "direction_limits": lambda d: {str(g): tuple(float(x) for x in v) for g, v in d.items()},
    "rotation_limits": lambda d: {str(g): tuple(float(x) for x in v) for g, v in d.items()},
    "unseen": lambda v: [str(g) for g in v], "stop_threshold": float,
    "continuations": _per_gesture(float), "smoothing": float, "fixed_frame": bool,
    "positions_only": bool, "gate_speeds": lambda v: (float(v[0]), float(v[1])),
}


@dataclass(frozen=True)
class LearnedSettings:
    """Every value of the live recognizer derived from its takes (None: not derived, or not
    used by this recognizer).

    Attributes
    ----------
    window_spacing : int
        Spacing [samples] of the BILTS+ windows with ``relative_window``: ``ds_scale`` over the
        takes' median progress step.
    rest_speed, move_speed : float
        The segmenter's rest and move levels [m/s of screw path].
    max_units : int
        Most movement units in a candidate (twice a take's, plus one).
    max_duration, max_pause : float
        Longest candidate [s] and longest rest inside one [s].
    pause_ratio : float
        Longest rest inside a candidate relative to its units' mean duration.
    one_go : list of str
        The gestures the takes draw in one go (no rest at a corner).
    closure_limits, opening_limits : dict of str to float
        Largest and smallest closure (end-to-start distance over path) accepted per gesture.
    size_limits : dict of str to (float, float)
        Smallest and largest size [m of screw path] accepted per gesture.
    travel_limits : dict of str to float
        Shortest travel [m] of the hand's position accepted per gesture (used with
        ``RecognizerConfig.size``): the 10th percentile of the takes' travel over the factor the
        size limit allows (:func:`~framefree.online.limits.travel_limit`). The size limit
        measures the screw path, to which a turn of the wrist adds as much as a move of the
        hand; in real continuous motion (SFINGE3D) small reaches whose palm turns as it stops
        passed a swipe's size limit on their turn alone. A library saved before v18 gets them
        from its takes when it is loaded.
    corner_limits : dict of str to int
        Most corners accepted, for each gesture whose takes agree on their number.
    proportion_limits : dict of str to list of (float, float)
        For each gesture whose takes agree on their number of corners, the smallest and largest
        length ratio of each stroke to the next that a candidate with as many corners may have
        (:func:`~framefree.online.proportions.proportion_limits`; used with
        ``RecognizerConfig.corners``). A library saved before they were learned gets them from
        its takes when it is loaded.
    forbidden_turns : dict of str to int
        :func:`~framefree.online.span_shape.turn_kinds` bits a candidate may not show, per
        gesture (used with ``RecognizerConfig.turns``).
    vertical_limits : dict of str to (float, float)
        Smallest and largest verticality per gesture (only with ``RecognizerConfig.up``).
    direction_limits : dict of str to (float, float, float, float)
        Per gesture whose takes agree on it, the mean direction (x, y, z) in which the hand
        moves in the tracker's frame and the cone's half-angle [deg] around it; a candidate
        outside counts ``OFF_CONE_FACTOR`` times farther from the gesture
        (:func:`~framefree.online.hand_direction.direction_limit`; only with
        ``RecognizerConfig.hand_frame``, the default).
    rotation_limits : dict of str to (float, float, float, float)
        The same for the axis about which the hand turns in the tracker's frame
        (:func:`~framefree.online.hand_direction.hand_turn`): per gesture whose takes agree on
        it, the mean axis and the cone's half-angle [deg]; a candidate that turns about an axis
        outside counts ``OFF_CONE_FACTOR`` times farther (only with ``hand_frame``). A library
        saved before they were learned gets them from its takes when it is loaded.
    fixed_frame : bool
        Whether no take ever turns its tracker (:func:`~framefree.online.hand_direction.
        fixed_frame`): a sensor of positions only, whose frame, where the cones lie, is the
        sensor's own and not the hand's. A candidate outside a cone is then refused as that
        gesture instead of counting ``OFF_CONE_FACTOR`` times farther, and another gesture's
        take outside it bounds no threshold (v33; only with ``hand_frame``). A library saved
        before it was learned keeps the factor it was calibrated with (False).
    gesture_thresholds : dict of str to float
        Decision threshold τ_g per gesture [DTW distance].
    unseen : list of str
        The gestures the tracker does not follow, which never fire: most of their takes give
        no candidate of themselves, as when another limb performs them
        (:func:`~framefree.online.thresholds.unseen_gestures`). A library saved before v20
        gets them from its takes when it is loaded.
    stop_threshold : float
        The stop detector's threshold on the windowed angular speed [rad/s].
    continuations : dict of str to float
        Per gesture, how long [s] after a candidate of it ends another enrolled gesture that
        begins the same way may still go on (:func:`~framefree.online.continuations.
        continuation_waits`); a pending candidate waits for a rest that long at most, or
        ``max_wait`` if longer. Learned for several trackers only (a library saved before
        gets them from its takes when it is loaded).
    smoothing : float
        Standard deviation [s] of the Gaussian that smooths the takes and the stream (0: none):
        the user's ``smoothing``, or, when it is None, ``noisy_smoothing`` for takes whose
        noise (positions, and turns times ``L``) would make a still hand appear to move
        (:func:`~framefree.online.smoothing.sensor_smoothing`, over every tracker's takes). A
        library saved before it was learned stays unsmoothed when it is loaded, as its other
        values were learned.
    positions_only : bool
        Whether the takes' orientation is too noisy to use
        (:func:`~framefree.online.noisy_orientation.orientation_unusable`): its noise times
        ``L`` would make a still hand appear to move even after the smoothing of a noisy
        sensor. Then every quaternion of the takes and of the stream is taken as the identity,
        and the recognizer works on the positions alone (v34). A library saved before it was
        learned keeps its orientation (False).
    gate_speeds : (float, float)
        The acceptance gate's fastest plausible speed [m/s] and angular speed [rad/s]: three
        times the takes' fastest speed (their 99th percentile), at least a hand-held tracker's
        5 m/s, and the hand-held 30 rad/s, which catches a hand tracker's palm flips
        (:func:`~framefree.online.acceptance.gate_limits`), so that a whole-arm stroke sampled
        at 30 Hz is not taken for a glitch (v35). A library saved before it was
        learned gets it from its takes when it is loaded (the gate plays no part in the
        calibration).
    provenance : Provenance
        Which rule derived each value, from which takes, in which framefree.
    """

    window_spacing: int | None = None
    rest_speed: float | None = None
    move_speed: float | None = None
    max_units: int | None = None
    max_duration: float | None = None
    max_pause: float | None = None
    pause_ratio: float | None = None
    one_go: list[str] | None = None
    closure_limits: dict[str, float] | None = None
    opening_limits: dict[str, float] | None = None
    size_limits: dict[str, tuple[float, float]] | None = None
    travel_limits: dict[str, float] | None = None
    corner_limits: dict[str, int] | None = None
    proportion_limits: dict[str, list[tuple[float, float]]] | None = None
    forbidden_turns: dict[str, int] | None = None
    vertical_limits: dict[str, tuple[float, float]] | None = None
    direction_limits: dict[str, tuple[float, float, float, float]] | None = None
    rotation_limits: dict[str, tuple[float, float, float, float]] | None = None
    fixed_frame: bool | None = None
    gesture_thresholds: dict[str, float] | None = None
    unseen: list[str] | None = None
    stop_threshold: float | None = None
    continuations: dict[str, float] | None = None
    smoothing: float | None = None
    positions_only: bool | None = None
    gate_speeds: tuple[float, float] | None = None
    provenance: Provenance = field(default_factory=Provenance)

    def __post_init__(self) -> None:
        for name, cast in _CASTS.items():
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, cast(value))
        if isinstance(self.provenance, dict):
            object.__setattr__(self, "provenance", Provenance(**self.provenance))
        if self.max_units is not None and self.max_units < 1:
            raise ValueError(f"max_units must be at least 1, got {self.max_units}")
        if self.window_spacing is not None and self.window_spacing < 1:
            raise ValueError(f"window_spacing must be at least 1, got {self.window_spacing}")
        if self.stop_threshold is not None and not self.stop_threshold > 0:
            raise ValueError(f"stop_threshold must be positive, got {self.stop_threshold}")
        bad = {g: v for g, v in (self.gesture_thresholds or {}).items() if not v > 0}
        if bad:
            raise ValueError(f"gesture thresholds must be positive, got {bad}")

    def values(self) -> dict[str, Any]:
        """The learned values by name (without the provenance)."""
        return {n: getattr(self, n) for n in LEARNED_NAMES}

    def replace(self, **changes: Any) -> LearnedSettings:
        """A copy with some values changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """Values and provenance, JSON-serializable (as a gesture library stores them)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> LearnedSettings:
        """Inverse of :meth:`to_dict`; unknown keys raise ``ValueError`` naming them."""
        unknown = sorted(set(d) - set(LEARNED_NAMES) - {"provenance"})
        if unknown:
            raise ValueError(f"unknown learned values {unknown}")
        return cls(**d)


#: Names of the learned values.
LEARNED_NAMES = tuple(f.name for f in dataclasses.fields(LearnedSettings) if f.name != "provenance")


def split_settings(settings: dict[str, Any], config: RecognizerConfig | None = None
                   ) -> tuple[RecognizerConfig, dict[str, Any]]:
    """Sort flat settings (keyword overrides, ``--set KEY=JSON``) into a configuration and the
    learned values given instead of derived.

    ``gesture_thresholds`` and ``stop_threshold`` are user settings, so they go to the
    configuration; any other learned name (``max_units``, ``closure_limits``, ...) is fixed as
    given; ``None`` for one of those is ignored (it is derived, as by default).

    Parameters
    ----------
    settings : dict
        Names as :meth:`RecognizerConfig.replace` takes them, or learned names.
    config : RecognizerConfig, optional
        The configuration they change (default ``RecognizerConfig()``).

    Returns
    -------
    config : RecognizerConfig
    given : dict
        Learned values to keep as given.

    Raises
    ------
    ValueError
        Naming every setting that is neither a configuration setting nor a learned value.
    """
    config = config or RecognizerConfig()
    names = RecognizerConfig.names() | {"descriptor", "constants"}
    unknown = sorted(set(settings) - names - set(LEARNED_NAMES))
    if unknown:
        raise ValueError(f"unknown recognizer settings {unknown}")
    mine = {k: v for k, v in settings.items() if k in names}
    given = {k: v for k, v in settings.items() if k not in names and v is not None}
    return config.replace(**mine), given


def restored_provenance(resolved: LearnedSettings, stored: LearnedSettings) -> Provenance:
    """The provenance of values restored from ``stored`` (a library's), completed to
    ``resolved``: the stored takes, version and note, every rule of ``resolved``, and a note
    naming the values learned only now (a library older than them)."""
    p = stored.provenance
    fresh = [n for n in resolved.provenance.rules if n not in p.rules]
    note = p.note
    if fresh:
        note = (f"{note}; " if note else "") + (f"{', '.join(fresh)} learned on loading by "
                                                f"framefree {__version__}")
    return dataclasses.replace(p, rules=dict(resolved.provenance.rules), note=note)
