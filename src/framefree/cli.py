"""The ``framefree`` command: one entry point, subcommands that read like sentences.

Each area of the toolkit contributes its subcommands from a module in :mod:`framefree.commands`;
this file only assembles them and turns framefree's input errors into one-line messages.
"""

from __future__ import annotations

import importlib
import sys

import click

from . import __version__
from .errors import FramefreeError

#: command modules, each exposing ``register(group)``
COMMAND_MODULES = ("core", "dataset", "benchmark", "online", "robot", "demo", "library")


class _Group(click.Group):
    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except FramefreeError as exc:
            click.secho(f"error: {exc}", fg="red", err=True)
            sys.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="framefree")
def cli() -> None:
    """Recognize hand-held 6-DoF motion gestures without calibrating any reference frame.

    \b
    Pose files are CSV without header, 8 columns: t [s], x, y, z [m], qw, qx, qy, qz.
    Run `framefree COMMAND --help` for the options of a command.
    """


for _name in COMMAND_MODULES:
    try:
        _mod = importlib.import_module(f"{__package__}.commands.{_name}")
    except ModuleNotFoundError as _exc:  # an area that is not written yet
        if _exc.name != f"{__package__}.commands.{_name}":
            raise
        continue
    _mod.register(cli)


def main() -> None:
    """Console-script entry point."""
    cli(prog_name="framefree")


if __name__ == "__main__":
    main()
