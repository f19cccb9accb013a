"""Classification off the pose path: a worker thread that runs the recognizer's decisions in order.

The pose path (acceptance, stop detection, resampling, segmentation) stays on the caller's thread
and costs a few tens of microseconds per pose. Every step that touches the spotter (a unit's
candidates classified, the pending candidate's timer, a discard after a stop) is handed to one
worker thread as a call, and the calls run one after another in the order they were made, so the
decisions are exactly those of the recognizer run inline. An event carries the time of the pose
that fired it (the source's clock), whenever the worker gets to it.

The numba kernels of the search release the GIL (``nogil``), so the pose path keeps running while
a candidate is classified. Every worker of the process takes :data:`KERNEL_LOCK` around a call:
two recognizers (two trackers) never launch parallel kernels at once, which numba's ``workqueue``
threading layer does not allow, and each classification still uses every core.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any

__all__ = ["KERNEL_LOCK", "SerialWorker"]

#: Held by a worker while it runs a call (see the module docstring).
KERNEL_LOCK = threading.Lock()


def _locked(fn: Callable[..., Any], *args: Any) -> Any:
    with KERNEL_LOCK:
        return fn(*args)


class SerialWorker:
    """Calls run one after another on one thread; results handed back in submission order.

    Parameters
    ----------
    name : str
        Thread name prefix.
    max_pending : int
        Most calls waiting or running. A caller that submits more waits until one finishes:
        the worker cannot fall behind without bound (memory stays bounded), and if it is too
        slow for the source, the source's queue absorbs it as it would inline.
    """

    def __init__(self, name: str = "framefree-classify", max_pending: int = 3000) -> None:
        if max_pending < 1:
            raise ValueError(f"max_pending must be at least 1, got {max_pending}")
        self.max_pending = int(max_pending)
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix=name)
        self._pending: deque[Future[Any]] = deque()

    def __len__(self) -> int:
        """Calls submitted whose results have not been handed back."""
        return len(self._pending)

    def submit(self, fn: Callable[..., Any], *args: Any) -> None:
        """Queue ``fn(*args)`` after every call submitted before."""
        if len(self._pending) >= self.max_pending:
            self._pending[-self.max_pending].result()  # at most max_pending unfinished
        self._pending.append(self._executor.submit(_locked, fn, *args))

    def done(self) -> list[Any]:
        """Results of the calls finished so far, oldest first, up to the first unfinished one
        (an exception raised by a call is raised here)."""
        out = []
        while self._pending and self._pending[0].done():
            out.append(self._pending.popleft().result())
        return out

    def wait(self) -> list[Any]:
        """Results of every call submitted, once all have finished, oldest first."""
        out = []
        while self._pending:
            out.append(self._pending.popleft().result())
        return out

    def close(self) -> None:
        """Finish the calls submitted, then stop the thread."""
        try:
            self.wait()
        finally:
            self._executor.shutdown(wait=True)
