"""What the stroke recognizer measures on the takes and on recorded non-gesture motion.

Every value here comes from data, never from a simulated population:

* **size range** of gesture g: [smallest take / ``size_factor``, largest take × ``size_growth``],
  a take's size being the screw path of its pre-smoothed poses (what the classifier measures on a
  candidate);
* **durations and speed**: a take's *active* time runs from the first to the last moment its
  smoothed speed exceeds a fifth of its peak; candidates last from the shortest active time /
  ``tempo_factor`` to the longest × ``tempo_factor``, and a candidate's peak smoothed speed must
  reach the slowest take's peak / ``tempo_factor`` (a person may be that much slower); the
  longest pause inside a take's active time (speed below a fifth of its peak) × ``tempo_factor``
  is how long a candidate waits for the rest of a longer gesture;
* **threshold** τ_g = P_g^(1−a) · N_g^a (a = ``threshold_position``) between
  P_g, the 90th percentile of the takes' leave-one-out distances (each take classified against the
  other takes of g: how far another performance of g lies), and N_g, the nearest motion that is
  not g: the nearest take of another gesture (the *rival*), or the nearest candidate cut from
  recorded everyday motion whose size fits g (the *everyday* motion: real pouring, scooping and
  free motion shipped with framefree, :func:`everyday_motions`, plus any non-gesture recordings
  the user gives). Where P_g ≥ N_g the gesture is reported as not separated.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import resources

import numpy as np

from ..core.trajectory import Trajectory
from ..errors import FramefreeError, TrajectoryError
from .spotting import SegmentClassifier
from .stroke_config import StrokeConfig
from .valleys import boundaries_of

__all__ = ["StrokeCalibration", "calibrate", "durations", "everyday_motions", "longest_pause",
           "take_sizes", "take_speeds"]

#: Fraction of a take's peak smoothed speed that bounds its active time.
ACTIVE_FRACTION = 0.2


def everyday_motions() -> list[Trajectory]:
    """The real non-gesture recordings shipped with framefree (``framefree/data/everyday``)."""
    folder = resources.files("framefree") / "data" / "everyday"
    out = []
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".csv"):
            with resources.as_file(entry) as path:
                out.append(Trajectory.from_csv(path))
    return out


@dataclass
class StrokeCalibration:
    """The measurements behind the thresholds, per gesture (for reports).

    Attributes
    ----------
    positive, rival, everyday : dict of str to float
        P_g, the nearest take of another gesture, the nearest everyday candidate of a fitting size
        (``inf`` where none fits).
    thresholds : dict of str to float
        τ_g.
    n_everyday : int
        Everyday candidates classified.
    """

    positive: dict[str, float] = field(default_factory=dict)
    rival: dict[str, float] = field(default_factory=dict)
    everyday: dict[str, float] = field(default_factory=dict)
    thresholds: dict[str, float] = field(default_factory=dict)
    n_everyday: int = 0

    @property
    def not_separated(self) -> list[str]:
        """Gestures whose takes spread farther than the nearest non-gesture motion."""
        return [g for g, p in self.positive.items()
                if not p < min(self.rival.get(g, math.inf), self.everyday.get(g, math.inf))]

    def summary(self) -> dict:
        """JSON-friendly."""
        return {"positive": self.positive, "rival": self.rival, "everyday": self.everyday,
                "thresholds": self.thresholds, "n_everyday": self.n_everyday,
                "not_separated": self.not_separated}


def take_sizes(classifier: SegmentClassifier, trajectories: Sequence[Trajectory], dt: float
               ) -> np.ndarray:
    """Size [m] of each take as the classifier measures a candidate (NaN for a take without
    motion)."""
    out = np.full(len(trajectories), np.nan)
    for i, tr in enumerate(trajectories):
        t, poses = tr.uniform_poses(dt)
        described = classifier.describe(t, poses)
        if described is not None:
            out[i] = described[1]
    return out


def take_speeds(trajectories: Sequence[Trajectory], c: StrokeConfig) -> list[np.ndarray]:
    """The smoothed motion speed [m/s] of each take on the uniform grid, as the boundary detector
    measures it (empty for a take too short to measure)."""
    out = []
    for tr in trajectories:
        try:
            _, poses = tr.uniform_poses(c.dt)
        except TrajectoryError:
            out.append(np.zeros(0))
            continue
        out.append(boundaries_of(poses, c.L, c.dt, sigma=c.smoothing)[1])
    return out


def longest_pause(speeds: Sequence[np.ndarray], c: StrokeConfig) -> float:
    """Longest pause [s] inside a take's active time (smoothed speed below a fifth of its peak),
    × ``tempo_factor``, and at least ``wait``."""
    longest = 0.0
    for v in speeds:
        if not (v.size and v.max() > 0):
            continue
        slow = v < ACTIVE_FRACTION * v.max()
        fast = np.flatnonzero(~slow)
        run = best = 0
        for k in range(fast[0], fast[-1] + 1):
            run = run + 1 if slow[k] else 0
            best = max(best, run)
        longest = max(longest, best * c.dt)
    return max(c.wait, longest * c.tempo_factor)


def durations(speeds: Sequence[np.ndarray], c: StrokeConfig) -> tuple[float, float]:
    """Shortest and longest candidate [s] from the takes' smoothed speeds (module docstring)."""
    active = []
    for v in speeds:
        if v.size and v.max() > 0:
            fast = np.flatnonzero(v > ACTIVE_FRACTION * v.max())
            active.append((fast[-1] - fast[0]) * c.dt)
    active = np.array([a for a in active if a > 0])
    if active.size == 0:
        raise FramefreeError("no movement found in the model recordings: every take is still")
    return max(10 * c.dt, float(active.min()) / c.tempo_factor), float(active.max()) * c.tempo_factor


def _everyday_distances(classifier: SegmentClassifier, recordings: Sequence[Trajectory],
                        labels: Sequence[str], c: StrokeConfig) -> tuple[dict[str, float], int]:
    """Nearest distance to each gesture of any candidate (as the spotter cuts them) of the
    everyday recordings whose size and peak speed fit that gesture; and the number of
    candidates."""
    labels_arr = np.asarray(labels)
    nearest = dict.fromkeys(c.size_limits, math.inf)
    n = 0
    for tr in recordings:
        try:
            t, poses = tr.uniform_poses(c.dt)
        except TrajectoryError:
            continue
        bounds, speeds = boundaries_of(poses, c.L, c.dt, sigma=c.smoothing)
        for i, (a, _) in enumerate(bounds):
            for b, _ in bounds[i + 1:]:
                span = (b - a) * c.dt
                if span > c.max_duration:
                    break
                if span < c.min_duration:
                    continue
                cut = slice(max(0, a - 5), b + 6)
                described = classifier.describe(t[cut], poses[cut])
                if described is None:
                    continue
                n += 1
                desc, size = described
                peak = float(speeds[a:b + 1].max())
                d = classifier.descriptor.distance_matrix([desc], classifier.models)[0]
                for g, (s_lo, s_hi) in c.size_limits.items():
                    if s_lo <= size <= s_hi and peak >= c.min_speeds[g]:
                        nearest[g] = min(nearest[g], float(d[labels_arr == g].min()))
    return nearest, n


def calibrate(classifier: SegmentClassifier, trajectories: Sequence[Trajectory],
              labels: Sequence[str], c: StrokeConfig,
              everyday: Sequence[Trajectory] | None = None) -> tuple[StrokeConfig, StrokeCalibration]:
    """Fill the configuration's ``None`` fields from the takes (and the everyday recordings: the
    shipped ones when ``everyday`` is ``None``)."""
    labels_arr = np.asarray([str(s) for s in labels])
    gestures = list(dict.fromkeys(labels_arr))
    if c.size_limits is None:
        sizes = take_sizes(classifier, trajectories, c.dt)
        limits = {}
        for g in gestures:
            s = sizes[labels_arr == g]
            s = s[np.isfinite(s)]
            if s.size == 0:
                raise FramefreeError(f"no movement found in the model recordings of {g!r}")
            limits[g] = (float(s.min()) / c.size_factor, float(s.max()) * c.size_growth)
        c = c.replace(size_limits=limits)
    if None in (c.min_duration, c.max_duration, c.min_speeds, c.max_pause):
        speeds = take_speeds(trajectories, c)
        if c.max_pause is None:
            c = c.replace(max_pause=longest_pause(speeds, c))
        lo, hi = durations(speeds, c)
        c = c.replace(min_duration=c.min_duration or lo, max_duration=c.max_duration or hi)
        if c.min_speeds is None:
            peaks = np.array([v.max() if v.size else np.nan for v in speeds])
            c = c.replace(min_speeds={g: float(np.nanmin(peaks[labels_arr == g])) / c.tempo_factor
                                      for g in gestures})
    cal = StrokeCalibration()
    if c.gesture_thresholds is not None:
        return c, cal
    D = classifier.descriptor.distance_matrix(classifier.models, classifier.models)
    np.fill_diagonal(D, np.inf)
    recordings = everyday_motions() if everyday is None else list(everyday)
    cal.everyday, cal.n_everyday = _everyday_distances(classifier, recordings, labels_arr, c)
    loo_all = []
    for g in gestures:
        own = labels_arr == g
        loo = D[np.ix_(own, own)].min(axis=1)
        loo = loo[np.isfinite(loo)]
        cal.positive[g] = float(np.percentile(loo, 90)) if loo.size else math.nan
        loo_all.extend(loo)
        cal.rival[g] = float(D[np.ix_(own, ~own)].min()) if (~own).any() else math.inf
    fallback = float(np.percentile(loo_all, 90)) if loo_all else math.nan
    for g in gestures:
        P = cal.positive[g] if math.isfinite(cal.positive[g]) else fallback
        N = min(cal.rival[g], cal.everyday[g])
        if not math.isfinite(N):
            N = 2.0 * P
        if not math.isfinite(P):
            P = 0.5 * N
        a = c.threshold_position
        cal.thresholds[g] = float(P ** (1 - a) * N ** a)
    return c.replace(gesture_thresholds=dict(cal.thresholds)), cal
