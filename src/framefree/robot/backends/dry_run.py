"""A backend that sends nothing: it logs the commands it would send and follows them ideally.

The TCP moves exactly as commanded (position integrated from the commanded velocity, orientation
set to the commanded one, gripper at its reference), so the planner runs as against a perfect
arm. A command is logged when it differs from the last logged one (state, label, velocity by
more than ``tol`` m/s, or gripper reference by more than 0.1 mm), so a log of a session is short.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from ..planner import Command

__all__ = ["DryRunBackend"]


class DryRunBackend:
    """Log the commands instead of sending them.

    Parameters
    ----------
    ee_pose : ndarray, shape (4, 4)
        Initial TCP pose [m].
    gripper_width : float
        Initial finger opening [m].
    dt : float
        Control period [s] (1 ms: libfranka's rate).
    log : str, Path or text stream, optional
        Also write every logged command as a JSON line to this file ('-': standard output) or
        open stream.
    tol : float
        Velocity change [m/s] that counts as a new command.
    """

    def __init__(self, ee_pose: np.ndarray, gripper_width: float = 0.07, dt: float = 0.001,
                 log: str | Path | TextIO | None = None, tol: float = 1e-3) -> None:
        self.dt = float(dt)
        self._T = np.array(ee_pose, dtype=float)
        self._gripper = float(gripper_width)
        self._t = 0.0
        self.tol = float(tol)
        #: every logged command: ``time``, ``velocity`` [m/s], ``gripper_width`` [m], ``state``, ``label``
        self.commands: list[dict[str, Any]] = []
        self._fh: TextIO | None = None
        self._own = False
        if hasattr(log, "write"):
            self._fh = log  # an open text stream (e.g. sys.stderr), not closed here
        elif log is not None:
            import sys

            self._own = str(log) != "-"
            self._fh = Path(log).open("w", encoding="utf-8") if self._own else sys.stdout

    @property
    def time(self) -> float:
        """Backend clock [s]."""
        return self._t

    @property
    def gripper_width(self) -> float:
        """Finger opening [m] (the last reference)."""
        return self._gripper

    def ee_pose(self) -> np.ndarray:
        """The TCP pose the commands so far would have produced, shape (4, 4)."""
        return self._T.copy()

    def apply(self, command: Command) -> None:
        """Follow ``command`` for one period, and log it when it changed."""
        rec = {"time": round(self._t, 9), "velocity": [float(v) for v in command.velocity],
               "gripper_width": float(command.gripper_width), "state": command.state,
               "label": command.label}
        last = self.commands[-1] if self.commands else None
        if (last is None or last["state"] != rec["state"] or last["label"] != rec["label"]
                or np.max(np.abs(np.subtract(last["velocity"], rec["velocity"]))) > self.tol
                or abs(last["gripper_width"] - rec["gripper_width"]) > 1e-4):
            self.commands.append(rec)
            if self._fh is not None:
                self._fh.write(json.dumps(rec) + "\n")
        self._T[:3, 3] += command.velocity * self.dt
        self._T[:3, :3] = command.orientation
        self._gripper = float(command.gripper_width)
        self._t += self.dt

    def close(self) -> None:
        """Close the log file."""
        if self._fh is not None and self._own:
            self._fh.close()
        self._fh = None
