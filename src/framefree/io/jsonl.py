"""JSON-lines event output: one JSON object per event, to a file or standard output."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any, TextIO

from ..errors import FramefreeError

__all__ = ["JsonlEmitter"]


class JsonlEmitter:
    """Write each event record as one line of JSON (flushed at once, so a pipe sees it live).

    Parameters
    ----------
    target : str
        ``-`` for standard output, else a file path (created or truncated).
    """

    def __init__(self, target: str) -> None:
        if not target:
            raise FramefreeError("--emit jsonl: give a file or '-' for standard output (jsonl:-)")
        self.target = target
        self._own = target != "-"
        if self._own:
            path = Path(target)
            if path.is_dir():
                raise FramefreeError(f"{target}: is a folder; --emit jsonl:FILE needs a file")
            try:
                path.parent.mkdir(parents=True, exist_ok=True)
                self._fh: TextIO = path.open("w", encoding="utf-8")
            except OSError as exc:
                raise FramefreeError(f"{target}: cannot write ({exc.strerror})") from None
        else:
            self._fh = sys.stdout

    def emit(self, record: dict[str, Any]) -> None:
        """Write one record."""
        self._fh.write(json.dumps(record) + "\n")
        self._fh.flush()

    def close(self) -> None:
        """Close the file (standard output stays open)."""
        if self._own and not self._fh.closed:
            self._fh.close()
