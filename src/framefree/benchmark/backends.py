"""Execution backends: run the benchmark's pure task functions in-process, on local processes
(joblib), or on an existing Dask or Ray cluster.

Every backend has one method, :meth:`Backend.run`, taking a top-level function and a list of
argument tuples and yielding ``(index, result)`` pairs as tasks finish. The task functions of
:mod:`framefree.benchmark.protocol` are pure (arguments in, result out, no shared state), so the
same functions run unchanged on every backend. Dask and Ray are optional extras
(``pip install 'framefree[dask]'`` / ``'framefree[ray]'``) imported only when asked for.
"""

from __future__ import annotations

import os
import tempfile
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from ..errors import FramefreeError

__all__ = [
    "BACKENDS",
    "CONNECT_TIMEOUT",
    "Backend",
    "BackendUnavailableError",
    "DaskBackend",
    "JoblibBackend",
    "RayBackend",
    "SerialBackend",
    "make_backend",
]

#: argument tuples of the tasks of one call
Tasks = Sequence[tuple[Any, ...]]
#: ``(task index, result)`` pairs in completion order
Results = Iterator[tuple[int, Any]]

#: names accepted by :func:`make_backend`
BACKENDS: tuple[str, ...] = ("joblib", "dask", "ray")


class BackendUnavailableError(FramefreeError):
    """The requested backend needs an optional package that is not installed."""


def _call_indexed(index: int, fn: Callable[..., Any], args: tuple[Any, ...]) -> tuple[int, Any]:
    return index, fn(*args)


def available_cpus() -> int:
    """CPU cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


class Backend(ABC):
    """Runs independent tasks; subclasses decide where.

    Attributes
    ----------
    name : str
    jobs : int
        Parallel workers (local backends) or a hint (cluster backends).
    task_threads : int or None
        Numba threads each task should use (None: leave the worker's default).
    """

    name: str = "?"

    def __init__(self, jobs: int = 1) -> None:
        self.jobs = max(1, int(jobs))
        self.task_threads: int | None = None

    @abstractmethod
    def run(self, fn: Callable[..., Any], tasks: Tasks) -> Results:
        """Run ``fn(*args)`` for each ``args`` in ``tasks``; yield ``(index, result)`` when done."""

    def close(self) -> None:
        """Release workers or cluster connections this backend started."""
        self.closed = True

    def __enter__(self) -> Backend:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def describe(self) -> str:
        """One line for logs: the backend and its parallelism."""
        return f"{self.name} ({self.jobs} worker{'s' if self.jobs != 1 else ''})"


class SerialBackend(Backend):
    """Runs every task in this process, in order (numba kernels still use all cores)."""

    name = "serial"

    def run(self, fn: Callable[..., Any], tasks: Tasks) -> Results:
        for i, args in enumerate(tasks):
            yield i, fn(*args)


class JoblibBackend(Backend):
    """Local worker processes through joblib (loky), results as they complete.

    Each task is told to use ``cores // jobs`` numba threads so that the processes do not
    oversubscribe the machine.
    """

    name = "joblib"

    def __init__(self, jobs: int = 2) -> None:
        super().__init__(jobs)
        self.task_threads = max(1, available_cpus() // self.jobs)

    def run(self, fn: Callable[..., Any], tasks: Tasks) -> Results:
        from joblib import Parallel, delayed

        par = Parallel(n_jobs=self.jobs, return_as="generator_unordered", batch_size=1)
        yield from par(delayed(_call_indexed)(i, fn, args) for i, args in enumerate(tasks))


#: seconds to wait for a user-given cluster address before giving up
CONNECT_TIMEOUT = 10.0


class DaskBackend(Backend):
    """A Dask ``distributed`` cluster: an existing one (``address``) or a local one started here.

    A local cluster listens on 127.0.0.1 only (scheduler, workers, and the scheduler's health and
    metrics HTTP endpoint), serves no dashboard, and keeps its scratch files in a temporary folder
    removed by :meth:`close`; only a user-given ``address`` reaches further.
    """

    name = "dask"

    def __init__(
        self, jobs: int = 2, address: str | None = None, timeout: float = CONNECT_TIMEOUT
    ) -> None:
        super().__init__(jobs)
        try:
            from dask.distributed import Client
        except ImportError as exc:
            raise BackendUnavailableError(
                f"the dask backend needs the optional extra: pip install 'framefree[dask]' ({exc})"
            ) from None
        self.address = address
        self._scratch: tempfile.TemporaryDirectory | None = None
        self._config: Any = None
        if address:
            try:
                self._client = Client(address, timeout=timeout)
            except (OSError, TimeoutError) as exc:
                raise FramefreeError(
                    f"{address}: no Dask scheduler answered within {timeout:g} s ({exc}); "
                    "start one (dask scheduler) or check --address"
                ) from None
            self._owned = False
        else:
            import dask

            self._scratch = tempfile.TemporaryDirectory(prefix="framefree-dask-")
            # the scheduler and nannies keep lock files in dask's temporary directory too
            self._config = dask.config.set({"temporary-directory": self._scratch.name})
            self._client = Client(
                n_workers=self.jobs,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
                worker_dashboard_address=None,
                local_directory=self._scratch.name,
            )
            self._owned = True
            self.task_threads = max(1, available_cpus() // self.jobs)

    @property
    def client(self) -> Any:
        """The ``dask.distributed.Client``."""
        return self._client

    def run(self, fn: Callable[..., Any], tasks: Tasks) -> Results:
        from dask.distributed import as_completed

        submit = self._client.submit
        futures = [submit(_call_indexed, i, fn, args, pure=False) for i, args in enumerate(tasks)]
        for fut in as_completed(futures):
            yield fut.result()

    def close(self) -> None:
        if getattr(self, "_owned", False):
            cluster = getattr(self._client, "cluster", None)
            self._client.close()
            if cluster is not None:
                cluster.close()
            self._owned = False
        if getattr(self, "_config", None) is not None:
            self._config.__exit__(None, None, None)
            self._config = None
        if self._scratch is not None:
            self._scratch.cleanup()
            self._scratch = None

    def describe(self) -> str:
        return f"dask ({self.address or f'local cluster on 127.0.0.1, {self.jobs} workers'})"


class RayBackend(Backend):
    """An existing Ray cluster: one this process already joined (``ray.init``), or ``address``.

    framefree starts no Ray cluster itself: Ray's servers (GCS, raylet, workers) listen on every
    network interface, and framefree opens nothing beyond 127.0.0.1 unless the user names an
    address. Start one yourself (``ray start --head --node-ip-address 127.0.0.1``) and pass its
    address, or use the Dask backend, whose local cluster stays on loopback.
    """

    name = "ray"

    def __init__(
        self, jobs: int = 2, address: str | None = None, timeout: float = CONNECT_TIMEOUT
    ) -> None:
        super().__init__(jobs)
        try:
            import ray
        except ImportError as exc:
            raise BackendUnavailableError(
                f"the ray backend needs the optional extra: pip install 'framefree[ray]' ({exc})"
            ) from None
        self._ray = ray
        self._owned = not ray.is_initialized()
        self.address = address
        if self._owned:
            if not address:
                raise FramefreeError(
                    "framefree starts no local Ray cluster (Ray listens on every network "
                    "interface); start one (ray start --head --node-ip-address 127.0.0.1) and pass "
                    "--address 127.0.0.1:6379, or use --backend dask (loopback only)"
                )
            self._connect(address, timeout)
        self._remote = ray.remote(_call_indexed)

    def _connect(self, address: str, timeout: float) -> None:
        import socket

        host, _, port = address.rpartition(":")
        if host and port.isdigit():  # fail fast when nothing listens (ray.init retries for long)
            try:
                socket.create_connection((host, int(port)), timeout=timeout).close()
            except OSError as exc:
                raise FramefreeError(
                    f"{address}: no Ray cluster answered within {timeout:g} s "
                    f"({exc.strerror or exc}); start one (ray start --head) or check --address"
                ) from None
        try:
            self._ray.init(address=address, log_to_driver=False)
        except (ConnectionError, RuntimeError, ValueError) as exc:
            raise FramefreeError(f"{address}: cannot join the Ray cluster ({exc})") from None

    def run(self, fn: Callable[..., Any], tasks: Tasks) -> Results:
        ray = self._ray
        pending = [self._remote.remote(i, fn, args) for i, args in enumerate(tasks)]
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            yield ray.get(done[0])

    def close(self) -> None:
        if self._owned:
            self._ray.shutdown()
            self._owned = False

    def describe(self) -> str:
        return f"ray ({self.address or 'the cluster this process joined'})"


def make_backend(
    name: str = "joblib",
    jobs: int | None = None,
    address: str | None = None,
    timeout: float = CONNECT_TIMEOUT,
) -> Backend:
    """Create a backend.

    Parameters
    ----------
    name : {"joblib", "dask", "ray"}
    jobs : int, optional
        Workers, at least 1; default (``None``): all available cores. ``joblib`` with one job
        runs in this process.
    address : str, optional
        Scheduler address of an existing Dask or Ray cluster; without it, Dask starts a local
        cluster that listens on 127.0.0.1 only (Ray needs an address, or a ``ray.init`` done by
        the caller: see :class:`RayBackend`).
    timeout : float
        Seconds to wait for the cluster at ``address``.

    Raises
    ------
    BackendUnavailableError
        If Dask or Ray is asked for but not installed.
    FramefreeError
        For ``jobs`` below 1, an unknown backend name, an address with joblib, or a cluster
        address where nothing answers.
    """
    if jobs is not None and jobs < 1:
        raise FramefreeError(f"--jobs must be at least 1 (leave it out for all cores), got {jobs}")
    n = available_cpus() if jobs is None else int(jobs)
    key = name.lower()
    if key == "joblib":
        if address:
            raise FramefreeError("--address is only meaningful with --backend dask or ray")
        return SerialBackend(1) if n == 1 else JoblibBackend(n)
    if key == "dask":
        return DaskBackend(n, address, timeout)
    if key == "ray":
        return RayBackend(n, address, timeout)
    raise FramefreeError(f"unknown backend {name!r}; choose one of {', '.join(BACKENDS)}")
