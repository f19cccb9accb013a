"""The ``framefree`` command: one entry point, subcommands that read like sentences.

Each area of the toolkit contributes its subcommands from a module in :mod:`framefree.commands`;
this file only assembles them and turns framefree's input errors into one-line messages. A module is
imported when one of its commands runs (or help lists them), so that ``framefree live`` does not
wait for the benchmark's or the robot's imports.
"""

from __future__ import annotations

import difflib
import importlib
import sys
import warnings

import click

from ._version import __version__
from .errors import FramefreeError, FramefreeWarning

#: command name -> module of :mod:`framefree.commands` whose ``register(group)`` adds it
COMMANDS = {
    "describe": "core", "classify": "core",
    "dataset": "dataset", "plot": "dataset",
    "benchmark": "benchmark",
    "stream": "online", "live": "online", "evaluate-stream": "evaluate_stream",
    "robot": "robot",
    "demo": "demo",
    "record": "library", "enroll": "library", "check": "library",
    "evaluate-people": "people",
}


def _one_line(exc: BaseException) -> str:
    """An OS error (unwritable output, full disk, ...) as one sentence naming the path."""
    if isinstance(exc, OSError) and exc.filename is not None:
        return f"{exc.filename}: {exc.strerror or exc}"
    return str(exc)


class _WarningPrinter:
    """Shows framefree's warnings as one line each; repeats of one problem are counted."""

    SHOWN_PER_PROBLEM = 3

    def __init__(self) -> None:
        self.seen: dict[str, int] = {}
        self._default = warnings.showwarning

    def show(self, message, category, filename, lineno, file=None, line=None) -> None:
        if not isinstance(message, FramefreeWarning):
            self._default(message, category, filename, lineno, file, line)
            return
        key = message.problem or str(message)
        self.seen[key] = self.seen.get(key, 0) + 1
        if self.seen[key] <= self.SHOWN_PER_PROBLEM:
            click.secho(f"warning: {message}", fg="yellow", err=True)

    def summary(self) -> None:
        for problem, count in self.seen.items():
            if count > self.SHOWN_PER_PROBLEM:
                more = count - self.SHOWN_PER_PROBLEM
                click.secho(f"warning: {more} more file(s): {problem}", fg="yellow", err=True)


class _Group(click.Group):
    """Runs a subcommand; input errors become one line and exit status 2 (unless ``--debug``).

    Subcommands are loaded on first use from their module (:data:`COMMANDS`).
    """

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(set(COMMANDS) | set(self.commands))

    def resolve_command(self, ctx: click.Context, args: list[str]):
        """As click's, with the nearest command names suggested for a mistyped one."""
        name = click.utils.make_str(args[0]) if args else ""
        if args and self.get_command(ctx, name) is None and not name.startswith("-"):
            close = difflib.get_close_matches(name, self.list_commands(ctx), n=2, cutoff=0.6)
            hint = f" Did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
            ctx.fail(f"No such command {name!r}.{hint} (framefree --help lists them)")
        return super().resolve_command(ctx, args)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in self.commands and cmd_name in COMMANDS:
            module = importlib.import_module(f"{__package__}.commands.{COMMANDS[cmd_name]}")
            module.register(self)
        return self.commands.get(cmd_name)

    def invoke(self, ctx: click.Context):
        debug = bool(ctx.params.get("debug"))
        printer = _WarningPrinter()
        with warnings.catch_warnings():
            warnings.simplefilter("always", FramefreeWarning)
            if not debug:
                warnings.showwarning = printer.show
            try:
                return super().invoke(ctx)
            except (FramefreeError, OSError) as exc:
                if debug:
                    raise
                click.secho(f"error: {_one_line(exc)}", fg="red", err=True)
                sys.exit(2)
            finally:
                printer.summary()


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="framefree")
@click.option("--debug", is_flag=True, help="Show the full traceback of an error.")
def cli(debug: bool) -> None:
    """Recognize hand-held 6-DoF motion gestures without calibrating any reference frame.

    \b
    Pose files are CSV without header, 8 columns: t [s], x, y, z [m], qw, qx, qy, qz.
    Errors in the input are reported in one line (exit status 2); --debug shows the traceback.
    Run `framefree COMMAND --help` for the options of a command.
    """



def main() -> None:
    """Console-script entry point."""
    cli(prog_name="framefree")


if __name__ == "__main__":
    main()
