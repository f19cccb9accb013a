"""Lab Streaming Layer: a pose inlet (``--source lsl://NAME``) and an event marker outlet
(``--emit lsl://NAME``), with liblsl kept on this machine by default.

Pose stream layout
------------------
A stream of ``float32``/``double64`` channels, **7 or 8 per tracker**, trackers one after the other:

* 7 channels: ``x, y, z, q0, q1, q2, q3`` — position [m, or ``units``], then the quaternion in
  ``quat_order`` (default ``wxyz``, scalar first; ``xyzw`` for scalar last, as ROS and Unity
  write it);
* 8 channels: the same and an eighth ``valid`` channel (0: the tracker lost tracking, the sample
  is skipped; anything else: valid).

The channel count decides: a multiple of 7 is read as 7 per tracker, else a multiple of 8 as 8
(give ``per_tracker`` when a count is a multiple of both, e.g. 56). A source yields one tracker's
poses (``lsl://NAME#INDEX``, default 0), or, for models of several trackers, every tracker at once;
:attr:`LslSource.trackers` says how many the stream carries.

Clock
-----
The time of each pose is the LSL time stamp the sender gave it (``clock="source"``), so events are
on the sender's clock; ``clock="local"`` adds liblsl's time correction, putting them on this
machine's ``pylsl.local_clock()`` (what LabRecorder aligns streams with). Marker events are pushed
with the event's time as their LSL time stamp, so in an XDF file they sit where the gesture ended.

Network scope
-------------
liblsl finds streams by multicast and broadcast on the whole local network unless configured.
Before pylsl is first imported, :func:`configure_liblsl` writes a configuration file owned by
framefree (``<tmp>/framefree-<uid>/lsl_api.cfg``) with resolve scope ``machine``, IPv6 off and the
known peer ``127.0.0.1``, and points the ``LSLAPICFG`` environment variable at it. Widening the
scope is the user's explicit choice: set ``LSLAPICFG`` to your own lsl_api.cfg (e.g. with
``ResolveScope = site``) before running framefree, and framefree leaves it alone.

liblsl's log
------------
liblsl reports the normal end of every stream, an outlet that goes while an inlet is connected to
it, as an error (``ERR| Stream transmission broke off ...; re-connecting...``, printed by the
inlet's side): the sending app decides when its outlet goes, so no order of closing on the
receiving side avoids it. framefree's configuration therefore sends liblsl's messages (errors
only) to ``<tmp>/framefree-<uid>/liblsl.log`` instead of the console; the console keeps one line
saying where that log is. An LSL problem framefree can name (no stream, a wrong layout) is still
one line of its own.
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FramefreeError

__all__ = ["LSL_CONFIG", "LslMarkerEmitter", "LslSource", "configure_liblsl", "import_pylsl",
           "lsl_config"]

_MISSING = "LSL needs pylsl: pip install 'framefree[lsl]'"

#: framefree's default liblsl configuration: discovery on this machine only.
LSL_CONFIG = """\
; written by framefree: keep Lab Streaming Layer discovery on this machine
[ports]
IPv6 = disable

[multicast]
ResolveScope = machine
MachineAddresses = {127.0.0.1}

[lab]
KnownPeers = {127.0.0.1}
"""


def lsl_config(folder: Path) -> str:
    """The configuration framefree writes: :data:`LSL_CONFIG`, and liblsl's log (errors only) in
    ``folder/liblsl.log`` rather than on the console (see the module docstring)."""
    return (f"{LSL_CONFIG}\n[log]\n; errors only, to this file: liblsl calls the normal end of a "
            f"stream an error\nlevel = -2\nfile = {folder / 'liblsl.log'}\n")


def configure_liblsl() -> Path | None:
    """Point liblsl at framefree's machine-only configuration, unless the user chose one.

    Must run before pylsl is imported (liblsl reads its configuration once, when it loads).

    Returns
    -------
    Path or None
        The configuration file in force when framefree wrote it; None when ``LSLAPICFG`` was
        already set by the user.
    """
    ours = Path(tempfile.gettempdir()) / f"framefree-{os.getuid()}" / "lsl_api.cfg"
    current = os.environ.get("LSLAPICFG")
    if current and Path(current) != ours:
        return None
    if "pylsl" in sys.modules and current is None:
        warnings.warn("pylsl was imported before framefree could configure it; liblsl may "
                      "discover streams on the whole network", stacklevel=2)
    ours.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
    text = lsl_config(ours.parent)
    if not ours.is_file() or ours.read_text() != text:
        ours.write_text(text)
    os.environ["LSLAPICFG"] = str(ours)
    return ours


def import_pylsl() -> Any:
    """Configure liblsl (see :func:`configure_liblsl`), then import and return pylsl."""
    configure_liblsl()
    try:
        import pylsl
    except ImportError:
        raise FramefreeError(_MISSING) from None
    return pylsl


def _layout(n_channels: int, per_tracker: int | None) -> int:
    if per_tracker is None:
        per_tracker = 7 if n_channels % 7 == 0 else 8 if n_channels % 8 == 0 else 0
    if per_tracker not in (7, 8) or n_channels == 0 or n_channels % per_tracker:
        raise FramefreeError(f"LSL stream of {n_channels} channels: expected 7 or 8 per tracker "
                             "(x y z and a quaternion, then an optional valid flag)")
    return per_tracker


class LslSource:
    """Poses of one tracker from an LSL stream found by name.

    Parameters
    ----------
    name : str
        The stream's name (``lsl://NAME``).
    tracker : int or None
        Which tracker of the stream (0-based); None: every tracker at once, each pose then
        positions (n, 3) and quaternions (n, 4) in the stream's order (a tracker whose valid
        flag is 0 gets NaN positions: the recognizer's gate skips and bridges it).
    quat_order : {"wxyz", "xyzw"}
        Quaternion order of the channels; poses come out scalar first.
    per_tracker : {7, 8}, optional
        Channels per tracker (default: from the channel count).
    clock : {"source", "local"}
        Time of a pose: the sender's time stamp, or it plus liblsl's time correction.
    resolve_timeout, timeout : float
        Seconds to find the stream; seconds without a sample before the source ends.
    """

    def __init__(self, name: str, tracker: int | None = 0, quat_order: str = "wxyz",
                 per_tracker: int | None = None, clock: str = "source",
                 resolve_timeout: float = 5.0, timeout: float | None = 5.0) -> None:
        if clock not in ("source", "local"):
            raise ValueError(f"clock must be 'source' or 'local', got {clock!r}")
        pylsl = import_pylsl()
        self.name, self.clock, self.timeout = name, clock, timeout
        self.tracker = None if tracker is None else int(tracker)
        found = pylsl.resolve_byprop("name", name, 1, resolve_timeout)
        if not found:
            raise FramefreeError(f"lsl://{name}: no LSL stream of that name on this machine within "
                                 f"{resolve_timeout:g} s (is the sending app running?)")
        info = found[0]
        self.per_tracker = _layout(info.channel_count(), per_tracker)
        self.trackers = info.channel_count() // self.per_tracker
        self.n_trackers = self.trackers if self.tracker is None else 1
        if self.tracker is not None and not 0 <= self.tracker < self.trackers:
            raise FramefreeError(f"lsl://{name}#{tracker}: the stream carries {self.trackers} "
                                 "tracker(s), numbered from 0")
        self._order = [3, 0, 1, 2] if quat_order == "xyzw" else [0, 1, 2, 3]
        self._inlet = pylsl.StreamInlet(info, max_buflen=360, recover=False)
        self._inlet.open_stream(resolve_timeout)
        from pylsl.util import LostError

        self._lost = LostError
        self.received = 0
        self.timed_out = False

    def __iter__(self) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        if self.tracker is None:
            yield from self._all()
            return
        k0 = self.tracker * self.per_tracker
        for ts, sample in self._samples():
            v = np.asarray(sample[k0:k0 + self.per_tracker], dtype=float)
            if self.per_tracker == 8 and v[7] == 0:
                continue
            self.received += 1
            yield ts, v[:3].copy(), v[3:7][self._order]

    def _all(self) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        """Every tracker of each sample: positions (n, 3), quaternions (n, 4) scalar first."""
        for ts, sample in self._samples():
            v = np.asarray(sample, dtype=float).reshape(self.trackers, self.per_tracker)
            p = v[:, :3].copy()
            if self.per_tracker == 8:
                p[v[:, 7] == 0] = np.nan
            self.received += 1
            yield ts, p, v[:, 3:7][:, self._order]

    def _samples(self) -> Iterator[tuple[float, list[float]]]:
        """``(time stamp [s], the whole sample)`` until the stream is lost or times out (then
        :attr:`timed_out`); the inlet is closed at the end."""
        try:
            while True:
                try:
                    sample, ts = self._inlet.pull_sample(
                        timeout=32000000.0 if self.timeout is None else self.timeout)
                except self._lost:
                    return
                if ts is None:
                    self.timed_out = True
                    return
                if self.clock == "local":
                    ts += self._inlet.time_correction()
                yield float(ts), sample
        finally:
            self.close()

    def close(self) -> None:
        """Close the inlet."""
        if self._inlet is not None:
            self._inlet.close_stream()
            self._inlet = None


#: Seconds a marker outlet stays open after its last marker, while inlets are connected.
LINGER = 1.0


class LslMarkerEmitter:
    """An LSL marker stream (type ``Markers``, one string channel, irregular rate) of events.

    Each marker is the event record as JSON (``label``, ``time``, ``distance``, ``threshold``,
    ``model``), time-stamped with the event's time.
    """

    def __init__(self, name: str, source_id: str = "") -> None:
        if not name:
            raise FramefreeError("--emit lsl://NAME: give the marker stream a name")
        pylsl = import_pylsl()
        info = pylsl.StreamInfo(name, "Markers", 1, pylsl.IRREGULAR_RATE, pylsl.cf_string,
                                source_id or f"framefree-{name}")
        info.desc().append_child_value("framefree", "gesture events as JSON")
        self.name = name
        self._outlet = pylsl.StreamOutlet(info)
        self._last_push = -math.inf

    def wait_for_consumers(self, timeout: float) -> bool:
        """Wait until an inlet is connected (True) or ``timeout`` seconds pass (False)."""
        return bool(self._outlet.wait_for_consumers(timeout))

    def emit(self, record: dict[str, Any]) -> None:
        """Push one marker."""
        self._outlet.push_sample([json.dumps(record)], float(record["time"]))
        self._last_push = time.monotonic()

    def close(self) -> None:
        """Drop the outlet (inlets see the stream end). liblsl sends in the background: a marker
        pushed less than :data:`LINGER` seconds ago is given that long to reach connected inlets
        before the outlet goes (dropped at once, the last event of a session was lost)."""
        if self._outlet is not None and self._outlet.have_consumers():
            time.sleep(max(0.0, LINGER - (time.monotonic() - self._last_push)))
        self._outlet = None
