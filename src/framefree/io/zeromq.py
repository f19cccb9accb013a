"""ZeroMQ on loopback: the pose messages, a subscriber (:class:`ZmqSource`) and a publisher
(:class:`ZmqPublisher`); :mod:`framefree.io.sources` opens them from ``zmq://`` specs.

ZeroMQ message format (PUB/SUB, one pose per message, no topic prefix)
------------------------------------------------------------------------
* **binary** (default): 64 bytes, 8 little-endian IEEE-754 float64 ``t, x, y, z, qw, qx, qy, qz``
  (``struct`` format ``"<8d"``);
* **JSON** (accepted too, for other languages): a UTF-8 object ``{"t": 1.23, "p": [x, y, z],
  "q": [qw, qx, qy, qz]}``;
* **several trackers**: binary ``t`` then ``x, y, z, qw, qx, qy, qz`` of each tracker in turn,
  ``8 + 56 n`` bytes for ``n`` trackers (one tracker is the 64-byte message above); JSON with
  one row per tracker, ``{"t": 1.23, "p": [[x, y, z], ...], "q": [[qw, qx, qy, qz], ...]}``.
  A source of several trackers takes every message with the same number of trackers (a NaN
  position: that tracker lost tracking);
* **end of stream**: an empty message (0 bytes). The subscriber stops when it receives it, or when
  no message arrives for ``timeout`` seconds.

Only loopback endpoints are accepted (``tcp://127.0.0.1:PORT``, ``tcp://localhost:PORT``,
``tcp://[::1]:PORT``, or ``ipc://`` / ``inproc://``): nothing here listens on or sends to another
machine, and nothing broadcasts or multicasts. The publisher binds, the subscriber connects (both
configurable). PUB/SUB drops messages sent before a subscriber has joined ("slow joiner"), so the
publisher waits ``join_wait`` seconds after binding before its first message.
"""

from __future__ import annotations

import json
import struct
import time
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np

from ..errors import FramefreeError

__all__ = ["MESSAGE_FORMAT", "Pose", "ZmqPublisher", "ZmqSource", "check_loopback", "decode_pose",
           "encode_pose"]

Pose = tuple[float, np.ndarray, np.ndarray]

#: ``struct`` format of a one-tracker binary pose message.
MESSAGE_FORMAT = "<8d"
_LOOPBACK = ("127.0.0.1", "localhost", "[::1]")



def check_loopback(endpoint: str) -> str:
    """Return ``endpoint`` if it stays on this machine, else raise :class:`FramefreeError`.

    Accepts ``zmq://HOST:PORT`` as an alias of ``tcp://HOST:PORT``.
    """
    if endpoint.startswith("zmq://"):
        endpoint = "tcp://" + endpoint[len("zmq://"):]
    if endpoint.startswith(("ipc://", "inproc://")):
        return endpoint
    if not endpoint.startswith("tcp://"):
        raise FramefreeError(f"{endpoint}: expected tcp://127.0.0.1:PORT (or ipc://, inproc://)")
    host, sep, port = endpoint[len("tcp://"):].rpartition(":")
    if not sep or not port.isdigit():
        raise FramefreeError(f"{endpoint}: expected tcp://127.0.0.1:PORT")
    if host not in _LOOPBACK:
        raise FramefreeError(
            f"{endpoint}: only loopback endpoints are allowed (127.0.0.1, localhost, [::1])"
        )
    return endpoint


def _attach(sock: Any, endpoint: str, bind: bool) -> None:
    """Bind or connect ``sock``; a busy port or a bad endpoint becomes a one-line error."""
    import zmq

    try:
        if bind:
            sock.bind(endpoint)
        else:
            sock.connect(endpoint)
    except zmq.ZMQError as exc:
        if exc.errno == zmq.EADDRINUSE:
            raise FramefreeError(
                f"{endpoint}: the port is already in use (another 'framefree stream'?); "
                "choose another --port"
            ) from None
        raise FramefreeError(f"{endpoint}: cannot {'bind' if bind else 'connect'} ({exc})") from None


def encode_pose(t: float, p: np.ndarray, q: np.ndarray) -> bytes:
    """Binary pose message: 64 bytes for one tracker (``p`` (3,), ``q`` (4,)), ``8 + 56 n`` for
    ``n`` trackers (``p`` (n, 3), ``q`` (n, 4))."""
    rows = np.column_stack([np.asarray(p, dtype=float).reshape(-1, 3),
                            np.asarray(q, dtype=float).reshape(-1, 4)])
    return struct.pack(f"<{1 + rows.size}d", float(t), *rows.ravel().tolist())


def decode_pose(msg: bytes) -> Pose | None:
    """Decode a binary or JSON pose message; ``None`` for the end-of-stream message. One tracker:
    ``p`` (3,), ``q`` (4,); several: ``p`` (n, 3), ``q`` (n, 4).

    Raises
    ------
    FramefreeError
        If the message is neither format.
    """
    if len(msg) == 0:
        return None
    if len(msg) == struct.calcsize(MESSAGE_FORMAT):
        v = struct.unpack(MESSAGE_FORMAT, msg)
        return v[0], np.array(v[1:4]), np.array(v[4:8])
    if msg[:1] == b"{":
        try:
            d = json.loads(msg.decode("utf-8"))
            p, q = np.asarray(d["p"], dtype=float), np.asarray(d["q"], dtype=float)
            if p.ndim == 1:
                return float(d["t"]), p.reshape(3), q.reshape(4)
            return float(d["t"]), p.reshape(-1, 3), q.reshape(p.shape[0], 4)
        except (ValueError, KeyError, TypeError) as exc:
            raise FramefreeError(f"malformed JSON pose message: {exc}") from None
    if len(msg) > 64 and (len(msg) - 8) % 56 == 0:
        v = np.frombuffer(msg, dtype="<f8")
        rows = v[1:].reshape(-1, 7)
        return float(v[0]), rows[:, :3].copy(), rows[:, 3:].copy()
    raise FramefreeError(f"pose message of {len(msg)} bytes: expected 64 bytes '<8d' (8 + 56 "
                         "per tracker for several) or JSON")


class ZmqSource:
    """Subscribe to pose messages on a loopback endpoint.

    Parameters
    ----------
    endpoint : str
        ``tcp://127.0.0.1:PORT`` (or ``zmq://127.0.0.1:PORT``).
    bind : bool
        Bind instead of connecting (when the publisher connects).
    timeout : float or None
        Stop after this many seconds without a message (None: wait forever).
    """

    def __init__(self, endpoint: str, bind: bool = False, timeout: float | None = 5.0,
                 several: bool = False) -> None:
        import zmq

        self.endpoint = check_loopback(endpoint)
        self.timeout = timeout
        #: trackers every message must carry (several: the first message's, or :meth:`expect`'s)
        self.expected: int | None = None if several else 1
        self._first: Pose | None = None
        self._ctx = zmq.Context.instance()
        self._sock = self._ctx.socket(zmq.SUB)
        self._sock.setsockopt(zmq.SUBSCRIBE, b"")
        self._sock.setsockopt(zmq.LINGER, 0)
        _attach(self._sock, self.endpoint, bind)
        self.received = 0
        #: whether the stream ended because no message came for ``timeout`` seconds
        self.timed_out = False

    @property
    def n_trackers(self) -> int:
        """Trackers per message (before the first message of a source of several: 2 until
        :meth:`expect` or :meth:`peek` tells)."""
        return self.expected or 2

    def expect(self, n: int) -> None:
        """Every message must carry ``n`` trackers (the models'); another count is an error."""
        self.expected = int(n)

    def _receive(self, poller: Any, wait_ms: int | None) -> Pose | None:
        if not poller.poll(wait_ms):
            self.timed_out = True
            return None
        pose = decode_pose(self._sock.recv())
        if pose is None:
            return None
        have = 1 if pose[1].ndim == 1 else pose[1].shape[0]
        if self.expected is None:
            self.expected = have
        elif have != self.expected:
            raise FramefreeError(f"{self.endpoint}: a pose message of {have} tracker(s), but "
                                 f"{self.expected} are expected (every message carries the same "
                                 "trackers)")
        return pose

    def peek(self) -> int:
        """Wait for the first message (up to ``timeout``) and return how many trackers it
        carries (0: none came); iterating yields it first."""
        import zmq

        poller = zmq.Poller()
        poller.register(self._sock, zmq.POLLIN)
        self._first = self._receive(poller, None if self.timeout is None else int(1000 * self.timeout))
        return 0 if self._first is None else int(self.expected or 0)

    def __iter__(self) -> Iterator[Pose]:
        import zmq

        poller = zmq.Poller()
        poller.register(self._sock, zmq.POLLIN)
        wait_ms = None if self.timeout is None else int(1000 * self.timeout)
        try:
            if self._first is not None:
                self.received += 1
                yield self._first
                self._first = None
            while not self._sock.closed:
                pose = self._receive(poller, wait_ms)
                if pose is None:
                    return
                self.received += 1
                yield pose
        finally:
            self.close()

    def close(self) -> None:
        """Close the socket."""
        if not self._sock.closed:
            self._sock.close(0)


class ZmqPublisher:
    """Publish pose messages on a loopback endpoint (binds by default).

    Parameters
    ----------
    endpoint : str
        ``tcp://127.0.0.1:PORT``.
    bind : bool
        Bind (default) or connect.
    join_wait : float
        Seconds to wait after binding/connecting before sending (slow-joiner gap).
    fmt : {"binary", "json"}
        Message format.
    """

    def __init__(self, endpoint: str, bind: bool = True, join_wait: float = 0.5,
                 fmt: str = "binary") -> None:
        import zmq

        if fmt not in ("binary", "json"):
            raise ValueError(f"fmt must be 'binary' or 'json', got {fmt!r}")
        self.endpoint = check_loopback(endpoint)
        self.fmt = fmt
        self._sock = zmq.Context.instance().socket(zmq.PUB)
        self._sock.setsockopt(zmq.LINGER, 1000)
        try:
            _attach(self._sock, self.endpoint, bind)
        except FramefreeError:
            self._sock.close(0)
            raise
        time.sleep(join_wait)
        self.sent = 0

    def send(self, t: float, p: np.ndarray, q: np.ndarray) -> None:
        """Publish one pose: ``p`` (3,) and ``q`` (4,), or (n, 3) and (n, 4) for n trackers."""
        if self.fmt == "binary":
            msg = encode_pose(t, p, q)
        else:
            msg = json.dumps({"t": float(t), "p": np.asarray(p, dtype=float).tolist(),
                              "q": np.asarray(q, dtype=float).tolist()}).encode()
        self._sock.send(msg)
        self.sent += 1

    def end(self) -> None:
        """Send the end-of-stream message."""
        self._sock.send(b"")

    def close(self) -> None:
        """Close the socket (after up to 1 s to flush)."""
        if not self._sock.closed:
            self._sock.close()

    def publish(self, source: Iterable[Pose]) -> int:
        """Send every pose of a source, then the end message; return the count."""
        for t, p, q in source:
            self.send(t, p, q)
        self.end()
        return self.sent
