"""Shared fixtures: paths to the real recordings (tests/real_data.py)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

from real_data import REAL_MOTIONS

settings.register_profile("framefree", deadline=None, max_examples=25, derandomize=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "framefree"))


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "realtime: tests with a 1 kHz simulator thread; make test "
                                       "runs them alone, after the others")

REPO = Path(__file__).resolve().parents[1]


REAL = REAL_MOTIONS


@pytest.fixture(scope="session")
def real_dir() -> Path:
    """Folder of the real recordings (kettle pouring, reference set)."""
    return REAL


@pytest.fixture(scope="session")
def kettle_files(real_dir: Path) -> list[Path]:
    """The six real kettle-pouring recordings (two tracker mountings)."""
    return sorted(real_dir.glob("kettle_pour_trial*_ref_*.csv"))
