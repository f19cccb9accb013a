"""Gesture models for the live recognizer: recordings replayed through the streaming routine.

See docs/online-paper.md, *Gesture models*.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ...core import se3
from ...core.progress import StreamingReparameterizer, cumulative_progress
from ...core.trajectory import Trajectory
from ...errors import FramefreeError
from .config import PaperConfig
from .preprocess import filtered_poses, replay

__all__ = ["GestureModels", "auto_resolution", "build_models"]


@dataclass(frozen=True)
class GestureModels:
    """Descriptor sequences of the model recordings, built by the streaming routine.

    Attributes
    ----------
    labels : tuple of str, length M
        Gesture label of each model.
    descriptors : tuple of ndarray, shape (N_j, 18)
        Online BILTS+ descriptor of each model recording.
    resolution : float
        Δs_res [m] used to build them (live data must use the same).
    sources : tuple of str
        Where each recording came from.
    """

    labels: tuple[str, ...]
    descriptors: tuple[np.ndarray, ...]
    resolution: float
    sources: tuple[str, ...] = field(default=())

    @property
    def gestures(self) -> list[str]:
        """Distinct labels in first-appearance order."""
        return list(dict.fromkeys(self.labels))

    def __len__(self) -> int:
        return len(self.labels)


def auto_resolution(
    trajectories: Sequence[Trajectory], L: float, samples: int = 50, presmooth: int = 1
) -> float:
    """Resolution Δs_res [m] at which Algorithm 1 keeps a median of ``samples`` geometric samples.

    The obvious guess is the median total screw path divided by ``samples - 1``; but the total
    screw path of a real recording also integrates the sensor noise of its rests, whereas
    Algorithm 1 (displacement from the last kept sample) does not accumulate noise. So the
    resolution is found by bisection (in log space) on the median number of kept samples, starting
    from that guess (docs/online-paper.md, *Gesture models*). ``presmooth``: the causal pre-filter
    of the streaming routine is applied first.
    """
    poses = [tr.poses() if presmooth <= 1 else se3.poses_from_pq(*filtered_poses(tr, presmooth))
             for tr in trajectories]
    totals = [cumulative_progress(T, "screw", L)[-1] for T in poses]
    guess = float(np.median(totals)) / (samples - 1)
    if not guess > 0:
        raise FramefreeError("the model recordings have no screw-path progress (no motion)")

    def median_count(res: float) -> float:
        return float(np.median([StreamingReparameterizer(res, L).run(T).size for T in poses]))

    lo, hi = guess / 64.0, guess * 4.0
    for _ in range(40):
        mid = math.sqrt(lo * hi)
        if median_count(mid) > samples:
            lo = mid
        else:
            hi = mid
        if hi / lo < 1.001:
            break
    return hi


def build_models(
    trajectories: Sequence[Trajectory], labels: Sequence[str], config: PaperConfig
) -> GestureModels:
    """Replay every recording through :class:`~framefree.online.paper.preprocess.StreamingBILTSPlus`.

    Raises
    ------
    FramefreeError
        If a recording is too short to give at least two descriptor samples.
    """
    if len(trajectories) != len(labels):
        raise ValueError(f"{len(trajectories)} trajectories but {len(labels)} labels")
    if len(trajectories) == 0:
        raise FramefreeError("no model recordings")
    res = config.resolution
    if res is None:
        res = auto_resolution(trajectories, config.L, config.resolution_samples, config.presmooth)
    descs = []
    for tr in trajectories:
        d, _ = replay(tr, res, config.L, config.ds_scale, config.window, config.twist_noise,
                      config.presmooth)
        if d.shape[0] < 2:
            raise FramefreeError(
                f"{tr.source or 'a model recording'}: only {d.shape[0]} descriptor samples at "
                f"resolution {res:.4g} m; use a finer resolution or a smaller ds_scale"
            )
        descs.append(d)
    return GestureModels(
        tuple(str(s) for s in labels), tuple(descs), float(res),
        tuple(tr.source or f"model_{k}" for k, tr in enumerate(trajectories)),
    )
