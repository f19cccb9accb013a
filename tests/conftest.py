"""Shared fixtures: paths to the real recordings in ../shared/data/real_motions."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

settings.register_profile("framefree", deadline=None, max_examples=25, derandomize=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "framefree"))

REPO = Path(__file__).resolve().parents[1]


def _find_real_motions() -> Path | None:
    for cand in (
        REPO / "shared" / "data" / "real_motions",
        REPO.parent / "shared" / "data" / "real_motions",
    ):
        if cand.is_dir():
            return cand
    return None


REAL = _find_real_motions()


@pytest.fixture(scope="session")
def real_dir() -> Path:
    """Folder of the real recordings (kettle pouring, reference set)."""
    if REAL is None:
        pytest.skip("shared/data/real_motions is not next to the checkout")
    return REAL


@pytest.fixture(scope="session")
def kettle_files(real_dir: Path) -> list[Path]:
    """The six real kettle-pouring recordings (two tracker mountings)."""
    return sorted(real_dir.glob("kettle_pour_trial*_ref_*.csv"))
