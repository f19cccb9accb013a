"""Helpers of the command-line tests: run a command in-process, assert a one-line error, a free
port on 127.0.0.1, a tiny dataset with a labelled session."""

from __future__ import annotations

import socket
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from framefree import Trajectory
from framefree.cli import cli
from framefree.replica import make_stream, save_stream, synthesize_gesture


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


def tiny_dataset(root: Path, gestures: Sequence[str], sequence: Sequence[str],
                 t0: float | None = None) -> Path:
    """Write 3 synthetic recordings per gesture (``root/<gesture>/original_1``) and a replica
    session performing ``sequence`` (``root/streams/stream.csv`` with its labels); with ``t0``
    the session's times start at ``t0`` [s] and are rounded to the nanosecond. Returns the
    session's path."""
    rng = np.random.default_rng(7)
    for g in gestures:
        d = root / g / "original_1"
        d.mkdir(parents=True)
        for k in range(3):
            synthesize_gesture(g, rng).to_csv(d / f"trial_{k + 1}.csv")
    traj, segs = make_stream(101, sequence=list(sequence))
    if t0 is not None:
        traj = Trajectory(np.rint((traj.t + t0) * 1e9) / 1e9, traj.p, traj.q, source="replica")
        segs = [replace(s, start_t=s.start_t + t0, end_t=s.end_t + t0) for s in segs]
    (root / "streams").mkdir()
    return save_stream(root / "streams" / "stream.csv", traj, segs)
