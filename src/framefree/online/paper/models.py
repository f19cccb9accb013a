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
from ...core.smoothing import gaussian_offsets
from ...core.trajectory import Trajectory
from ...descriptors.bilts import window_spacing
from ...errors import FramefreeError
from .config import PaperConfig
from .preprocess import densify_poses, filtered_poses, replay

__all__ = ["MAX_INTERPOLATE", "GestureModels", "auto_interpolation", "auto_resolution", "build_models"]

#: Largest number of poses per raw step :func:`auto_interpolation` tries.
MAX_INTERPOLATE = 8


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
    interpolate : int
        Poses offered to Algorithm 1 per raw step (1: none interpolated; live data must use the
        same).
    """

    labels: tuple[str, ...]
    descriptors: tuple[np.ndarray, ...]
    resolution: float
    sources: tuple[str, ...] = field(default=())
    interpolate: int = 1

    @property
    def gestures(self) -> list[str]:
        """Distinct labels in first-appearance order."""
        return list(dict.fromkeys(self.labels))

    def __len__(self) -> int:
        return len(self.labels)


def _model_poses(trajectories: Sequence[Trajectory], presmooth: int, interpolate: int) -> list[np.ndarray]:
    """The poses (N_i, 4, 4) that Algorithm 1 sees for each recording: pre-filtered, densified."""
    poses = [tr.poses() if presmooth <= 1 else se3.poses_from_pq(*filtered_poses(tr, presmooth))
             for tr in trajectories]
    return [densify_poses(T, interpolate) for T in poses]


def auto_resolution(
    trajectories: Sequence[Trajectory], L: float, samples: int = 50, presmooth: int = 1,
    interpolate: int = 1,
) -> float:
    """Resolution Δs_res [m] at which Algorithm 1 keeps a median of ``samples`` geometric samples.

    The obvious guess is the median total screw path divided by ``samples - 1``; but the total
    screw path of a real recording also integrates the sensor noise of its rests, whereas
    Algorithm 1 (displacement from the last kept sample) does not accumulate noise. So the
    resolution is found by bisection (in log space) on the median number of kept samples, starting
    from that guess (docs/online-paper.md, *Gesture models*). ``presmooth``: the causal pre-filter
    of the streaming routine is applied first; ``interpolate``: then the poses put between
    consecutive ones (:func:`~framefree.online.paper.preprocess.densify_poses`).
    """
    poses = _model_poses(trajectories, presmooth, interpolate)
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


def _fewest_descriptors(poses: Sequence[np.ndarray], res: float, L: float, ds_scale: float,
                        window: int) -> int:
    """Descriptor samples of the shortest recording at resolution ``res``: ``n - 5 - 2m``."""
    _, after = gaussian_offsets(window)
    m = window_spacing(ds_scale, res)
    fewest = min(StreamingReparameterizer(res, L).run(T).size for T in poses)
    return fewest - (after + 1) - 2 * m


def auto_interpolation(trajectories: Sequence[Trajectory], config: PaperConfig) -> tuple[int, float]:
    """The fewest poses per raw step, and the resolution, that give every recording two
    descriptor samples.

    Algorithm 1 keeps at most every pose it is offered, so recordings of few poses (20 fps
    examples of about 1.5 s) cannot give it the ``resolution_samples`` it aims at: the bisection
    then runs to its finest resolution, the window spacing to its cap (23) and the shortest
    recordings give no descriptor sample (``n - 5 - 2m < 2``). Here ``k = 1, 2, ...,``
    :data:`MAX_INTERPOLATE` poses per step are tried (``k - 1`` put between every two by ScLERP,
    live as for the models) until the shortest recording gives two. Recordings that already do
    (the paper's 50 Hz recordings) keep ``k = 1``: nothing changes for them.

    Returns
    -------
    interpolate : int
        Poses per raw step.
    resolution : float
        Δs_res [m] (``config.resolution`` when set, else :func:`auto_resolution`'s).
    """
    c = config
    k_fixed = c.interpolate
    for k in ([k_fixed] if k_fixed is not None else range(1, MAX_INTERPOLATE + 1)):
        res = c.resolution
        if res is None:
            res = auto_resolution(trajectories, c.L, c.resolution_samples, c.presmooth, k)
        poses = _model_poses(trajectories, c.presmooth, k)
        if _fewest_descriptors(poses, res, c.L, c.ds_scale, c.window) >= 2:
            return k, res
    return (k_fixed or 1), res


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
    k, res = auto_interpolation(trajectories, config)
    descs = []
    for tr in trajectories:
        d, _ = replay(tr, res, config.L, config.ds_scale, config.window, config.twist_noise,
                      config.presmooth, k)
        if d.shape[0] < 2:
            raise FramefreeError(
                f"{tr.source or 'a model recording'}: only {d.shape[0]} descriptor samples at "
                f"resolution {res:.4g} m with {k} poses per sample step; use a finer resolution, "
                "a smaller ds_scale or a larger interpolate"
            )
        descs.append(d)
    return GestureModels(
        tuple(str(s) for s in labels), tuple(descs), float(res),
        tuple(tr.source or f"model_{j}" for j, tr in enumerate(trajectories)), k,
    )
