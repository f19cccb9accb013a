"""Sample acceptance: which raw tracker samples the live recognizer may use.

A real tracker delivers NaN poses, zero quaternions, repeated or backwards time stamps, quaternion
sign flips, time-stamp jitter, dropouts and single-sample glitches, and it sometimes relocates
(its pose jumps for good). :class:`SampleGate` turns such a stream into a clean one:

* invalid samples (non-finite values, zero quaternion), repeated time stamps (closer than
  ``min_interval`` to the previous sample) and backwards time stamps are skipped;
* quaternions are normalized and their sign made continuous
  (:func:`framefree.core.se3.align_quaternion_sign`);
* a sample is *consistent* with a reference sample when the hand could have moved between them:
  displacement at most ``max_speed × Δ + position_tolerance`` and rotation angle at most
  ``max_angular_speed × Δ + angle_tolerance``, with ``Δ = max(dt, period) + time_tolerance``, so
  the test is in physical units and holds whatever the gap (time-stamp jitter cannot trip it);
* a sample consistent with the last accepted one and at most ``gap_factor`` nominal periods after
  it is accepted at once;
* samples that are not (after a longer gap, far from the last accepted sample, or at the very
  start) are held as *candidates* until enough consecutive, mutually consistent ones confirm them:
  two after a gap, ``patience`` when they are far from the last accepted pose. A held sample
  contradicted by the next one while that one agrees with the last accepted pose was a glitch
  (counted in ``outliers``) and is dropped;
* a confirmed gap of at most ``max_bridge`` seconds is bridged: poses are inserted by screw linear
  interpolation (ScLERP) between the last accepted pose and the first confirmed one, at about the
  nominal sample period (the median of recent sample intervals); the stream is not restarted;
* a longer gap, or confirmed far samples (a relocation), restart the stream
  (:attr:`Accepted.restarted`).

Memory is bounded: at most ``patience`` held samples and ``period_window`` recent intervals.
"""

from __future__ import annotations

import math
import statistics
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..core import se3
from ..core.trajectory import Trajectory

__all__ = ["GATE_FACTOR", "GATE_STAT_KEYS", "HAND_HELD_SPEEDS", "Accepted", "Sample", "SampleGate",
           "gate_limits", "well_formed"]


def well_formed(t: float, p: Sequence[float] | np.ndarray, q: Sequence[float] | np.ndarray,
                stats: dict[str, int]) -> tuple[float, np.ndarray, np.ndarray] | None:
    """One pose sample as ``(t [s], p (3,) [m], q (4,) unit quaternion w, x, y, z)``, copied from
    the caller's arrays; ``None`` for a sample with a NaN or infinite value (counted in
    ``stats["nan"]``) or a zero quaternion (``stats["bad_quaternion"]``)."""
    t = float(t)
    p = np.array(p, dtype=np.float64).reshape(3)
    q = np.array(q, dtype=np.float64).reshape(4)
    if not (math.isfinite(t) and np.isfinite(p).all() and np.isfinite(q).all()):
        stats["nan"] += 1
        return None
    nq = math.sqrt(float(q @ q))
    if not nq > 1e-9 or not math.isfinite(nq):
        stats["bad_quaternion"] += 1
        return None
    return t, p, q / nq


#: The gate's fastest plausible speed [m/s] and angular speed [rad/s] of a hand-held tracker
#: drawing a gesture: :class:`SampleGate`'s defaults, and the least :func:`gate_limits` gives.
HAND_HELD_SPEEDS = (5.0, 30.0)

#: How much faster than the fastest take a live sample may move before the acceptance gate takes
#: it for a glitch (:func:`gate_limits`).
GATE_FACTOR = 3.0


def gate_limits(trajectories: Sequence[Trajectory], factor: float = GATE_FACTOR,
                floor: tuple[float, float] = HAND_HELD_SPEEDS, turns: bool = True
                ) -> tuple[float, float]:
    """The acceptance gate's fastest plausible speed [m/s] and angular speed [rad/s], from the
    takes: ``factor`` × the largest 99th percentile of any take's sample-to-sample speed, at
    least ``floor``; with ``turns`` False the angular speed is ``floor``'s.

    A hand-held tracker drawing a gesture stays below 5 m/s and 30 rad/s; a controller in a golf
    swing or a hook does not (the six Machete Vive people: 99th percentiles of 6.3-12.2 m/s and
    17-50 rad/s). Between two samples 33 ms apart (a skeleton tracker's 30 Hz) a hand at 8 m/s
    moves farther than the hand-held limit allows, and the gate took one Machete person's
    fastest strokes for glitches and relocations: 8 restarts in a session of 2.7 minutes
    (docs/online-history.md, v35). A take of a constant orientation (a sensor of positions only)
    turns at 0 rad/s and keeps the angular floor.

    One tracker learns the speed alone (``turns`` False): a hand tracker flips the palm's
    orientation now and then, faster than a hand turns, and the hand-held angular limit is what
    takes such a flip for a relocation (after which no stop fires, v20). Learned from SFINGE3D's
    dictionary, the angular limit rises to 46 rad/s, and one flip fired a false stop.
    """
    v_max, w_max = 0.0, 0.0
    for tr in trajectories:
        dt = np.diff(tr.t)
        v = np.linalg.norm(np.diff(tr.p, axis=0), axis=1) / dt
        dots = np.clip(np.abs(np.sum(tr.q[1:] * tr.q[:-1], axis=1)), 0.0, 1.0)
        w = 2.0 * np.arccos(dots) / dt
        v_max = max(v_max, float(np.percentile(v, 99)))
        w_max = max(w_max, float(np.percentile(w, 99)))
    return max(floor[0], factor * v_max), max(floor[1], factor * w_max if turns else 0.0)


#: A pose sample: time [s], position (3,) [m], unit quaternion (4,) ``(w, x, y, z)``.
Sample = tuple[float, np.ndarray, np.ndarray]

#: Counters of :attr:`SampleGate.stats`.
GATE_STAT_KEYS = (
    "samples",  # samples offered
    "accepted",  # real samples passed on (bridged ones not included)
    "nan",  # skipped: NaN or inf in t, p or q
    "bad_quaternion",  # skipped: zero-norm quaternion
    "repeated",  # skipped: same time stamp as the previous sample (duplicates)
    "backwards",  # skipped: time stamp before the previous sample
    "sign_flips",  # quaternion signs negated to stay continuous
    "bridged_gaps",  # gaps filled by interpolation
    "bridged_samples",  # samples inserted by interpolation
    "gaps",  # gaps too long to bridge (restarts)
    "outliers",  # skipped: single glitches inconsistent with their neighbours
    "relocations",  # restarts after `patience` consistent far samples
    "clock_resets",  # restarts after `patience` consecutive backwards time stamps
)


@dataclass
class Accepted:
    """What :meth:`SampleGate.push` passes on for one offered sample.

    Attributes
    ----------
    samples : list of (float, ndarray (3,), ndarray (4,))
        Clean samples ``(t, p, q)``, oldest first (none, one, or several: held samples once
        confirmed, and bridged ones). Times strictly increase across calls (within one stream)
        and quaternions are unit and sign-continuous.
    restarted : bool
        The stream restarted before these samples (a gap too long to bridge, a relocation or a
        clock reset): anything built on the previous samples should be discarded.
    relocated : bool
        The restart was a relocation: the tracker's pose jumped farther than a hand moves.
    """

    samples: list[Sample] = field(default_factory=list)
    restarted: bool = False
    relocated: bool = False


@dataclass
class _Held:
    t: float
    p: np.ndarray
    q: np.ndarray


class SampleGate:
    """Streaming acceptance of raw pose samples (see the module docstring for the rules).

    Parameters
    ----------
    max_bridge : float
        Longest gap [s] filled by interpolation (0.5); longer gaps restart the stream.
    nominal_period : float
        Sample period [s] assumed until the stream has shown its own (0.02).
    gap_factor : float
        An interval longer than ``gap_factor`` × period is a gap (2.5: ±8 ms of time-stamp jitter
        on a 20 ms period stays below it).
    max_speed : float
        Fastest plausible hand speed [m/s] (5).
    max_angular_speed : float
        Fastest plausible hand angular speed [rad/s] (30; a quick wrist flick reaches about 15).
    position_tolerance : float
        Allowance for tracker noise [m] (0.02).
    angle_tolerance : float
        Allowance for tracker noise [rad] (0.1).
    time_tolerance : float
        Allowance for time-stamp jitter [s] added to every interval (0.01).
    patience : int
        Consecutive, mutually consistent far samples taken as a relocation (3).
    min_interval : float
        Samples closer in time than this [s] to the previous one are repeats (1e-4).
    period_window : int
        Number of recent sample intervals whose median is the nominal period (16).

    Attributes
    ----------
    stats : dict of str to int
        Counters (see :data:`GATE_STAT_KEYS`).
    period : float
        Current nominal sample period [s].
    """

    def __init__(
        self,
        *,
        max_bridge: float = 0.5,
        nominal_period: float = 0.02,
        gap_factor: float = 2.5,
        max_speed: float = 5.0,
        max_angular_speed: float = 30.0,
        position_tolerance: float = 0.02,
        angle_tolerance: float = 0.1,
        time_tolerance: float = 0.01,
        patience: int = 3,
        min_interval: float = 1e-4,
        period_window: int = 16,
    ) -> None:
        positive = {"max_bridge": max_bridge, "nominal_period": nominal_period,
                    "max_speed": max_speed, "max_angular_speed": max_angular_speed}
        for name, value in positive.items():
            if not value > 0:
                raise ValueError(f"{name} must be positive, got {value}")
        if not gap_factor > 1:
            raise ValueError(f"gap_factor must exceed 1, got {gap_factor}")
        if patience < 2:
            raise ValueError(f"patience must be at least 2, got {patience}")
        self.max_bridge = float(max_bridge)
        self.nominal_period = float(nominal_period)
        self.gap_factor = float(gap_factor)
        self.max_speed = float(max_speed)
        self.max_angular_speed = float(max_angular_speed)
        self.position_tolerance = float(position_tolerance)
        self.angle_tolerance = float(angle_tolerance)
        self.time_tolerance = float(time_tolerance)
        self.patience = int(patience)
        self.min_interval = float(min_interval)
        self._intervals: deque[float] = deque(maxlen=int(period_window))
        self.reset()

    # ------------------------------------------------------------------------------------ state
    def reset(self) -> None:
        """Forget the stream and zero the counters."""
        self.stats: dict[str, int] = dict.fromkeys(GATE_STAT_KEYS, 0)
        self._intervals.clear()
        self.period = self.nominal_period
        self._last: _Held | None = None  # last sample passed on
        self._held: list[_Held] = []  # candidates awaiting confirmation (at most `patience`)
        self._held_far = False  # the first candidate was inconsistent with the last sample
        self._backwards_run = 0
        self._clock_reset = False  # the clock restarted: report it with the next samples released
        self._q_ref: np.ndarray | None = None  # last quaternion passed on (sign reference)

    @property
    def n_held(self) -> int:
        """Number of samples held for confirmation (at most ``patience``)."""
        return len(self._held)

    # ---------------------------------------------------------------------------------- helpers
    def _ratio(self, a: _Held, b: _Held) -> float:
        """How far ``b`` is from ``a`` relative to the plausible motion limits (≤ 1: consistent)."""
        span = max(abs(b.t - a.t), self.period) + self.time_tolerance
        d = b.p - a.p
        dist = math.sqrt(float(d @ d))
        cos_half = min(1.0, abs(float(a.q @ b.q)))
        angle = 2.0 * math.acos(cos_half)
        return max(dist / (self.max_speed * span + self.position_tolerance),
                   angle / (self.max_angular_speed * span + self.angle_tolerance))

    def _is_gap(self, dt: float) -> bool:
        return dt > self.gap_factor * self.period

    def _emit(self, out: Accepted, s: _Held, real: bool = True) -> None:
        """Pass ``s`` on with its sign aligned to the previous sample; update the period."""
        q = s.q
        if self._q_ref is not None and se3.quaternion_sign(q, self._q_ref) < 0.0:
            q = -q
            if real:
                self.stats["sign_flips"] += 1
        self._q_ref = q
        last = self._last
        if last is not None:
            if real and s.t - last.t <= self.max_bridge:
                self._intervals.append(s.t - last.t)
                self.period = statistics.median(self._intervals)
        if real:
            self.stats["accepted"] += 1
        self._last = _Held(s.t, s.p, q)
        out.samples.append((s.t, s.p.copy(), q.copy()))

    def _bridge(self, out: Accepted, a: _Held, b: _Held) -> None:
        """Insert ScLERP poses between ``a`` and ``b`` at about the nominal period."""
        dt = b.t - a.t
        n = max(0, round(dt / self.period) - 1)
        if n == 0:
            return
        alpha = np.arange(1, n + 1) / (n + 1)
        A = np.repeat(se3.poses_from_pq(a.p, a.q)[None], n, axis=0)
        B = np.repeat(se3.poses_from_pq(b.p, b.q)[None], n, axis=0)
        T = se3.sclerp(A, B, alpha)
        p, q = se3.pq_from_poses(T)
        self.stats["bridged_gaps"] += 1
        self.stats["bridged_samples"] += n
        for k in range(n):
            self._emit(out, _Held(a.t + float(alpha[k]) * dt, p[k], q[k]), real=False)

    def _restart(self, out: Accepted) -> None:
        out.restarted = out.restarted or self._last is not None or self._clock_reset
        self._clock_reset = False
        self._last = None

    # ------------------------------------------------------------------------------------- push
    def push(
        self, t: float, p: Sequence[float] | np.ndarray, q: Sequence[float] | np.ndarray
    ) -> Accepted:
        """Offer one raw sample; return what may be used now.

        Parameters
        ----------
        t : float
            Time stamp [s].
        p : array_like, shape (3,)
            Position [m].
        q : array_like, shape (4,)
            Orientation quaternion ``(w, x, y, z)``, any norm and sign.

        Returns
        -------
        Accepted
            The clean samples this one releases, and whether the stream restarted before them.
        """
        st = self.stats
        st["samples"] += 1
        out = Accepted()
        s = self._validate(t, p, q)
        if s is not None:
            self._place(s, out)
        return out

    def _validate(
        self, t: float, p: Sequence[float] | np.ndarray, q: Sequence[float] | np.ndarray
    ) -> _Held | None:
        st = self.stats
        sample = well_formed(t, p, q, st)
        if sample is None:
            return None
        t = sample[0]
        s = _Held(*sample)
        prev = self._held[-1] if self._held else self._last
        if prev is not None:
            dt = t - prev.t
            if abs(dt) < self.min_interval:
                st["repeated"] += 1
                return None
            if dt < 0.0:
                st["backwards"] += 1
                self._backwards_run += 1
                if self._backwards_run < self.patience:
                    return None
                st["clock_resets"] += 1
                self._held.clear()
                self._last = None
                self._clock_reset = True
        self._backwards_run = 0
        return s

    def _place(self, s: _Held, out: Accepted) -> None:
        """Accept, hold or drop a valid sample ``s`` (times already checked)."""
        last = self._last
        r_last = math.inf
        if last is not None and s.t - last.t <= self.max_bridge:
            r_last = self._ratio(last, s)
        if self._held:
            c = self._held[-1]
            r_held = self._ratio(c, s)
            if r_held <= 1.0 and not self._is_gap(s.t - c.t):
                self._hold(s, out)
                return
            if r_last <= 1.0 or r_held > 1.0:
                self.stats["outliers"] += len(self._held)
                self._held.clear()
            else:
                self._hold(s, out)
                return
        if last is not None and r_last <= 1.0 and not self._is_gap(s.t - last.t):
            self._emit(out, s)
            return
        self._held_far = last is not None and s.t - last.t <= self.max_bridge and r_last > 1.0
        self._hold(s, out)

    def _hold(self, s: _Held, out: Accepted) -> None:
        """Add a candidate; release the candidates once enough agree."""
        self._held.append(s)
        need = self.patience if self._held_far else 2
        if len(self._held) < need:
            return
        first = self._held[0]
        last = self._last
        if self._held_far:
            self.stats["relocations"] += 1
            out.relocated = True
            self._restart(out)
        elif last is not None and first.t - last.t <= self.max_bridge:
            self._bridge(out, last, first)
        else:
            if last is not None:
                self.stats["gaps"] += 1
            self._restart(out)
        for h in self._held:
            self._emit(out, h)
        self._held.clear()
        self._held_far = False
