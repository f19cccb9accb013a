"""A tiny dataset in the HPM layout, built from real recordings moved by known frames."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from framefree import Trajectory
from framefree.core.se3 import rotation_from_vector

#: gesture -> recording in shared/data/real_motions/reference_set
SOURCES = {
    "helix": "syn_helix_screw_wobble.csv",
    "pour": "ip_pouring_motion.csv",
    "scoop": "ip_scooping_motion.csv",
}


def pose(R: np.ndarray, p: tuple[float, float, float]) -> np.ndarray:
    """Homogeneous (4, 4) pose from a rotation (3, 3) and a translation [m]."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


RZ180 = np.diag([-1.0, -1.0, 1.0])
RX90 = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])


def noisy(traj: Trajectory, rng: np.random.Generator, time_scale: float) -> Trajectory:
    """1 mm / 1° white noise and a time scaling (a 'new trial' of the same gesture)."""
    T = traj.poses().copy()
    n = len(traj)
    T[:, :3, 3] += rng.normal(0, 0.001, (n, 3))
    T[:, :3, :3] = T[:, :3, :3] @ rotation_from_vector(rng.normal(0, np.pi / 180, (n, 3)))
    return Trajectory.from_poses(traj.t * time_scale, T)


def write_dataset(
    root: Path,
    real_dir: Path,
    contexts: dict[str, tuple[np.ndarray | None, np.ndarray | None, float]],
    trial_names: tuple[str, ...] = ("trial_1", "trial_2", "trial_3"),
    gestures: dict[str, str] | None = None,
    seed: int = 0,
) -> Path:
    """Write ``root/<gesture>/<context>/<trial>.csv``.

    ``contexts`` maps a context name to ``(world pose or None, body pose or None, kept fraction)``.
    """
    rng = np.random.default_rng(seed)
    for g, fname in (gestures or SOURCES).items():
        base = Trajectory.from_csv(real_dir / "reference_set" / fname)
        for ctx, (W, B, frac) in contexts.items():
            for k, name in enumerate(trial_names):
                tr = noisy(base, rng, 1.0 + 0.1 * (k - 1))
                tr = tr.transformed(world=W, body=B)
                if frac < 1:
                    tr = tr.head(frac)
                tr.to_csv(root / g / ctx / f"{name}.csv")
    return root


HPM_LIKE = {
    "original_1": (None, None, 1.0),
    "original_2": (None, None, 1.0),
    "body_frame_1": (None, pose(RZ180, (0.05, 0, 0)), 1.0),
    "world_frame_1": (pose(RX90, (0, 1.0, 0)), None, 1.0),
    "first_half": (None, None, 0.5),
}


@pytest.fixture(scope="session")
def tiny_root(tmp_path_factory: pytest.TempPathFactory, real_dir: Path) -> Path:
    """3 gestures × 5 contexts (HPM names) × 3 trials, trials 1–2 training, 3 test."""
    return write_dataset(tmp_path_factory.mktemp("tiny_hpm"), real_dir, HPM_LIKE)
