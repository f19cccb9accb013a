"""Start a local rerun viewer that listens on loopback only, or fail fast with one line.

``rerun.spawn`` starts the viewer with its default bind address (``0.0.0.0``: every network
interface) and, when the viewer cannot open a window, waits several seconds and leaves a logging
stream that blocks on flush. Here the viewer is started as ``rerun --bind 127.0.0.1 --port PORT``
and watched: the call returns once the viewer accepts connections on ``127.0.0.1:PORT``, and
raises :class:`~framefree.errors.FramefreeError` (one line, the viewer's own reason) as soon as the
viewer exits, or when it has not come up within ``wait`` seconds. A viewer already listening on
the port is reused, as ``rerun.spawn`` does. Waiting sleeps in short steps, so Ctrl-C is always
honoured (the half-started viewer is then ended).
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from ..errors import FramefreeError

__all__ = ["DEFAULT_PORT", "LOOPBACK", "has_display", "start_viewer", "viewer_command"]

LOOPBACK = "127.0.0.1"
DEFAULT_PORT = 9876
_SAVE_HINT = ("record with --save FILE.rrd instead and open it where there is a screen "
              "(rerun --bind 127.0.0.1 FILE.rrd)")


def has_display(environ: dict[str, str] | None = None) -> bool:
    """Whether a window can be opened: on Linux a ``DISPLAY`` or Wayland socket must be named.

    Parameters
    ----------
    environ : dict, optional
        The environment to read (default: ``os.environ``).
    """
    env = os.environ if environ is None else environ
    if not sys.platform.startswith("linux"):
        return True
    return any(env.get(k) for k in ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"))


def _executable() -> str:
    """The ``rerun`` program rerun-sdk installed (the binary itself, not the Python launcher in
    ``bin/``, so that ending it ends the viewer), else ``rerun`` on PATH."""
    spec = importlib.util.find_spec("rerun_cli")
    name = "rerun.exe" if os.name == "nt" else "rerun"
    here = Path(spec.origin).parent / name if spec is not None and spec.origin else None
    found = str(here) if here is not None and here.exists() else shutil.which("rerun")
    if found is None:
        raise FramefreeError("--view rerun: the rerun viewer program was not found; "
                             "pip install 'framefree[view]'")
    return found


def viewer_command(port: int = DEFAULT_PORT, executable: str | None = None) -> list[str]:
    """The command line of a viewer whose gRPC server listens on ``127.0.0.1:port`` only."""
    return [executable or _executable(), "--bind", LOOPBACK, "--port", str(int(port)),
            "--hide-welcome-screen"]


def _listening(port: int) -> bool:
    """Whether something accepts TCP connections on ``127.0.0.1:port``."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.settimeout(0.2)
        return s.connect_ex((LOOPBACK, port)) == 0


def _last_line(path: Path) -> str:
    """The viewer's last meaningful output line (its reason for exiting), stripped of colours."""
    text = path.read_text(errors="replace") if path.exists() else ""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    errors = [ln for ln in lines if "error" in ln.lower()] or lines
    line = errors[-1] if errors else "no output"
    line = re.sub(r"os error at \S+: ", "", line)  # the viewer's source location
    while "\x1b[" in line:
        start = line.index("\x1b[")
        end = line.find("m", start)
        line = line[:start] + (line[end + 1:] if end >= 0 else "")
    return line[:300]


def start_viewer(port: int | None = None, wait: float = 15.0,
                 executable: str | None = None) -> str:
    """Start (or reuse) a rerun viewer on loopback; return the URL a recording connects to.

    Parameters
    ----------
    port : int, optional
        TCP port of the viewer's gRPC server on ``127.0.0.1`` (default :data:`DEFAULT_PORT`).
    wait : float
        Seconds the viewer may take to accept connections before it is given up [s].
    executable : str, optional
        The ``rerun`` program (default: the one rerun-sdk installed).

    Returns
    -------
    str
        ``rerun+http://127.0.0.1:PORT/proxy``.

    Raises
    ------
    FramefreeError
        No display, no viewer program, or the viewer exited or did not come up in time.
    """
    port = DEFAULT_PORT if port is None else int(port)
    url = f"rerun+http://{LOOPBACK}:{port}/proxy"
    if _listening(port):
        return url
    if not has_display():
        raise FramefreeError(f"--view rerun: no display here (DISPLAY and WAYLAND_DISPLAY are "
                             f"unset); {_SAVE_HINT}")
    cmd = viewer_command(port, executable)
    with tempfile.TemporaryDirectory(prefix="framefree-rerun-", ignore_cleanup_errors=True) as tmp:
        log = Path(tmp) / "viewer.log"
        with log.open("wb") as fh:
            proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=fh, stderr=fh,
                                    start_new_session=True)
        try:
            reason = _wait_until_listening(proc, port, wait)
        except BaseException:  # Ctrl-C while waiting: end the half-started viewer
            _end(proc)
            raise
        if reason is not None:
            _end(proc)
            detail = _last_line(log) if reason == "exited" else f"not listening after {wait:g} s"
            raise FramefreeError(f"--view rerun: the viewer could not start ({detail}); "
                                 f"{_SAVE_HINT}")
    return url


def _wait_until_listening(proc: subprocess.Popen, port: int, wait: float,
                          grace: float = 1.0) -> str | None:
    """None once the viewer listens and is still running ``grace`` seconds later (its server
    starts before its window, which may then fail); ``"exited"`` or ``"timeout"`` otherwise."""
    deadline = time.monotonic() + wait
    up_since: float | None = None
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            return "exited"
        if up_since is None and _listening(port):
            up_since = time.monotonic()
        if up_since is not None and time.monotonic() - up_since >= grace:
            return None
        time.sleep(0.05)
    return "timeout"


def _end(proc: subprocess.Popen) -> None:
    """Stop a viewer this module started (and reap it: no defunct child is left)."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=3)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
