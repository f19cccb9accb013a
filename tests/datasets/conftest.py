"""Session fixtures: one replica generated into a temporary folder and loaded once."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from framefree.core import se3
from framefree.datasets import Dataset, load_dataset
from framefree.replica import make_replica

SEED = 7


@pytest.fixture(scope="session")
def replica_root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A freshly generated replica (seed 7, one stream)."""
    return make_replica(tmp_path_factory.mktemp("replica"), seed=SEED, n_streams=1)


@pytest.fixture(scope="session")
def replica(replica_root: Path) -> Dataset:
    """The replica, loaded."""
    return load_dataset(replica_root)


def trial(ds: Dataset, gesture: str, context: str, name: str):
    """The trajectory of one trial."""
    (t,) = [x for x in ds.trials if (x.gesture, x.context, x.name) == (gesture, context, name)]
    return t.trajectory


def residuals(T_ref: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per-sample error of poses ``T`` (n, 4, 4) w.r.t. ``T_ref``: (position error in the world
    [m] (n, 3), rotation vector of ``R_ref^T R`` [rad] (n, 3))."""
    dp = T[:, :3, 3] - T_ref[:, :3, 3]
    dr = se3.vector_from_rotation(np.swapaxes(T_ref[:, :3, :3], 1, 2) @ T[:, :3, :3])
    return dp, dr
