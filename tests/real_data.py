"""Where the real recordings are: the full sets in ../shared/data when they are next to the
checkout, else the subset shipped in tests/data (tests/data/README.md), so a fresh clone tests
real tracker data too."""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parent
REPO = TESTS.parent
SHIPPED = TESTS / "data"


def _first(*candidates: Path) -> Path:
    return next((c for c in candidates if c.is_dir()), candidates[-1])


def _shared(name: str) -> list[Path]:
    return [REPO / "shared" / "data" / name, REPO.parent / "shared" / "data" / name]


#: pouring, scooping and free motions; a reference set with frame-changed copies
REAL_MOTIONS = _first(*_shared("real_motions"), SHIPPED / "real_motions")
#: HTC Vive recordings of people, two controllers each (Machete format)
MACHETE = _first(*_shared("machete_vive"), SHIPPED / "machete_vive")
#: the shipped subset itself (always present)
SHIPPED_MACHETE = SHIPPED / "machete_vive"
#: two takes of the fastest Machete person (Sub_U005's golf swing and right uppercut), shipped
SHIPPED_FAST_MACHETE = SHIPPED / "machete_fast"


def shipped_right_controller() -> tuple[list, list[str]]:
    """The right controller's recordings (Trajectory) of the shipped real people, and their
    gestures."""
    from framefree.datasets.people_layout import load_people

    people = load_people(SHIPPED_MACHETE)
    return [r.sample.trackers[0] for r in people], [r.gesture for r in people]
