"""OSC event output (python-osc): one UDP message per event to ``osc://HOST:PORT/ADDRESS``.

Message arguments, in order: ``label`` (string), ``time`` (float, s on the source's clock),
``distance`` (float, -1 for a stop signal), ``threshold`` (float, -1 for a stop signal). The host
is whatever the user names (Wekinator, Max/MSP, TouchDesigner listen on 127.0.0.1 by default);
nothing is sent to a broadcast address: python-osc's client does not enable broadcast.
"""

from __future__ import annotations

import ipaddress
from typing import Any

from ..errors import FramefreeError

__all__ = ["OscEmitter", "parse_osc_spec"]

_MISSING = "OSC output needs python-osc: pip install 'framefree[osc]'"


def parse_osc_spec(spec: str) -> tuple[str, int, str]:
    """``osc://HOST:PORT/ADDRESS`` -> ``(host, port, address)``; default address ``/framefree/event``."""
    rest = spec[len("osc://"):] if spec.startswith("osc://") else spec
    hostport, slash, path = rest.partition("/")
    host, sep, port = hostport.rpartition(":")
    if not sep or not port.isdigit() or not host or not 0 < int(port) < 65536:
        raise FramefreeError(f"--emit {spec}: expected osc://HOST:PORT/ADDRESS "
                             "(e.g. osc://127.0.0.1:9000/gesture)")
    host = host.strip("[]")
    try:
        ip = ipaddress.ip_address(host)
    except ValueError:
        ip = None
    if ip is not None and (ip.is_multicast or str(ip).endswith(".255") or ip.is_unspecified):
        raise FramefreeError(f"--emit {spec}: broadcast, multicast and unspecified addresses "
                             "are refused")
    return host, int(port), "/" + path if slash and path else "/framefree/event"


class OscEmitter:
    """Send each event record as an OSC message.

    Parameters
    ----------
    host : str
    port : int
    address : str
        OSC address pattern, e.g. ``/gesture``.
    """

    def __init__(self, host: str, port: int, address: str = "/framefree/event") -> None:
        try:
            from pythonosc.udp_client import SimpleUDPClient
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self.host, self.port, self.address = host, port, address
        self._client = SimpleUDPClient(host, port)

    @classmethod
    def from_spec(cls, spec: str) -> OscEmitter:
        """Emitter from ``osc://HOST:PORT/ADDRESS``."""
        return cls(*parse_osc_spec(spec))

    def emit(self, record: dict[str, Any]) -> None:
        """Send one record."""
        d, th = record["distance"], record["threshold"]
        self._client.send_message(self.address, [
            record["label"], float(record["time"]),
            -1.0 if d is None else float(d), -1.0 if th is None else float(th),
        ])

    def close(self) -> None:
        """Nothing to flush (UDP)."""
