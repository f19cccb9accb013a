"""Event outputs for ``--emit``: one spec syntax, several transports, every event the same record.

Spec syntax (``--emit`` is repeatable):

* ``jsonl:-`` (standard output) or ``jsonl:FILE`` — one JSON object per line (:mod:`.jsonl`);
* ``osc://HOST:PORT/ADDRESS`` — an OSC message per event (:mod:`.osc`);
* ``lsl://NAME`` — an LSL marker stream named NAME (:mod:`.lsl`);
* ``ros2:///TOPIC`` — ``std_msgs/String`` JSON messages on a live ROS 2 topic (:mod:`.ros2`,
  where rclpy can be imported).

Every event becomes the record ``{"label", "time", "distance", "threshold", "model"}``: ``time`` is
on the pose source's clock [s] (the time stamps of the poses that went in), ``distance`` the
dissimilarity of the best model and ``threshold`` the gesture's decision threshold (both ``null``
for a stop signal).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Protocol

from ..errors import FramefreeError
from ..labels import STOP

__all__ = ["Emitter", "Emitters", "check_spec", "event_record", "open_emitter"]


class Emitter(Protocol):
    """What every output has: ``emit`` one event record, ``close`` at the end."""

    def emit(self, record: dict[str, Any]) -> None: ...

    def close(self) -> None: ...


def event_record(event: Any, thresholds: Mapping[str, float]) -> dict[str, Any]:
    """The transport-independent record of one event.

    Parameters
    ----------
    event : framefree.online.Event
        Anything with ``label``, ``time``, ``dissimilarity`` and ``model``.
    thresholds : mapping of str to float
        Decision threshold of each gesture (``recognizer.gesture_thresholds``).

    Returns
    -------
    dict
        ``label`` (str), ``time`` (float, seconds on the source's clock), ``distance`` and
        ``threshold`` (float, or None for a stop signal), ``model`` (int, -1 for a stop).
    """
    stop = event.label == STOP or not math.isfinite(event.dissimilarity) or event.dissimilarity < 0
    th = thresholds.get(event.label)
    return {
        "label": event.label,
        "time": float(event.time),
        "distance": None if stop else float(event.dissimilarity),
        "threshold": None if (stop or th is None) else float(th),
        "model": int(event.model),
    }


def check_spec(spec: str) -> None:
    """Raise FramefreeError for a malformed ``--emit`` spec, without opening anything."""
    if spec.startswith("osc://"):
        from .osc import parse_osc_spec

        parse_osc_spec(spec)
    elif spec.startswith("ros2://"):
        from .ros2 import parse_topic

        parse_topic(spec)
    elif spec in ("jsonl:", "lsl://") or not spec.startswith(("jsonl:", "lsl://")):
        raise FramefreeError(f"--emit {spec}: expected jsonl:-, jsonl:FILE, "
                             "osc://HOST:PORT/ADDRESS, lsl://NAME or ros2:///TOPIC")


def to_stdout(specs: list[str] | tuple[str, ...]) -> bool:
    """Whether any ``--emit`` spec writes to standard output (``jsonl:-``).

    A command that emits there sends its human-readable lines to standard error instead, so that
    standard output stays pure JSON lines for a pipe.
    """
    return any(spec == "jsonl:-" for spec in specs)


def open_emitter(spec: str) -> Emitter:
    """Output from an ``--emit`` spec; a malformed spec or a missing extra raise FramefreeError."""
    if spec.startswith("jsonl:"):
        from .jsonl import JsonlEmitter

        return JsonlEmitter(spec[len("jsonl:"):])
    if spec.startswith("osc://"):
        from .osc import OscEmitter

        return OscEmitter.from_spec(spec)
    if spec.startswith("lsl://"):
        from .lsl import LslMarkerEmitter

        return LslMarkerEmitter(spec[len("lsl://"):])
    if spec.startswith("ros2://"):
        from .ros2 import Ros2Emitter

        return Ros2Emitter(spec)
    raise FramefreeError(f"--emit {spec}: expected jsonl:-, jsonl:FILE, osc://HOST:PORT/ADDRESS, "
                         "lsl://NAME or ros2:///TOPIC")


class Emitters:
    """Several outputs fed the same events.

    Parameters
    ----------
    specs : sequence of str
        ``--emit`` specs (see the module docstring).
    thresholds : mapping of str to float
        Each gesture's decision threshold, put into every record.
    """

    def __init__(self, specs: list[str] | tuple[str, ...], thresholds: Mapping[str, float]) -> None:
        self.thresholds = dict(thresholds)
        self.outputs: list[Emitter] = []
        try:
            for s in specs:
                self.outputs.append(open_emitter(s))
        except BaseException:
            self.close()
            raise
        self.sent = 0

    def __call__(self, event: Any) -> None:
        """Send one event to every output."""
        rec = event_record(event, self.thresholds)
        for out in self.outputs:
            out.emit(rec)
        self.sent += 1

    def close(self) -> None:
        """Close every output."""
        for out in self.outputs:
            out.close()
