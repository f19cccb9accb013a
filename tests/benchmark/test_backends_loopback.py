"""Clusters framefree starts listen on 127.0.0.1 only and leave nothing behind; framefree starts
no Ray cluster (Ray listens on every interface); an unreachable scheduler fails in one line.
Dask is in the dev extra; the Ray tests run where Ray is installed."""

from __future__ import annotations

import secrets
import shutil
import socket
import tempfile
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from framefree.benchmark.backends import DaskBackend, make_backend
from framefree.errors import FramefreeError

psutil = pytest.importorskip("psutil")  # installed with dask[distributed]

LOOPBACK = {"127.0.0.1", "::1"}


def _listening_addresses(root: psutil.Process) -> set[str]:
    """Local addresses of every TCP socket in LISTEN state of ``root`` and its children."""
    addresses = set()
    for proc in [root, *root.children(recursive=True)]:
        try:
            conns = proc.net_connections(kind="inet")
        except (psutil.NoSuchProcess, psutil.AccessDenied):
            continue
        addresses |= {c.laddr.ip for c in conns if c.status == psutil.CONN_LISTEN}
    return addresses


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _square(x: int) -> int:
    return x * x


def test_local_dask_cluster_listens_on_loopback_only_without_dashboard() -> None:
    pytest.importorskip("dask.distributed")
    import dask

    temporary_before = dask.config.get("temporary-directory")
    me = psutil.Process()
    before = _listening_addresses(me)
    with make_backend("dask", jobs=1) as bk:
        assert isinstance(bk, DaskBackend)
        results = dict(bk.run(_square, [(k,) for k in range(4)]))
        assert results == {0: 0, 1: 1, 2: 4, 3: 9}
        opened = _listening_addresses(me) - before
        assert opened, "a local cluster listens somewhere"
        assert opened <= LOOPBACK, opened
        # the scheduler's HTTP endpoint (health, metrics) is on loopback too, and serves no dashboard
        port = bk.client.scheduler_info()["services"]["dashboard"]
        with pytest.raises(urllib.error.HTTPError, match="404"):
            urllib.request.urlopen(f"http://127.0.0.1:{port}/status", timeout=10)
        scratch = Path(bk._scratch.name)
        assert scratch.is_dir()
        # lock files of the scheduler and nannies go there too, not to a dask-scratch-space
        assert dask.config.get("temporary-directory") == str(scratch)
    assert not scratch.exists()
    assert dask.config.get("temporary-directory") == temporary_before
    assert "127.0.0.1" in bk.describe()


def test_unreachable_dask_scheduler_is_one_line_after_a_short_timeout() -> None:
    pytest.importorskip("dask.distributed")
    address = f"tcp://127.0.0.1:{_free_port()}"
    with pytest.raises(FramefreeError, match=rf"{address}: no Dask scheduler answered within 1 s"):
        make_backend("dask", jobs=1, address=address, timeout=1)


def test_jobs_below_one_are_rejected() -> None:
    for jobs in (0, -3):
        with pytest.raises(FramefreeError, match=f"--jobs must be at least 1.*got {jobs}"):
            make_backend("joblib", jobs=jobs)


def test_ray_backend_starts_no_cluster_of_its_own() -> None:
    ray = pytest.importorskip("ray")
    assert not ray.is_initialized()
    me = psutil.Process()
    before = _listening_addresses(me)
    children = {p.pid for p in me.children(recursive=True)}
    with pytest.raises(FramefreeError, match=r"starts no local Ray cluster.*--address"):
        make_backend("ray", jobs=1)
    assert not ray.is_initialized()
    assert _listening_addresses(me) == before
    assert {p.pid for p in me.children(recursive=True)} == children


def test_ray_backend_uses_the_session_the_caller_started(monkeypatch) -> None:
    ray = pytest.importorskip("ray")
    # a token in the environment keeps Ray from writing one into the home folder
    monkeypatch.setenv("RAY_AUTH_TOKEN", secrets.token_hex(32))
    temp = tempfile.mkdtemp(prefix="ffray-")  # short: Ray's socket paths must stay < 108 bytes
    ray.init(num_cpus=1, include_dashboard=False, log_to_driver=False, _temp_dir=temp)
    try:
        with make_backend("ray", jobs=1) as bk:
            assert dict(bk.run(abs, [(-3,), (4,)])) == {0: 3, 1: 4}
        assert ray.is_initialized()  # the caller's session is the caller's to end
    finally:
        ray.shutdown()
        shutil.rmtree(temp, ignore_errors=True)


def test_unreachable_ray_cluster_is_one_line() -> None:
    pytest.importorskip("ray")
    address = f"127.0.0.1:{_free_port()}"
    with pytest.raises(FramefreeError, match=rf"{address}: no Ray cluster answered within 1 s"):
        make_backend("ray", jobs=1, address=address, timeout=1)
