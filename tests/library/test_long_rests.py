"""A take that rests far longer between its moves than any other: it would widen the pause every
gesture may make, so the candidate limits leave it out, and ``enroll`` and ``check`` name it
(docs/online-history.md, *Session 41* and *Session 42*)."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.library import GestureLibrary, TakeSet, enroll, write_take
from framefree.library.long_rests import long_rest, long_rest_findings, longest_rests
from framefree.online.limits import limits_of_units, odd_rest_take
from framefree.online.segmentation import Unit

from .conftest import chain

DOUBLE = "go_left/original_1/trial_1"


@pytest.fixture(scope="module")
def two_in_one(hpm_takes: TakeSet) -> TakeSet:
    """The HPM seven, one *go left* take replaced by two performances joined by their rests (as
    a take that holds its way back after a rest)."""
    k = hpm_takes.names.index(DOUBLE)
    joined = chain([hpm_takes.takes[k], hpm_takes.takes[k + 1]], DOUBLE)
    return TakeSet((*hpm_takes.takes[:k], joined, *hpm_takes.takes[k + 1:]), hpm_takes.labels,
                   hpm_takes.names)


def test_the_hpm_takes_have_no_long_rest(hpm_library: GestureLibrary) -> None:
    assert long_rest_findings(hpm_library) == []
    assert longest_rests(hpm_library).max() < 1.0


def test_a_take_holding_two_performances_is_named(two_in_one: TakeSet) -> None:
    lib = enroll(two_in_one, built_from=["two in one"])
    found = long_rest(lib)
    assert found is not None and found.name == DOUBLE
    assert found.rest > 2 * found.others
    (finding,) = long_rest_findings(lib)
    assert finding.gesture == "go_left" and f"--remove {DOUBLE}" in finding.message
    assert "does not widen" in finding.message


def test_the_take_does_not_widen_the_limits_of_every_gesture(two_in_one: TakeSet) -> None:
    """Counted, its 1.5 s rest would let every gesture pause 3.8 s inside (session 41)."""
    with_it = enroll(two_in_one, built_from=["two in one"]).learned_settings()
    without = enroll(two_in_one.without([DOUBLE]), built_from=["without"]).learned_settings()
    for name in ("max_units", "max_duration", "max_pause", "pause_ratio"):
        assert getattr(with_it, name) == pytest.approx(getattr(without, name)), name


def test_a_given_pause_allowance_is_not_the_takes_doing(two_in_one: TakeSet) -> None:
    lib = enroll(two_in_one, built_from=["two in one"], max_pause=1.0)
    assert lib.learned_settings().provenance.rules["max_pause"] == "given"
    assert long_rest(lib) is None and long_rest_findings(lib) == []


def test_enroll_notes_the_take(two_in_one: TakeSet, tmp_path: Path) -> None:
    folder = tmp_path / "lib"
    for take, label, name in zip(two_in_one.takes, two_in_one.labels, two_in_one.names,
                                 strict=True):
        if label in ("go_left", "go_right", "go_up"):
            write_take(take, folder, label, name.split("/")[1])
    res = CliRunner().invoke(cli, ["enroll", str(folder), "-o", str(tmp_path / "lib.npz")])
    assert res.exit_code == 0, res.output
    assert "note: take go_left/original_1/trial_1 rests" in res.output


@pytest.mark.parametrize(("gaps", "labels", "odd"), [
    ([0.3, 0.4, 1.5, 0.2], "aabb", 2),
    ([0.3, 0.4, 1.5], "aab", None),  # a gesture of one take may pause as it does
    ([0.3, 1.5], "aa", None),  # too few takes to tell
    ([0.1, 0.2, 0.45, 0.0], "aabb", None),  # no longer than any gesture may rest at a corner
    ([0.7, 0.6, 1.3, 0.5], "aabb", None),  # not twice as long as the next
])
def test_which_take_rests_far_longer_than_the_others(gaps: list[float], labels: str,
                                                     odd: int | None) -> None:
    assert odd_rest_take(gaps, list(labels), min_pause=0.5) == odd


def _units(*spans: tuple[float, float]) -> list[Unit]:
    return [Unit(round(a * 50), round(b * 50), a, b, 1.0, True) for a, b in spans]


def test_the_limits_of_one_and_of_several_trackers_leave_the_take_out() -> None:
    """``limits_of_units`` serves both recognizers: with the takes' labels the odd take counts
    for nothing, without them (as before session 42) it sets every limit."""
    takes = [_units((0.0, 1.0), (1.3, 2.0)), _units((0.0, 0.9), (1.2, 2.1)),
             _units((0.0, 1.0)), _units((0.0, 1.0), (2.5, 3.5), (3.6, 4.0))]
    labels = ["go_left", "go_left", "go_up", "go_up"]
    assert limits_of_units(takes, 2.5, 1.5, labels, min_pause=0.5) == pytest.approx(
        limits_of_units(takes[:3], 2.5, 1.5))
    most, longest, pause, _ = limits_of_units(takes, 2.5, 1.5)
    assert (most, longest, pause) == (7, pytest.approx(10.0), pytest.approx(3.75))
