"""Every ``framefree`` command the README and docs/ name in code exists (a named subcommand of a
group included): documentation never sends a reader to a command that is not there."""

from __future__ import annotations

import re
from pathlib import Path

import click
import pytest

from framefree.cli import cli

REPO = Path(__file__).resolve().parents[1]
DOCS = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
FENCE = re.compile(r"^```[^\n]*\n(.*?)^```", re.MULTILINE | re.DOTALL)
INLINE = re.compile(r"`([^`\n]+)`")
#: ``framefree`` then lowercase words, alternatives separated by ``/`` or ``|``
NAMED = re.compile(r"(?<![\w./-])framefree((?: (?:[/|] )?[a-z][a-z0-9_-]*)+)")


def code_of(text: str) -> list[str]:
    """Fenced blocks and inline code spans of a Markdown text."""
    blocks = FENCE.findall(text)
    rest = FENCE.sub("", text)
    return blocks + INLINE.findall(rest)


def named_commands(code: str) -> list[tuple[str, ...]]:
    """Command paths named in ``code``: ``framefree robot sim / demo`` gives ``("robot", "sim")``
    and ``("robot", "demo")``; words after a command that is not a group are its arguments."""
    found = []
    for match in NAMED.finditer(code):
        if code[:match.start()].endswith(("import ", "from ")):
            continue  # Python: the package, not the command
        words = re.findall(r"([/|] )?([a-z][a-z0-9_-]*)", match.group(1))
        path: tuple[str, ...] = ()
        for sep, word in words:
            if sep:  # a sibling of the last command
                found.append((*path[:-1], word))
                continue
            parent = _resolve(path)
            if path and not isinstance(parent, click.Group):
                break  # the arguments of a plain command
            path = (*path, word)
            found.append(path)
    return found


def _resolve(path: tuple[str, ...]) -> click.Command | None:
    cmd: click.Command | None = cli
    ctx = click.Context(cli)
    for word in path:
        if not isinstance(cmd, click.Group):
            return None
        cmd = cmd.get_command(ctx, word)
    return cmd


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: str(p.relative_to(REPO)))
def test_every_named_command_exists(doc):
    missing = sorted({" ".join(p) for code in code_of(doc.read_text())
                      for p in named_commands(code) if _resolve(p) is None})
    assert not missing, f"{doc.name} names commands that do not exist: {missing}"
