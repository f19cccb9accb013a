"""Fixtures of the transport tests: a tiny gesture set, a replica session, and a network guard."""

from __future__ import annotations

from pathlib import Path

import pytest

from cli_helpers import tiny_dataset

GESTURES = ("go_left", "open_gripper")

#: Start of the replica session on the transports' clock [s]. LSL and ROS clocks never read 0
#: (liblsl even replaces a time stamp of 0 by "now"), and ROS stamps are whole nanoseconds: the
#: session's times are moved to start here and rounded to the nanosecond, so that the CSV, the LSL
#: stream and the bag carry bit-identical times.
T0 = 1000.0


@pytest.fixture(scope="module")
def tiny(tmp_path_factory) -> tuple[Path, Path]:
    """``(dataset folder, stream CSV)``: 3 recordings per gesture and a replica session that
    performs both gestures (with labels beside it)."""
    root = tmp_path_factory.mktemp("tiny")
    return root, tiny_dataset(root, GESTURES, [*GESTURES, *GESTURES], t0=T0)


def _counters() -> dict[str, int]:
    """Packets sent on non-loopback interfaces, and IPv4/IPv6 multicast and broadcast packets."""
    out: dict[str, int] = {}
    for line in Path("/proc/net/dev").read_text().splitlines()[2:]:
        name, _, data = line.partition(":")
        name = name.strip()
        if name != "lo":
            out[f"tx_packets:{name}"] = int(data.split()[9])
    lines = Path("/proc/net/netstat").read_text().splitlines()
    for head, vals in zip(lines[::2], lines[1::2], strict=True):
        if head.startswith("IpExt:"):
            table = dict(zip(head.split()[1:], map(int, vals.split()[1:]), strict=True))
            out["OutMcastPkts"] = table["OutMcastPkts"]
            out["OutBcastPkts"] = table["OutBcastPkts"]
    snmp6 = Path("/proc/net/snmp6")
    if snmp6.is_file():
        for line in snmp6.read_text().splitlines():
            key, *val = line.split()
            if key == "Ip6OutMcastPkts":
                out[key] = int(val[0])
    return out


@pytest.fixture
def loopback_only():
    """Fail the test if anything left this machine while it ran: no packet on a non-loopback
    interface, no multicast and no broadcast packet (counters of this network namespace)."""
    if not Path("/proc/net/dev").is_file():
        pytest.skip("no /proc/net/dev to check the network rule with")
    before = _counters()
    yield
    after = _counters()
    grew = {k: after[k] - before.get(k, 0) for k in after if after[k] != before.get(k, 0)}
    assert not grew, f"packets left loopback during the test: {grew}"
