import socket
import threading

import numpy as np
import pytest

from framefree.errors import FramefreeError
from framefree.io.sources import (
    CsvReplay,
    ZmqPublisher,
    ZmqSource,
    check_loopback,
    decode_pose,
    encode_pose,
)
from framefree.online import Event
from framefree.online.evaluation import match_events


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_message_format_roundtrip():
    p, q = np.array([1.0, -2.0, 3.5]), np.array([0.5, 0.5, -0.5, 0.5])
    msg = encode_pose(1.25, p, q)
    assert len(msg) == 64
    t, p2, q2 = decode_pose(msg)
    assert t == 1.25 and np.array_equal(p, p2) and np.array_equal(q, q2)
    t, p3, _ = decode_pose(b'{"t": 2.0, "p": [1, 2, 3], "q": [1, 0, 0, 0]}')
    assert t == 2.0 and p3.tolist() == [1, 2, 3]
    assert decode_pose(b"") is None
    with pytest.raises(FramefreeError):
        decode_pose(b"garbage")


def test_only_loopback_endpoints():
    assert check_loopback("zmq://127.0.0.1:5556") == "tcp://127.0.0.1:5556"
    for bad in ("tcp://0.0.0.0:5556", "tcp://192.168.1.2:5556", "tcp://*:5556", "epgm://x", "udp://127.0.0.1:1"):
        with pytest.raises(FramefreeError):
            check_loopback(bad)


def test_zmq_roundtrip_on_loopback(kettle):
    port = _free_port()
    endpoint = f"tcp://127.0.0.1:{port}"
    n = 200
    sub = ZmqSource(endpoint, timeout=5.0)

    def publish():
        pub = ZmqPublisher(endpoint, join_wait=0.5)
        for k in range(n):
            pub.send(kettle.t[k], kettle.p[k], kettle.q[k])
        pub.end()
        pub.close()

    th = threading.Thread(target=publish, daemon=True)
    th.start()
    got = list(sub)  # stops at the end message (or after 5 s of silence)
    th.join(10)
    assert not th.is_alive()
    assert len(got) == n
    np.testing.assert_array_equal(np.array([g[0] for g in got]), kettle.t[:n])
    np.testing.assert_array_equal(np.array([g[1] for g in got]), kettle.p[:n])


def test_zmq_source_times_out():
    sub = ZmqSource(f"tcp://127.0.0.1:{_free_port()}", timeout=0.2)
    assert list(sub) == []


def test_csv_replay_paces(kettle):
    import time

    src = CsvReplay(kettle, rate=200.0)
    t0 = time.perf_counter()
    rows = [r for _, r in zip(range(41), src, strict=False)]
    assert len(rows) == 41
    assert time.perf_counter() - t0 >= 0.19
    fast = list(CsvReplay(kettle, speed=0))
    assert len(fast) == len(kettle)


class Seg:
    def __init__(self, label, a, b):
        self.label, self.start_t, self.end_t = label, a, b


def test_event_matching_rule():
    segs = [Seg("a", 1.0, 2.0), Seg("b", 5.0, 6.0), Seg("stop", 8.0, 8.5)]
    events = [
        Event("a", 1.9, 0.1, 0),  # TP (before the end)
        Event("a", 2.3, 0.1, 0),  # repeat: FP
        Event("b", 4.0, 0.1, 1),  # before the start: FP
        Event("b", 6.4, 0.1, 1),  # within tolerance: TP
        Event("a", 8.2, 0.1, 0),  # wrong label: FP
    ]
    r = match_events(events, segs, duration=60.0, tolerance=0.5)
    assert (r.tp, r.fp, r.fn) == (2, 3, 1)
    assert r.precision == pytest.approx(2 / 5)
    assert r.recall == pytest.approx(2 / 3)
    assert r.latencies == pytest.approx([-0.1, 0.4])
    assert r.nongesture_minutes == pytest.approx((60 - 1.5 - 1.5 - 1.0) / 60)


def test_per_gesture_counts_a_miss_for_the_label_and_a_false_positive_for_the_event():
    from framefree.online.evaluation import per_gesture

    segs = [Seg("a", 1.0, 2.0), Seg("b", 5.0, 6.0), Seg("stop", 8.0, 8.5)]
    events = [Event("a", 1.9, 0.1, 0), Event("a", 2.3, 0.1, 0), Event("b", 4.0, 0.1, 1),
              Event("b", 6.4, 0.1, 1), Event("a", 8.2, 0.1, 0)]
    rows = per_gesture([match_events(events, segs, duration=60.0, tolerance=0.5)] * 2)
    assert (rows["a"]["tp"], rows["a"]["fp"], rows["a"]["fn"]) == (2, 4, 0)
    assert (rows["b"]["tp"], rows["b"]["fp"], rows["b"]["fn"]) == (2, 2, 0)
    assert (rows["stop"]["tp"], rows["stop"]["fp"], rows["stop"]["fn"]) == (0, 0, 2)
    assert rows["a"]["latency_median_s"] == pytest.approx(-0.1)
    assert rows["b"]["latency_median_s"] == pytest.approx(0.4)
    assert rows["stop"]["latency_median_s"] is None


def test_timeline_draws_each_candidate_against_its_gestures_threshold(tmp_path):
    """The lower panel shows the nearest gesture's distance over that gesture's τ_g (one line at
    1); a single float threshold still works."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    from framefree.datasets import Segment
    from framefree.online.evaluation import StreamTrace, plot_timeline

    t = np.linspace(0.0, 10.0, 50)
    d = np.column_stack([1.0 + np.sin(t) ** 2, 3.0 + np.cos(t) ** 2])
    trace = StreamTrace(t, d, ["a", "b"], {"a": 0.8, "b": 2.5})
    seen = {}
    real_savefig = plt.Figure.savefig

    def spy(fig, *args, **kwargs):
        ax = fig.axes[1]
        seen["lines"] = {round(float(ln.get_ydata()[0]), 6) for ln in ax.get_lines()
                         if ln.get_linestyle() == "--" and len(ln.get_ydata())}
        seen["points"] = np.sort(np.concatenate([c.get_offsets()[:, 1] for c in ax.collections
                                                 if len(c.get_offsets())]))
        return real_savefig(fig, *args, **kwargs)

    plt.Figure.savefig = spy
    try:
        out = plot_timeline(tmp_path / "t.png", [Segment("a", 1.0, 2.0)], [], trace)
        assert out.is_file() and seen["lines"] == {1.0}
        assert np.allclose(seen["points"], np.sort(np.minimum(d[:, 0] / 0.8, d[:, 1] / 2.5)))
        plot_timeline(tmp_path / "t3.png", [], [], StreamTrace(t, d, ["a", "b"]), 1.2)
        assert np.allclose(seen["points"], np.sort(d.min(axis=1) / 1.2))
    finally:
        plt.Figure.savefig = real_savefig
