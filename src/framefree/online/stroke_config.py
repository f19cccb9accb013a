"""What a user may set on the stroke recognizer (:class:`~framefree.online.StrokeRecognizer`).

Twenty-three fields: the classifier's descriptor (as offline), the time scales of the boundary detector,
how long a candidate waits, how differently from the takes a person may perform (sizes and
tempo), where the thresholds sit between the takes and non-gesture motion, and the stop signal.
The eight fields that default to ``None`` are measured on the takes when the recognizer is built
(:mod:`~framefree.online.stroke_calibration`) and kept with a gesture library, so a library
restores without recalibrating. See ``docs/online.md``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from ..descriptors.bilts import ALIGNMENTS

__all__ = ["StrokeConfig"]


@dataclass(frozen=True)
class StrokeConfig:
    """Settings of the stroke recognizer.

    Attributes
    ----------
    L : float
        Scale length [m] of the screw path: the classifier's progress and descriptor, and the
        motion speed (0.1).
    ds_scale, presmooth, axis_prior, align, n_samples : float, int, float, str, int
        The classifier's BILTS+ settings, as the recommended offline classifier (0.06 m, 5 samples,
        1.0, ``"gram"``, 50).
    window_spacing : int or None
        BILTS+ window spacing [samples]; ``None``: from the takes (``ds_scale`` over their median
        progress step).
    dt : float
        Step of the uniform grid [s] (0.02: the offline classifier's 50 Hz).
    smoothing : float
        Standard deviation [s] of the Gaussian that smooths the motion speed before its minima are
        taken as boundaries (0.1).
    wait : float
        Seconds an accepted candidate waits, after its end became known, for a better overlapping
        one (0.3).
    size_factor, size_growth : float
        A person may perform a gesture ``size_factor`` times smaller (1.5) or ``size_growth`` times
        larger (2.5) than the smallest and largest take.
    tempo_factor : float
        ... and ``tempo_factor`` times faster or slower than the quickest and slowest take (2).
    threshold_position : float
        Where τ_g lies between the takes' spread P_g and the nearest non-gesture motion N_g:
        ``P_g^(1−a) · N_g^a`` (0.7).
    gesture_thresholds : dict of str to float or None
        τ_g per gesture; ``None``: calibrated on the takes and the non-gesture recordings.
    size_limits : dict of str to (float, float) or None
        Size range [m] per gesture; ``None``: from the takes with ``size_factor``/``size_growth``.
    min_duration, max_duration : float or None
        Shortest and longest candidate [s]; ``None``: from the takes' active durations with
        ``tempo_factor``.
    min_speeds : dict of str to float or None
        Lowest peak speed [m/s] of a candidate per gesture; ``None``: the slowest take's peak
        smoothed speed / ``tempo_factor``.
    max_pause : float or None
        Longest pause [s] inside a gesture; ``None``: the longest pause inside a take's active time
        × ``tempo_factor``, at least ``wait``.
    stop_threshold : float or None
        Angular speed [rad/s] of the stop signal; ``None``: ``stop_margin`` × the fastest sustained
        rotation of any take, at least 3 rad/s.
    stop_margin : float
        (1.3).
    max_bridge : float
        Longest dropout [s] bridged by interpolation; longer gaps restart the stream (0.5).
    """

    L: float = 0.1
    ds_scale: float = 0.06
    presmooth: int = 5
    axis_prior: float = 1.0
    align: str = "gram"
    n_samples: int = 50
    window_spacing: int | None = None
    dt: float = 0.02
    smoothing: float = 0.1
    wait: float = 0.3
    size_factor: float = 1.5
    size_growth: float = 2.5
    tempo_factor: float = 2.0
    threshold_position: float = 0.7
    gesture_thresholds: dict[str, float] | None = None
    size_limits: dict[str, tuple[float, float]] | None = None
    min_duration: float | None = None
    max_duration: float | None = None
    min_speeds: dict[str, float] | None = None
    max_pause: float | None = None
    stop_threshold: float | None = None
    stop_margin: float = 1.3
    max_bridge: float = 0.5

    def __post_init__(self) -> None:
        for name in ("L", "ds_scale", "dt", "smoothing", "size_factor", "size_growth",
                     "tempo_factor", "stop_margin", "max_bridge"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if self.wait < 0:
            raise ValueError(f"wait must not be negative, got {self.wait}")
        if self.presmooth < 1 or self.n_samples < 5:
            raise ValueError("presmooth must be at least 1 and n_samples at least 5")
        if not 0 <= self.threshold_position <= 1:
            raise ValueError(f"threshold_position must be in [0, 1], got {self.threshold_position}")
        if self.align not in ALIGNMENTS:
            raise ValueError(f"align must be one of {', '.join(ALIGNMENTS)}, got {self.align!r}")
        if self.window_spacing is not None and not self.window_spacing >= 1:
            raise ValueError(f"window_spacing must be at least 1, got {self.window_spacing}")
        for name in ("min_duration", "max_duration", "max_pause", "stop_threshold"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise ValueError(f"{name} must be positive, got {value}")
        if self.gesture_thresholds is not None:
            bad = {g: v for g, v in self.gesture_thresholds.items() if not float(v) > 0}
            if bad:
                raise ValueError(f"gesture thresholds must be positive, got {bad}")
            object.__setattr__(self, "gesture_thresholds",
                               {str(g): float(v) for g, v in self.gesture_thresholds.items()})
        if self.min_speeds is not None:
            object.__setattr__(self, "min_speeds", {str(g): float(v) for g, v in self.min_speeds.items()})
        if self.size_limits is not None:
            object.__setattr__(self, "size_limits", {str(g): (float(v[0]), float(v[1]))
                                                     for g, v in self.size_limits.items()})

    def replace(self, **changes: Any) -> StrokeConfig:
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """All fields as a JSON-serializable dict."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> StrokeConfig:
        """Inverse of :meth:`to_dict`; unknown keys raise ``ValueError`` naming them."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = set(d) - names
        if unknown:
            raise ValueError(f"unknown recognizer settings {sorted(unknown)}")
        return cls(**d)
