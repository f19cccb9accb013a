"""Shared fixtures: the HPM seven (replica, original_1) as a vocabulary, enrolled once."""

from __future__ import annotations

from pathlib import Path

import pytest

from framefree.core.trajectory import Trajectory
from framefree.library import GestureLibrary, TakeSet, enroll, join_recordings, read_takes
from framefree.replica import replica_path


@pytest.fixture(scope="session")
def hpm_takes() -> TakeSet:
    """The 35 original_1 recordings of the replica (seed 0)."""
    return read_takes(replica_path(), "original_1")


@pytest.fixture(scope="session")
def hpm_library(hpm_takes: TakeSet) -> GestureLibrary:
    """The HPM seven enrolled with the default recognizer settings."""
    return enroll(hpm_takes, built_from=[str(replica_path())])


@pytest.fixture(scope="session")
def hpm_library_file(hpm_library: GestureLibrary, tmp_path_factory: pytest.TempPathFactory) -> Path:
    return hpm_library.save(tmp_path_factory.mktemp("lib") / "hpm.npz")


def chain(trajs: list[Trajectory], source: str = "session") -> Trajectory:
    """Recordings joined into one: each moved rigidly to start where the previous one ended."""
    return join_recordings(trajs, source)


def scaled(traj: Trajectory, factor: float, source: str) -> Trajectory:
    """Positions scaled by ``factor`` about the first one (a bigger version of the same motion)."""
    return Trajectory(traj.t, traj.path_scaled(factor).p, traj.q, source=source)
