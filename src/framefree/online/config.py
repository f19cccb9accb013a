"""What a user sets on framefree's live recognizer (segment spotting), in one frozen dataclass.

A recognizer's settings come from three places, each with its own home:

* :class:`RecognizerConfig` (here): the few choices a user makes — the vertical, stricter or
  looser thresholds, how long a gesture waits for a rest, which shape rules apply;
* :class:`~framefree.online.learned.LearnedSettings`: every value measured on the takes when the
  recognizer is built (speed levels, candidate limits, shape limits, thresholds), each with the
  rule that derived it; a gesture library file stores them, so loading it calibrates nothing;
* :class:`~framefree.online.constants.DescriptorSettings` and
  :class:`~framefree.online.constants.SpottingConstants`: the descriptor's design and facts about
  people in general, reached through this configuration's ``descriptor`` and ``constants``.

:meth:`RecognizerConfig.replace` and :meth:`RecognizerConfig.from_dict` also take the name of
any descriptor setting or constant (``replace(ds_scale=0.09)``), so ``--set KEY=JSON`` reaches
every one of them. See ``docs/online.md`` (What you may set).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from .constants import DescriptorSettings, SpottingConstants
from .vertical import up_vector

__all__ = ["DescriptorSettings", "RecognizerConfig", "SpottingConstants"]

#: Names of the two nested groups of a configuration.
GROUPS = {"descriptor": DescriptorSettings, "constants": SpottingConstants}


@dataclass(frozen=True)
class RecognizerConfig:
    """The live recognizer's user settings.

    Parameters
    ----------
    up : {"+x", "-x", "+y", "-y", "+z", "-z"} or None
        The axis of the tracking system's world that points up, or None: no vertical is known
        and nothing depends on one (default). When set, a candidate must move about as
        vertically as its gesture's takes, so a Z is no N; a world tilted against this axis
        then breaks recognition.
    hand_frame : bool
        Whether the way the hand moves and turns in the tracker's frame counts as evidence
        (default True). A gesture whose takes move the same way in that frame (many takes that
        agree more than random directions would: a dictionary of many people's examples, not
        one person's five takes) learns a cone of directions, and one whose takes turn the hand
        about the same axis a cone of axes (v29); a candidate outside either must match
        ``OFF_CONE_FACTOR`` (1.5) times more closely to be taken for it
        (:mod:`framefree.online.hand_direction`). It pays where the tracker's frame sits on
        every hand about the same way (a hand tracker's palm, a controller held by its
        handle); a tracker turned in the hand since the takes costs only the performances near
        their threshold. Takes whose tracker never turns (a sensor of positions only) have the
        sensor's own frame, which the stream shares while the sensor stays where it stood: a
        candidate outside a cone of theirs is refused (v33). False: nothing depends on how the
        tracker sits in the hand, nor on where a sensor of positions only stands (for one moved
        since the takes). One tracker only: the recognizer of several trackers does not use it.
    threshold : float or None
        One decision threshold τ for every gesture, > 0 [DTW distance]; None: each gesture's is
        calibrated on the takes.
    gesture_thresholds : dict of str to float or None
        τ_g of every gesture, > 0 (None: calibrated); then no calibration runs.
    stop_threshold : float or None
        The stop signal's angular speed [rad/s], > 0; None: from the takes (the fastest rotation
        of any take, with a margin).
    confirm : float
        Rest [s] after a candidate before it fires, >= 0 (0.2): shorter reacts sooner, longer
        waits for a longer gesture that may contain it.
    max_wait : float
        Latest firing time [s] after a candidate's end, > 0 (1.0), when the hand does not rest.
    closure, size, corners, turns, gesture_pauses : bool
        Each shape rule on or off: a candidate must come back to its start as its gesture's
        takes do (closure and opening limits, True); lie within their size range (True); have
        no more corners than they agree on, keep the proportions of its two strokes where they
        agree on one, and not turn the same way at two corners where they always turn back, as
        a Z does (True); not turn back where they always turn the same way, as a triangle does
        (``turns``, False: real people's swings break it); and, for a gesture the takes draw in
        one go, not rest at a corner (True).
    max_bridge : float
        Longest dropout [s] of the tracker bridged by interpolation instead of restarting, > 0
        (0.5).
    smoothing : float or None
        Standard deviation [s] of a centred Gaussian that smooths the takes and the stream alike,
        >= 0 (0: none), or None: decided from the takes (default). A noisy sensor, such as a
        skeleton tracker's wrist joint, is then smoothed by ``noisy_smoothing`` (0.067 s), which
        gave back on 1-2 cm of noise what the noise had cost, and a precise one not at all
        (:mod:`framefree.online.smoothing`). A smoothed stream reaches the recognizer three
        standard deviations late. Several trackers are smoothed alike.
    descriptor : DescriptorSettings
        How motions are described and compared (scale length ``L``, window, smoothing).
    constants : SpottingConstants
        Constants about people and the spotter's design.
    """

    up: str | None = None
    hand_frame: bool = True
    threshold: float | None = None
    gesture_thresholds: dict[str, float] | None = None
    stop_threshold: float | None = None
    confirm: float = 0.2
    max_wait: float = 1.0
    closure: bool = True
    size: bool = True
    corners: bool = True
    turns: bool = False
    gesture_pauses: bool = True
    max_bridge: float = 0.5
    smoothing: float | None = None
    descriptor: DescriptorSettings = field(default_factory=DescriptorSettings)
    constants: SpottingConstants = field(default_factory=SpottingConstants)

    def __post_init__(self) -> None:
        for name in ("max_bridge", "max_wait"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if self.confirm < 0:
            raise ValueError(f"confirm must not be negative, got {self.confirm}")
        if self.smoothing is not None and not (self.smoothing >= 0
                                               and math.isfinite(self.smoothing)):
            raise ValueError(f"smoothing must be a finite number >= 0, got {self.smoothing}")
        for name in ("threshold", "stop_threshold"):
            if getattr(self, name) is not None and not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if self.up is not None:
            up_vector(self.up)  # names the axes it accepts
        if self.gesture_thresholds is not None:
            bad = {g: v for g, v in self.gesture_thresholds.items() if not float(v) > 0}
            if bad:
                raise ValueError(f"gesture thresholds must be positive, got {bad}")
            object.__setattr__(self, "gesture_thresholds",
                               {str(g): float(v) for g, v in self.gesture_thresholds.items()})
        for name, kind in GROUPS.items():
            value = getattr(self, name)
            if isinstance(value, dict):
                object.__setattr__(self, name, kind(**value))
            elif not isinstance(value, kind):
                raise TypeError(f"{name} must be a {kind.__name__}, got {type(value).__name__}")

    @classmethod
    def user_names(cls) -> tuple[str, ...]:
        """The names of the user settings (every field but the two nested groups)."""
        return tuple(f.name for f in dataclasses.fields(cls) if f.name not in GROUPS)

    @classmethod
    def names(cls) -> frozenset[str]:
        """Every name :meth:`replace` accepts: user settings, descriptor settings, constants."""
        out = set(cls.user_names())
        for kind in GROUPS.values():
            out.update(kind.names())
        return frozenset(out)

    def replace(self, **changes: Any) -> RecognizerConfig:
        """A copy with some settings changed.

        A name may be a user setting, a descriptor setting (``L``, ``ds_scale``, ...), a
        constant (``size_factor``, ...) or one of the groups (``descriptor=...``).

        Raises
        ------
        ValueError
            For a name that is none of these (learned values are given to
            :meth:`Recognizer.from_trajectories <framefree.online.Recognizer.from_trajectories>`
            instead; its message says so).
        """
        unknown = sorted(set(changes) - self.names() - set(GROUPS))
        if unknown:
            raise ValueError(f"unknown recognizer settings {unknown}")
        own = {k: v for k, v in changes.items() if k in self.user_names() or k in GROUPS}
        for name, kind in GROUPS.items():
            group = own.get(name, getattr(self, name))
            group = kind(**group) if isinstance(group, dict) else group
            mine = {k: v for k, v in changes.items() if k in kind.names()}
            if mine:
                own[name] = group.replace(**mine)
        return dataclasses.replace(self, **own)

    def to_dict(self) -> dict[str, Any]:
        """Every setting as a JSON-serializable dict (the groups nested under their names)."""
        return dataclasses.asdict(self)

    def flat(self) -> dict[str, Any]:
        """Every setting in one flat dict (user settings, descriptor settings, constants)."""
        d = {n: getattr(self, n) for n in self.user_names()}
        for name in GROUPS:
            d.update(getattr(self, name).to_dict())
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RecognizerConfig:
        """Inverse of :meth:`to_dict`; flat names (as :meth:`replace` takes) are accepted too.

        Raises
        ------
        ValueError
            Naming every unknown key.
        """
        return cls().replace(**d)
