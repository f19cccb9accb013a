"""Cutting one long recording into takes of a gesture, at the rests between them.

A person records a new gesture by performing it several times in one go, resting briefly between
performances. The rests are found with a motion speed that does not depend on where the tracker's
world frame is or how the tracker sits in the hand: the screw-path rate (:mod:`framefree.core.progress`)
of the lightly smoothed poses, in metres per second (rotation weighted by the scale length ``L``).

The rest level is derived from the recording itself: its noise floor (a low quantile of the speed:
the hand resting with the tracker's jitter) and its peak speed (a high quantile), placed between
the two on a log scale. A *rest* is a stretch below that level lasting at least ``min_rest``
seconds (a twitch in its middle, too brief and too small to be a take, does not break it);
everything between two rests is a take. Its motion onset and end are found by going
outwards from where the speed crossed the rest level to where it falls to twice the noise floor.
Each take is trimmed to them, keeping ``margin`` seconds of rest on both sides (as in the HPM
recordings, which start and end with the hand still), and dropped when it is too short or too
small to be a gesture (a twitch).
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core import se3
from ..core.progress import progress_increments
from ..core.smoothing import smooth_poses
from ..core.trajectory import MIN_SAMPLES, Trajectory
from ..errors import FramefreeError

__all__ = [
    "TakeSettings",
    "TakeSpan",
    "cut_take",
    "find_takes",
    "join_recordings",
    "motion_speed",
    "rest_level",
    "split_takes",
    "takes_from_speed",
    "write_take",
]

#: Sample period of the speed signal [s] (poses are resampled by ScLERP on this grid).
SPEED_PERIOD = 0.02


@dataclass(frozen=True)
class TakeSettings:
    """How a recording is cut into takes.

    Attributes
    ----------
    L : float
        Scale length [m] of the screw path (rotation weight), as the recognizer's.
    smoothing : float
        Width [s] of the Gaussian smoothing of the poses before the speed is taken.
    min_rest : float
        Shortest rest [s] that separates two takes. Longer than the pauses inside a gesture
        (out-and-back gestures stop for 0.1–0.4 s at their turning point).
    margin : float
        Rest [s] kept before the motion onset and after its end.
    level : float
        Where the rest level lies between the noise floor ``n`` and the peak speed ``P``:
        ``n^(1-level) · P^level``.
    noise_quantile, peak_quantile : float
        Quantiles of the speed taken as noise floor and as peak speed.
    min_duration : float
        Shortest take [s] (motion part, without the margins).
    min_path : float
        Smallest screw path [m] of a take (smaller motions are twitches, not gestures).
    onset_factor : float
        The motion onset and end are where the speed falls to ``onset_factor`` × the noise floor
        (going outwards from where it crossed the rest level), so that the kept margin is rest.
    """

    L: float = 0.2
    smoothing: float = 0.3
    min_rest: float = 0.9
    margin: float = 0.75
    level: float = 0.4
    noise_quantile: float = 0.1
    peak_quantile: float = 0.99
    min_duration: float = 0.3
    min_path: float = 0.03
    onset_factor: float = 2.0

    def __post_init__(self) -> None:
        for name in ("L", "smoothing", "min_rest", "min_duration"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if not self.margin >= 0:
            raise ValueError(f"margin must be >= 0, got {self.margin}")
        if not 0 < self.level < 1:
            raise ValueError(f"level must be in (0, 1), got {self.level}")
        if not 0 <= self.noise_quantile < self.peak_quantile <= 1:
            raise ValueError("need 0 <= noise_quantile < peak_quantile <= 1")


@dataclass(frozen=True)
class TakeSpan:
    """Where one take lies in a recording (times in the recording's clock) [s].

    Attributes
    ----------
    onset, end : float
        First and last moment of the motion (speed above the rest level).
    start, stop : float
        The trimmed take: ``onset - margin`` and ``end + margin``, kept within the rests around it.
    peak_speed : float
        Largest screw-path rate during the take [m/s].
    path : float
        Screw path of the motion [m].
    """

    onset: float
    end: float
    start: float
    stop: float
    peak_speed: float
    path: float

    @property
    def duration(self) -> float:
        """Motion duration ``end - onset`` [s]."""
        return self.end - self.onset


def motion_speed(traj: Trajectory, L: float = 0.2, smoothing: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    """Screw-path rate of the smoothed poses: a frame-free motion speed.

    Parameters
    ----------
    traj : Trajectory
        The recording.
    L : float
        Scale length [m] of the screw path.
    smoothing : float
        Gaussian smoothing width [s] applied to the poses (resampled every
        :data:`SPEED_PERIOD` seconds by ScLERP first).

    Returns
    -------
    t : ndarray, shape (K,)
        Times [s] (the recording's clock) of the speed samples.
    speed : ndarray, shape (K,)
        Screw-path rate [m/s] (rotation contributes ``L`` × angular speed).
    """
    if traj.duration < MIN_SAMPLES * SPEED_PERIOD:
        raise FramefreeError(f"{traj.source or 'recording'}: {traj.duration:.2f} s is too short "
                             "to find takes")
    tq, T = traj.uniform_poses(SPEED_PERIOD)
    window = max(1, round(smoothing / SPEED_PERIOD))
    if window > 1:
        T = smooth_poses(T, window)
    inc = progress_increments(T, "screw", L) / np.diff(tq)
    speed = np.empty(tq.size)
    speed[0], speed[-1] = inc[0], inc[-1]
    speed[1:-1] = 0.5 * (inc[:-1] + inc[1:])
    return traj.t[0] + tq, speed


def rest_level(speed: np.ndarray, settings: TakeSettings) -> tuple[float, float, float]:
    """Noise floor, peak speed and rest level [m/s] of a speed signal (see the module docstring)."""
    peak = float(np.quantile(speed, settings.peak_quantile))
    noise = max(float(np.quantile(speed, settings.noise_quantile)), 1e-3 * peak, 1e-9)
    level = noise ** (1.0 - settings.level) * peak**settings.level
    return noise, peak, level


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Half-open index ranges ``[a, b)`` of the True runs of a boolean array."""
    padded = np.concatenate([[False], mask, [False]]).astype(np.int8)
    edges = np.flatnonzero(np.diff(padded))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _twitches_at_rest(t: np.ndarray, v: np.ndarray, moving: np.ndarray, s: TakeSettings
                      ) -> np.ndarray:
    """``moving`` (K,) bool with every twitch counted as rest: a motion too brief and too small
    to be a take (a fidget, a tracker's glitch) between two rests that are each shorter than
    ``min_rest``. Left as motion, it would make both rests too short and join the takes around
    them; a twitch next to a full rest (the slow start of a take) stays motion."""
    out = moving.copy()
    for (a0, b0), (a1, b1) in itertools.pairwise(_runs(~moving)):
        brief = t[a1 - 1] - t[b0] < s.min_duration and np.sum(v[b0:a1]) * SPEED_PERIOD < s.min_path
        if brief and max(b0 - a0, b1 - a1) * SPEED_PERIOD < s.min_rest:
            out[b0:a1] = False
    return out


def find_takes(traj: Trajectory, settings: TakeSettings | None = None) -> list[TakeSpan]:
    """Locate the takes of a recording (see the module docstring).

    Parameters
    ----------
    traj : Trajectory
        One long recording: rest, take, rest, take, ..., rest.
    settings : TakeSettings, optional
        Defaults to ``TakeSettings()``.

    Returns
    -------
    list of TakeSpan
        In time order; empty when the recording holds no motion that qualifies.
    """
    s = settings or TakeSettings()
    return takes_from_speed(*motion_speed(traj, s.L, s.smoothing), s)


def takes_from_speed(t: np.ndarray, v: np.ndarray, settings: TakeSettings | None = None
                     ) -> list[TakeSpan]:
    """The takes of a motion speed signal: times (K,) [s] every :data:`SPEED_PERIOD`, speeds (K,)
    [m/s] (:func:`motion_speed`, or the sum of several trackers' speeds); see :func:`find_takes`."""
    s = settings or TakeSettings()
    noise, peak, level = rest_level(v, s)
    if not peak > 0:
        return []
    dt = SPEED_PERIOD
    moving = _twitches_at_rest(t, v, v >= level, s)
    # a rest shorter than min_rest between two motions is part of the take
    for a, b in _runs(~moving):
        if a > 0 and b < v.size and (b - a) * dt < s.min_rest:
            moving[a:b] = True
    runs = [(a, b) for a, b in _runs(moving)
            if t[b - 1] - t[a] >= s.min_duration and np.sum(v[a:b]) * dt >= s.min_path]
    low = min(s.onset_factor * noise, level)
    spans: list[TakeSpan] = []
    for k, (a, b) in enumerate(runs):
        # a take owns the rests around it up to their middle
        lo = (runs[k - 1][1] + a) // 2 if k else 0
        hi = (b + runs[k + 1][0]) // 2 if k + 1 < len(runs) else v.size
        while a > lo and v[a - 1] > low:  # back to where the motion really starts
            a -= 1
        while b < hi and v[b] > low:
            b += 1
        onset, end = t[a], t[b - 1]
        spans.append(TakeSpan(float(onset), float(end), float(max(onset - s.margin, t[lo])),
                              float(min(end + s.margin, t[hi - 1])), float(v[a:b].max()),
                              float(np.sum(v[a:b]) * dt)))
    return spans


def cut_take(traj: Trajectory, span: TakeSpan, source: str | None = None) -> Trajectory:
    """The samples of ``traj`` within ``span.start .. span.stop``, time shifted to start at 0."""
    keep = (traj.t >= span.start - 1e-9) & (traj.t <= span.stop + 1e-9)
    t = traj.t[keep]
    if t.size < MIN_SAMPLES:
        raise FramefreeError(f"{traj.source or 'recording'}: the take at {span.onset:.2f} s has "
                             f"only {t.size} samples")
    return Trajectory(t - t[0], traj.p[keep], traj.q[keep], source=source)


def split_takes(traj: Trajectory, settings: TakeSettings | None = None) -> list[Trajectory]:
    """Cut a recording into takes, each trimmed to its motion with a short rest margin.

    Parameters
    ----------
    traj : Trajectory
        One long recording of repeated performances separated by rests.
    settings : TakeSettings, optional
        Defaults to ``TakeSettings()``.

    Returns
    -------
    list of Trajectory
        One per take, in time order, time starting at 0; ``source`` says where it was cut.

    Examples
    --------
    >>> takes = split_takes(Trajectory.from_csv("wave_session.csv"))   # doctest: +SKIP
    >>> [round(tk.duration, 1) for tk in takes]                          # doctest: +SKIP
    [2.3, 2.1, 2.4, 2.2, 2.0]
    """
    name = traj.source or "recording"
    return [cut_take(traj, sp, f"{name} take {k + 1} ({sp.start:.2f}-{sp.stop:.2f} s)")
            for k, sp in enumerate(find_takes(traj, settings))]


_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def write_take(take: Trajectory, library: str | Path, gesture: str, context: str = "own") -> Path:
    """Write a take as ``<library>/<gesture>/<context>/trial_<k>.csv`` (the dataset layout).

    ``k`` is one more than the largest trial number already there, so existing takes are never
    overwritten.

    Parameters
    ----------
    take : Trajectory
    library : str or Path
        The library folder (created if needed).
    gesture, context : str
        Folder names: letters, digits, ``_``, ``-`` and ``.``, not starting with ``.`` or ``-``.

    Returns
    -------
    Path
        The written file.
    """
    for what, name in (("gesture", gesture), ("context", context)):
        if not _NAME.match(name) or name == "streams":
            raise FramefreeError(f"{what} name {name!r}: use letters, digits, _ - . (e.g. wave_twice)")
    folder = Path(library) / gesture / context
    found = (re.fullmatch(r"trial_(\d+)", f.stem) for f in folder.glob("trial_*.csv"))
    numbers = [int(m.group(1)) for m in found if m]
    path = folder / f"trial_{max(numbers, default=0) + 1}.csv"
    take.to_csv(path)
    return path


def join_recordings(trajectories: Sequence[Trajectory], source: str = "joined recording") -> Trajectory:
    """Recordings joined into one, as if performed one after the other without letting go.

    Each recording is moved rigidly so that it starts at the pose where the previous one ended,
    and its time stamps continue after the previous one's (one median sample period later).
    Recordings that start and end at rest (like the HPM trials) give a session of takes
    separated by rests — the input :func:`split_takes` expects.

    Parameters
    ----------
    trajectories : sequence of Trajectory
    source : str

    Returns
    -------
    Trajectory
    """
    if not trajectories:
        raise ValueError("no recordings to join")
    T = trajectories[0].poses()
    t = trajectories[0].t - trajectories[0].t[0]
    for b in trajectories[1:]:
        Tb = b.poses()
        G = T[-1] @ se3.transform_inverse(Tb[0])
        T = np.concatenate([T, G[None] @ Tb[1:]])
        t = np.concatenate([t, b.t[1:] - b.t[0] + t[-1] + float(np.median(np.diff(b.t)))])
    return Trajectory.from_poses(t, T, source=source)
