"""An orientation too noisy to use: the recognizer then works on the positions alone (v34).

A skeleton tracker's joint orientations can jitter by many degrees from one sample to the next.
The recognizer smooths a noisy sensor (:mod:`~framefree.online.smoothing`), but past some level
the orientation carries no gesture any more: with 10° of white noise per sample on the Machete
right controller's orientations no gesture of 120 was found, where the same takes without their
orientation find most of them (docs/online-history.md, v32 and v34).

The rule needs no new constant. The motion speed counts a turn as ``L`` times its angle, and a
hand at rest must look at rest: :func:`~framefree.online.smoothing.noise_limit` is the noise at
which a still hand appears to move at ``still_speed``. If the orientation's noise alone, times
``L``, stays above that limit *after* the Gaussian that smooths a noisy sensor
(``noisy_smoothing``), no rest can be seen in the turns, and the orientation is dropped: every
quaternion of the takes and of the stream is taken as the identity, as a sensor of positions
only writes it (:func:`~framefree.online.hand_direction.fixed_frame` then holds). A Gaussian of
``s`` samples' standard deviation leaves white noise ``(2 √π s)^(-1/2)`` of its deviation; the
samples count as independent at the sensor's period or the recognizer's grid step, whichever is
longer (a slower sensor, interpolated onto the grid, repeats its noise).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.trajectory import Trajectory
from .learned import GIVEN
from .smoothing import noise_limit, rotation_noise

__all__ = ["IDENTITY", "constant_orientation", "orientation_unusable", "residual_noise",
           "resolve_orientation", "unusable_orientation_advice"]

#: The quaternion ``(w, x, y, z)`` written for every sample once the orientation is dropped.
IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def residual_noise(noise: float, smoothing: float, period: float, dt: float) -> float:
    """White noise of ``noise`` per sample after a centred Gaussian of ``smoothing`` [s], the
    samples independent every ``max(period, dt)`` [s]: ``noise · (2 √π s)^(-1/2)`` with ``s``
    the Gaussian's deviation in such samples (at most ``noise``)."""
    s = smoothing / max(period, dt)
    if not s > 0:
        return noise
    return noise * min(1.0, (2.0 * math.sqrt(math.pi) * s) ** -0.5)


def orientation_unusable(trajectories: Sequence[Trajectory], still_speed: float, lag: float,
                         smoothing: float, L: float, dt: float) -> tuple[bool, float]:
    """Whether the takes' orientation is too noisy to use, and its noise [rad per axis and
    sample] (the median over the takes of :func:`~framefree.online.smoothing.rotation_noise`).

    Too noisy: ``L`` times that noise, smoothed by ``smoothing`` [s]
    (:func:`residual_noise`, at the takes' median sample period), exceeds
    :func:`~framefree.online.smoothing.noise_limit` (``still_speed`` [m/s], ``lag`` [s]).
    ``(False, nan)`` when no take is long enough to read a noise.
    """
    noise = [x for x in (rotation_noise(tr) for tr in trajectories) if math.isfinite(x)]
    if not noise:
        return False, float("nan")
    level = float(np.median(noise))
    period = float(np.median([np.median(np.diff(tr.t)) for tr in trajectories]))
    residual = residual_noise(L * level, smoothing, period, dt)
    return residual > noise_limit(still_speed, lag), level


def constant_orientation(traj: Trajectory) -> Trajectory:
    """``traj`` with every quaternion the identity: its positions alone."""
    return Trajectory(traj.t, traj.p, np.tile(IDENTITY, (traj.t.size, 1)), source=traj.source)


def resolve_orientation(trajectories: Sequence[Trajectory], config: Any, draft: Any,
                        restoring: bool = False) -> list[Trajectory]:
    """Fill ``draft``'s ``positions_only`` and return the takes as the recognizer uses them:
    without their orientation when it is too noisy (:func:`orientation_unusable`), else as
    given. A value ``draft`` holds wins (a library's, or one the caller fixed); a library saved
    before this was learned keeps its orientation, as it was calibrated."""
    if restoring:
        draft.fill("a library saved before framefree learned whether the orientation is usable: "
                   "kept", positions_only=False)
    if draft.missing("positions_only"):
        k = config.constants
        unusable, noise = orientation_unusable(trajectories, k.still_speed, k.speed_lag * k.dt,
                                               k.noisy_smoothing, config.descriptor.L, k.dt)
        draft.fill(f"{orientation_unusable.__module__}.orientation_unusable (orientation noise "
                   f"{math.degrees(noise):.2g}° per sample)", positions_only=unusable)
    if not draft.values["positions_only"]:
        return list(trajectories)
    return [constant_orientation(tr) for tr in trajectories]


def unusable_orientation_advice(trajectories: Sequence[Trajectory], config: Any,
                                learned: Any) -> str | None:
    """One line when the recognizer decided to drop the orientation of ``trajectories`` (its
    takes as given), else ``None`` (also when a caller fixed ``positions_only``)."""
    if not learned.positions_only or learned.provenance.rules.get("positions_only") == GIVEN:
        return None
    k = config.constants
    _, noise = orientation_unusable(trajectories, k.still_speed, k.speed_lag * k.dt,
                                    k.noisy_smoothing, config.descriptor.L, k.dt)
    return (f"the takes' orientation is too noisy to use ({math.degrees(noise):.2g}° per sample: "
            "even smoothed, a still hand would appear to turn), so the takes and the stream are "
            "recognized from their positions alone, without the stop signal, a quick roll of the "
            "hand (--set positions_only=false keeps the orientation)")
