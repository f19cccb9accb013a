"""The rest and move levels of the live segmenter, learned from the model recordings.

A unit of motion starts when the motion speed (:func:`~framefree.online.segmentation.motion_speed`)
rises above the *move* level and ends when it falls below the *rest* level. Both come from the
takes (:func:`speed_levels`): ``noise_factor`` times the noise floor of their rests, bounded by
the peak speed of their strokes. Takes cut where the motion starts and ends, as a benchmark's
segmented examples are, have no rest to measure (:func:`restless_takes`); their level is taken
from the speed at which they start or end (:func:`rest_level`).

See ``docs/online.md`` (What it learns from the takes; Models cut without rests).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import numpy as np

from ..core.trajectory import Trajectory
from .segmentation import SpeedLevels, motion_speed

__all__ = [
    "GOING_SOMEWHERE",
    "end_speed",
    "going_somewhere",
    "holds_no_rest",
    "rest_level",
    "restless_takes",
    "slowest_stretch",
    "speed_levels",
    "take_motion",
    "take_speeds",
]


def take_speeds(trajectories: Sequence[Trajectory], L: float, dt: float = 0.02, lag: int = 5
                ) -> Iterator[np.ndarray]:
    """Each recording's motion speed [m/s] on the uniform grid, as :func:`take_motion` gives it
    (without the positions): what :func:`speed_levels` measures."""
    for v, _ in take_motion(trajectories, L, dt, lag):
        yield v


def take_motion(trajectories: Sequence[Trajectory], L: float, dt: float = 0.02, lag: int = 5
                ) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Each recording's motion speed (n - lag,) [m/s] on the uniform grid
    (:func:`~framefree.online.segmentation.motion_speed`, without the first ``lag`` samples that
    have none), with its positions (n, 1, 3) [m] on the same grid (the speed's sample ``k`` ends
    at position ``k + lag``)."""
    for tr in trajectories:
        _, poses = tr.uniform_poses(dt)
        yield motion_speed(poses, dt, L, lag)[lag:], poses[:, None, :3, 3]


#: Net displacement over path length above which an end of a recording *goes somewhere*: a hand
#: that holds still jitters about one point (the replica's noisy rests: 0.05–0.34 over 0.2 s),
#: a hand in motion heads one way (Machete recordings cut at 5 % of their peak: 0.94 at the
#: median).
GOING_SOMEWHERE = 0.5


def going_somewhere(positions: np.ndarray) -> float:
    """How straight a stretch of positions (m, k, 3) [m] of ``k`` trackers heads one way: the sum of
    their net displacements over the sum of their path lengths (0 for no motion)."""
    path = float(np.linalg.norm(np.diff(positions, axis=0), axis=2).sum())
    net = float(np.linalg.norm(positions[-1] - positions[0], axis=1).sum())
    return net / path if path > 0 else 0.0


def end_speed(v: np.ndarray, lag: int) -> float:
    """The slower of a recording's mean motion speeds [m/s] over its first and its last ``lag``
    samples of speed ``v`` (n,): where a recording cut from a stream starts or ends."""
    return min(float(v[:lag].mean()), float(v[-lag:].mean()))


def holds_no_rest(v: np.ndarray, positions: np.ndarray, lag: int, share: float = 0.05) -> bool:
    """Whether a recording holds no rest at either end: over both its first and its last ``lag``
    samples of motion speed ``v`` (n - lag,) [m/s] the hand moves faster than ``share`` × its peak
    (:func:`end_speed`), and over the positions (n, k, 3) of those stretches it heads one way
    (:data:`GOING_SOMEWHERE`). A hand at rest is slower than ``share`` of the gesture or, where a
    sensor's noise makes it seem faster, goes nowhere. A recording too short to tell, or with a
    gap, rests."""
    if v.size < 2 * lag or not np.isfinite(v).all():
        return False
    if end_speed(v, lag) <= share * float(v.max()):
        return False
    n = 2 * lag + 1
    return min(going_somewhere(positions[:n]), going_somewhere(positions[-n:])) > GOING_SOMEWHERE


def slowest_stretch(v: np.ndarray, samples: int) -> float:
    """The slowest mean motion speed [m/s] over ``samples`` consecutive samples of ``v`` (n,)
    inside a recording's motion: between the first and the last sample faster than half its
    peak, where the ends of a recording cut in mid-motion take no part (the mean of that stretch
    where it is shorter)."""
    fast = np.flatnonzero(v > 0.5 * float(v.max()))
    inside = v[fast[0]:fast[-1] + 1]
    if inside.size <= samples:
        return float(inside.mean())
    return float(np.convolve(inside, np.full(samples, 1.0 / samples), "valid").min())


#: Share of the takes whose slowest stretch may lie below the rest level of takes cut in
#: mid-motion (:func:`rest_level`): the 10th percentile, as the noise floor is a recording's.
SLOW_TAKES = 10.0


def rest_level(motions: Sequence[tuple[np.ndarray, np.ndarray]], lag: int = 5,
               noise_factor: float = 3.0, peak_fraction: float = 0.05,
               rest_samples: int = 10) -> float:
    """The rest level [m/s] of model recordings from their motion (speed (n - lag,), non-empty,
    and positions (n, k, 3), as :func:`take_motion` gives them).

    ``noise_factor`` times the median noise floor (the 10th percentile of a recording's speed),
    the floor counting at most ``peak_fraction`` × the median peak: a rest is slower than that
    (session 29). Where most recordings hold no rest (:func:`holds_no_rest`: a benchmark's
    examples cut where the motion starts and ends), they have no floor to measure:

    * where they start or end slower than that level, the level is the median speed at which
      they do (:func:`end_speed`, session 30): where the cut was made, the hand left its rest.
      The Machete right controller's takes cut at 5 % of their peak speed get 0.27 m/s (all
      eleven gestures; 0.21 as recorded), SFINGE3D's dictionary cut the same way 0.094 (0.098 as
      recorded);
    * where they start or end faster (cut in mid-motion: the Machete takes cut at 10 % start at
      0.8 m/s, above the level of 0.55), the level is at most the slowest the hand moves for a
      rest's length (``rest_samples``) inside the recordings' motion (:func:`slowest_stretch`),
      the 10th percentile over the recordings (:data:`SLOW_TAKES`; v37). A rest so long inside a
      gesture would end its unit, and the part after it would start a candidate of its own:
      the top of a golf swing, whose second half was taken for a cartwheel. The Machete takes cut
      at 10 % or 20 % get 0.19–0.37 m/s instead of 0.54–0.58.

    Either way at least ``peak_fraction`` × the smallest peak, so that a noiseless recording
    still separates strokes.
    """
    peaks = [float(v.max()) for v, _ in motions]
    floor = min(float(np.median([np.percentile(v, 10) for v, _ in motions])),
                peak_fraction * float(np.median(peaks)))
    rest = noise_factor * floor
    restless = [end_speed(v, lag) for v, p in motions if holds_no_rest(v, p, lag, peak_fraction)]
    if 2 * len(restless) > len(motions):
        start = float(np.median(restless))
        if start < rest:
            rest = start
        else:
            slowest = [slowest_stretch(v, rest_samples) for v, _ in motions]
            rest = min(rest, float(np.percentile(slowest, SLOW_TAKES)))
    return max(rest, peak_fraction * min(peaks))


def speed_levels(
    trajectories: Sequence[Trajectory],
    L: float,
    dt: float = 0.02,
    lag: int = 5,
    noise_factor: float = 3.0,
    peak_fraction: float = 0.05,
    move_factor: float = 1.5,
    rest_before: float = 0.2,
) -> SpeedLevels:
    """Rest and move levels from model recordings (each a gesture, usually between rests).

    The noise floor of a recording is the 10th percentile of its motion speed (its rests make up
    well over a tenth of it); the rest level is ``noise_factor`` × the median floor of the
    recordings, but at least ``peak_fraction`` × the smallest stroke peak of any recording so that
    a noiseless recording still separates strokes; the move level is ``move_factor`` × the rest
    level (the hysteresis that keeps noise around the rest level from starting units).

    The median, not the largest floor (before v17): a recording cut without a rest has no noise
    floor, only its slowest motion, and on real data one such take put the rest level above
    every take's peak speed (SFINGE3D's swipes: 0.58 m/s from the largest floor, 0.10 m/s from
    the median; docs/online-history.md, *v17*). Where most takes are cut without a rest, even the
    median floor may put the move level near the takes' peaks; the move level is then at most half
    the median take's peak, so the typical take starts a unit. Not the slowest take's peak, nor
    a low percentile: in a recording of two trackers one may hardly move (real Vive takes: 0.11
    m/s, against 3.3 at the median), and leaving one person out of the Vive models put the 10th
    percentile low enough to pull the rest level from 0.2 to 0.09 m/s, which cut real gestures
    into pieces.

    Where most takes hold no rest (:func:`restless_takes`: a benchmark's segmented examples),
    they have no noise floor to measure, and the rest level is at most the speed at which they
    start or end or, where that is faster, the slowest the hand moves for ``rest_before``
    seconds inside them (:func:`rest_level`).

    Parameters
    ----------
    trajectories : sequence of Trajectory
        Model recordings.
    L : float
        Scale length of the screw path [m].
    dt : float
        Grid step [s].
    rest_before : float
        How long [s] the hand rests before a candidate that starts after a full rest.
    """
    motions = [(v, p) for v, p in take_motion(trajectories, L, dt, lag) if v.size]
    if not motions:
        raise ValueError("no model recording is long enough to measure its motion speed")
    rest = rest_level(motions, lag, noise_factor, peak_fraction, max(1, round(rest_before / dt)))
    typical_peak = float(np.median([v.max() for v, _ in motions]))
    if move_factor * rest > 0.5 * typical_peak:  # most takes cut without a rest: the typical take
        rest = 0.5 * typical_peak / move_factor  # must reach twice the move level to start a unit
    return SpeedLevels(rest=rest, move=move_factor * rest)


def restless_takes(
    trajectories: Sequence[Trajectory], L: float, dt: float = 0.02, lag: int = 5,
    share: float = 0.05,
) -> np.ndarray:
    """Which model recordings hold no rest (N,) bool (:func:`holds_no_rest`): at both ends the
    hand moves faster than ``share`` × the recording's peak motion speed and heads one way.

    :func:`speed_levels` measures the noise floor where the takes hold still; a recording cut
    where the motion starts and ends (a benchmark's segmented example) has only its slowest
    motion. Restless: 75 % of the Machete right controller's recordings cut at 5 % of their peak
    speed, 98 % cut at 20 %, 15 % as recorded; SFINGE3D's swipes 30 %; none of the replica's
    takes in any context, whose noise makes a resting hand seem to move at up to a seventh of
    its peak speed (docs/online-history.md, *Session 30*).
    """
    return np.array([holds_no_rest(v, p, lag, share)
                     for v, p in take_motion(trajectories, L, dt, lag)], dtype=bool)
