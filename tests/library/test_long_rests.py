"""A take that rests far longer between its moves than any other: it widens the pause every
gesture may make, and ``enroll`` and ``check`` name it (docs/online-history.md, *Session 41*)."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.library import GestureLibrary, TakeSet, enroll, write_take
from framefree.library.long_rests import long_rest, long_rest_findings, longest_rests

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
    # it did widen the pause allowance of every gesture
    assert lib.learned_settings().max_pause > 2 * enroll_pause(two_in_one, DOUBLE)


def test_a_given_pause_allowance_is_not_the_takes_doing(two_in_one: TakeSet) -> None:
    lib = enroll(two_in_one, built_from=["two in one"], max_pause=1.0)
    assert lib.learned_settings().provenance.rules["max_pause"] == "given"
    assert long_rest(lib) is None and long_rest_findings(lib) == []


def enroll_pause(takes: TakeSet, name: str) -> float:
    """The pause allowance learned without the take ``name``."""
    return enroll(takes.without([name]), built_from=["without"]).learned_settings().max_pause


def test_enroll_notes_the_take(two_in_one: TakeSet, tmp_path: Path) -> None:
    folder = tmp_path / "lib"
    for take, label, name in zip(two_in_one.takes, two_in_one.labels, two_in_one.names,
                                 strict=True):
        if label in ("go_left", "go_right", "go_up"):
            write_take(take, folder, label, name.split("/")[1])
    res = CliRunner().invoke(cli, ["enroll", str(folder), "-o", str(tmp_path / "lib.npz")])
    assert res.exit_code == 0, res.output
    assert "note: take go_left/original_1/trial_1 rests" in res.output
