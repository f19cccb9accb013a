"""The offline classifier of a live candidate: its descriptor and its distance to every model.

A candidate segment cut out of the pose buffer is described and compared with the model
recordings exactly as :class:`~framefree.classifier.NearestNeighborClassifier` describes and
compares a recording (the same descriptor object, the same DTW distance), so a gesture seen live
gets the label it would get offline. The search may be pruned by lower bounds
(:mod:`framefree.core.pruning`) without changing the nearest model or its distance.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..core.progress import reparameterize
from ..core.pruning import ModelBank, pruned_nearest
from ..core.trajectory import Trajectory
from ..descriptors.base import Descriptor
from ..errors import DegenerateMotionError

__all__ = ["SegmentClassifier"]


class SegmentClassifier:
    """1-NN distances of a pose segment to every model, as the offline classifier computes them.

    Parameters
    ----------
    descriptor : Descriptor
        The offline descriptor (e.g. BILTS+ with screw progress and presmoothing).
    models : sequence of ndarray
        Model descriptor sequences, computed with ``descriptor.compute`` on the model recordings.
    """

    def __init__(self, descriptor: Descriptor, models: Sequence[np.ndarray], prune: bool = True) -> None:
        self.descriptor = descriptor
        self.models = list(models)
        spec = descriptor.distance_spec()
        #: packed models for exact pruned search (None: the descriptor's distance cannot be pruned)
        self.bank = ModelBank(self.models, spec) if spec is not None and self.models else None
        #: search with lower bounds (:mod:`framefree.core.pruning`); the nearest model and its
        #: distance are those of the full search
        self.prune = prune
        #: DTW cells computed / that a full search would compute, over every search
        self.cells = [0, 0]

    def describe(self, times: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, float] | None:
        """Descriptor of a segment (times (n,) [s], poses (n, 4, 4)) and its size: the total
        progress [m of screw path] of its pre-smoothed poses. ``None`` if it has no motion.

        The two steps of ``descriptor.compute`` (reparameterize, then describe), so the descriptor
        is the offline one bit for bit and the size comes for free.
        """
        if poses.shape[0] < 5:
            return None
        traj = Trajectory.from_poses(times - times[0], poses, source="live segment")
        D = self.descriptor
        try:
            rep = reparameterize(traj, D.progress, D.L, D.n_samples, presmooth=D.presmooth)
            return D.from_reparameterized(rep.poses, rep.ds), rep.total
        except DegenerateMotionError:
            return None

    def distances(self, times: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, float]:
        """Distance (M,) from the segment to every model (``inf`` if it has no motion) and the
        segment's size [m] (0 if it has no motion). Its DTW cells count in :attr:`cells`: as
        the search itself without pruning, as computed on top of it where a pruned search needs
        every exact distance."""
        out = self.describe(times, poses)
        if out is None:
            return np.full(len(self.models), math.inf), 0.0
        if self.bank is not None:
            cells = self.bank.dtw_cells * out[0].shape[0]
            self.cells[0] += cells
            self.cells[1] += 0 if self.pruning else cells
        return self.descriptor.distance_matrix([out[0]], self.models)[0], out[1]

    @property
    def pruning(self) -> bool:
        """Whether :meth:`search_described` can be used (:attr:`prune` set and the distance
        allows it); otherwise :meth:`distances` computes every model's distance."""
        return self.prune and self.bank is not None

    def search_described(self, descriptor: np.ndarray, accept_below: np.ndarray | None = None
                         ) -> np.ndarray:
        """Distances (M,) from a descriptor (n, F) (:meth:`describe`) to the models, pruned:
        every value is a model's exact distance or a lower bound of it. With ``accept_below``
        (each model's threshold), whether the nearest model is below its threshold is exact, and
        when it is, so are the nearest model and its distance
        (:func:`~framefree.core.pruning.pruned_nearest`); without it, the nearest model and its
        distance always are. When ``accept_below`` accepts nothing (all zero), nothing is
        searched: every value is ``inf``."""
        if accept_below is not None and not np.any(accept_below > 0.0):
            self.cells[1] += self.bank.dtw_cells * descriptor.shape[0]
            return np.full(len(self.models), math.inf)
        found = pruned_nearest(descriptor, self.bank, accept_below=accept_below)
        self.cells[0] += found.cells
        self.cells[1] += found.full_cells
        return found.values
