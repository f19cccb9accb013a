"""Helpers of the command-line tests: run a command in-process, assert a one-line error."""

from __future__ import annotations

import socket

from click.testing import CliRunner

from framefree.cli import cli


def run(*args: object):
    """Invoke ``framefree ARGS...`` in-process; every argument is passed as a string."""
    return CliRunner().invoke(cli, [str(a) for a in args])


def one_line_error(result, *fragments: str) -> str:
    """Assert exit 2, no traceback, an ``error:`` line holding every fragment; return it."""
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    lines = [ln for ln in result.output.splitlines() if ln.startswith(("error:", "Error:"))]
    assert len(lines) == 1, result.output
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    return lines[0]


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nothing listens on right now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])
