"""The command table of the lazily loading ``framefree`` group matches what the modules register."""

from __future__ import annotations

import importlib
import subprocess
import sys

import click
from click.testing import CliRunner

from framefree.cli import COMMANDS, cli


def test_every_registered_command_is_in_the_table_and_back():
    for module in set(COMMANDS.values()):
        group = click.Group()
        importlib.import_module(f"framefree.commands.{module}").register(group)
        assert {name for name, m in COMMANDS.items() if m == module} == set(group.commands)


def test_help_lists_every_command():
    out = CliRunner().invoke(cli, ["--help"]).output
    assert all(f"  {name} " in out for name in COMMANDS)


def test_the_live_command_loads_no_dataset_generator_and_no_numba():
    """``framefree live --help`` imports neither the replica generators nor numba (start-up)."""
    code = ("import sys; from framefree.cli import cli; from click.testing import CliRunner; "
            "CliRunner().invoke(cli, ['live', '--help']); "
            "print(sorted(m for m in ('numba', 'framefree.datasets', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_public_names_load_on_first_use():
    import pytest

    import framefree
    import framefree.online

    for module in (framefree, framefree.online):
        assert set(module.__all__) <= set(dir(module))
        for name in module.__all__:
            assert getattr(module, name) is not None
        with pytest.raises(AttributeError, match="no attribute"):
            module.no_such_name  # noqa: B018
