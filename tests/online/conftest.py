"""Shared fixtures: small gesture sets cut from the real recordings (tests/real_data.py)."""

from __future__ import annotations

import numpy as np
import pytest

from framefree import Trajectory
from framefree.online.paper import PaperConfig
from real_data import REAL_MOTIONS

DATA = REAL_MOTIONS


def _load(name: str) -> Trajectory:
    path = DATA / name
    if not path.is_file():
        pytest.skip(f"real recording {name} not available")
    return Trajectory.from_csv(path)


@pytest.fixture(scope="session")
def kettle() -> Trajectory:
    return _load("kettle_pour_trial1_ref_com.csv")


@pytest.fixture(scope="session")
def model_set() -> tuple[list[Trajectory], list[str]]:
    """Six kettle pours (one 'pour' gesture, two body frames) and two other real motions."""
    names = [f"kettle_pour_trial{k}_ref_{r}.csv" for k in (1, 2, 3) for r in ("com", "top")]
    trajs = [_load(n) for n in names]
    trajs.append(_load("reference_set/ip_scooping_motion.csv"))
    trajs.append(_load("reference_set/ip_pouring_motion.csv"))
    return trajs, ["pour"] * 6 + ["scoop", "pour_ip"]


@pytest.fixture(scope="session")
def config() -> PaperConfig:
    return PaperConfig(resolution=0.04, threshold=0.5, stop_threshold=3.0)


def concatenate(trajs: list[Trajectory], rest: float = 1.0) -> Trajectory:
    """Recordings played one after the other, each rigidly moved to start where the last ended,
    with ``rest`` seconds of standstill in between (50 Hz)."""
    ts, ps, qs = [], [], []
    t_end = 0.0
    T_end = None
    from framefree.core import se3

    for tr in trajs:
        T = tr.poses()
        if T_end is not None:
            T = (T_end @ se3.transform_inverse(T[0]))[None] @ T
            hold = np.arange(1, int(rest * 50) + 1) * 0.02
            ts.append(t_end + hold)
            p_h, q_h = se3.pq_from_poses(np.repeat(T_end[None], hold.size, axis=0))
            ps.append(p_h)
            qs.append(q_h)
            t_end += hold[-1]
        p, q = se3.pq_from_poses(T)
        ts.append(t_end + 0.02 + tr.t - tr.t[0])
        ps.append(p)
        qs.append(q)
        t_end = ts[-1][-1]
        T_end = T[-1]
    return Trajectory(np.concatenate(ts), np.concatenate(ps), np.concatenate(qs), source="concat")


@pytest.fixture(scope="session")
def concat():
    """The :func:`concatenate` helper."""
    return concatenate
