"""``framefree record`` from sources of several trackers: a multi-tracker CSV file (cut at once)
and live sources that bring every tracker in each pose (an LSL stream of several trackers, a
ROS 2 bag of several pose topics, ZeroMQ multi-tracker messages), cut as the rests arrive
(:class:`~framefree.library.multi_takes.MultiTakeRecorder`). Takes go to
``LIBRARY/GESTURE/trial_<k>.csv`` (multi-tracker CSV): a ``--models`` folder, and a source of
``framefree enroll``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import click

from ..errors import FramefreeError

__all__ = ["open_record_source", "record_if_several", "record_multi_file", "record_multi_live"]

#: Seconds of stream time between two looks for finished takes while recording.
_POLL_PERIOD = 0.5


class _OneTracker:
    """A source of several trackers that brings one: poses as (t, p (3,), q (4,))."""

    n_trackers = 1

    def __init__(self, source: Any) -> None:
        self.source = source

    def __iter__(self):
        for t, p, q in self.source:
            yield t, p.reshape(-1, 3)[0], q.reshape(-1, 4)[0]


def open_record_source(spec: str, timeout: float) -> Any | None:
    """A live source ``spec`` names, opened, with its number of trackers (``n_trackers``), or None
    for the sources of one tracker that ``record`` reads as before (a CSV file, a bag of one
    topic, ``lsl://NAME#K``, OpenVR): ``lsl://NAME`` brings every tracker of its stream, ZeroMQ
    those of its first message, a bag spec those it names (``BAG#/right,/left``)."""
    from ..io.sources import carries_several, open_source

    if spec.startswith("lsl://") and "#" not in spec:
        src = open_source(spec, speed=0.0, timeout=timeout, several=True)
        return src if src.n_trackers > 1 else _OneTracker(src)
    if spec.startswith(("zmq://", "tcp://", "ipc://")):
        src = open_source(spec, speed=0.0, timeout=timeout, several=True)
        if src.source.peek() == 0:
            raise FramefreeError(f"{spec}: no pose arrived within {timeout:g} s; is a publisher "
                                 "running (framefree stream FILE --port PORT)?")
        return src
    if carries_several(spec):
        return open_source(spec, speed=0.0, timeout=timeout, several=True)
    return None


def record_if_several(source: str, gesture: str, library: str, settings: Any,
                      max_takes: int | None, timeout: float, tracker_names: str | None
                      ) -> tuple[bool, Any]:
    """``framefree record`` when ``source`` carries several trackers. Returns whether it did, and
    the source already opened for one tracker (None: the caller opens it)."""
    from ..io.multicsv import has_tracker_header

    if has_tracker_header(source):
        record_multi_file(source, gesture, library, settings, max_takes)
        return True, None
    opened = open_record_source(source, timeout)
    if opened is not None and opened.n_trackers > 1:
        record_multi_live(opened, source, gesture, library, settings, max_takes, tracker_names)
        return True, None
    if tracker_names is not None:
        raise FramefreeError("--tracker-names applies to a source of several trackers")
    return False, opened


def _names(src: Any, given: str | None) -> tuple[str, ...]:
    n = int(src.n_trackers)
    if given is None:
        known = getattr(getattr(src, "traj", None), "names", None)  # a bag's topics or frames
        return tuple(known or (f"tracker_{k}" for k in range(n)))
    names = tuple(s.strip() for s in given.split(","))
    if len(names) != n or len(set(names)) != n or not all(names):
        raise FramefreeError(f"--tracker-names {given}: the source carries {n} trackers; give "
                             f"{n} different names")
    return names


def record_multi_live(src: Iterable[Any], spec: str, gesture: str, library: str, settings: Any,
                      max_takes: int | None, tracker_names: str | None = None) -> None:
    """Record takes of several trackers from a live source as the rests after them arrive."""
    from ..library.multi_takes import MultiTakeRecorder, write_multi_take

    names = _names(src, tracker_names)
    recorder = MultiTakeRecorder(names, settings)
    click.echo(f"recording {gesture!r} from {spec}, {len(names)} trackers ({', '.join(names)}), "
               "cut at the rests of their combined motion: perform it, rest a second or two, "
               "perform it again ... (Ctrl-C to stop)", err=True)
    written: list[Path] = []

    def save(found: Sequence[Any]) -> None:
        for span, take in found:
            if max_takes is not None and len(written) >= max_takes:
                return
            written.append(write_multi_take(take, library, gesture))
            click.secho(f"take {len(written)} recorded ({span.duration:.1f} s) — rest, then "
                        f"perform the next   [{written[-1]}]", fg="green", err=True)

    last = None
    try:
        for t, p, q in src:
            recorder.push(t, p, q)
            if last is None or t - last >= _POLL_PERIOD:
                last = t
                save(recorder.poll())
            if max_takes is not None and len(written) >= max_takes:
                break
    except KeyboardInterrupt:
        pass
    if max_takes is None or len(written) < max_takes:
        save(recorder.finish())
    if recorder.skipped:
        click.echo(f"{recorder.skipped} poses with a lost tracker or an old time left out", err=True)
    _done(written, gesture, library)


def record_multi_file(source: str, gesture: str, library: str, settings: Any,
                      max_takes: int | None) -> None:
    """``framefree record`` from a multi-tracker CSV: the takes, cut at the rests of the trackers'
    combined speed, written as ``LIBRARY/GESTURE/trial_<k>.csv`` (multi-tracker CSV)."""
    from ..io.multicsv import read_multi_csv
    from ..library.multi_takes import split_multi_takes, write_multi_take

    found = split_multi_takes(read_multi_csv(source), settings)[:max_takes]
    click.echo(f"recording {gesture!r} from {source} ({len(found[0][1].names) if found else 0} "
               "trackers, cut at the rests of their combined motion)", err=True)
    written = []
    for k, (span, take) in enumerate(found, start=1):
        written.append(write_multi_take(take, library, gesture))
        click.secho(f"take {k} recorded ({span.duration:.1f} s)   [{written[-1]}]", fg="green",
                    err=True)
    _done(written, gesture, library)


def _done(written: list[Path], gesture: str, library: str) -> None:
    folder = Path(library) / gesture
    total = len(list(folder.glob("*.csv"))) if folder.is_dir() else 0
    click.echo(f"{len(written)} takes of {gesture} written to {folder} ({total} there now). "
               f"Next: framefree enroll {library} -o {Path(library).name}.npz, or "
               f"framefree live --models {library} --source ...", err=True)
    if not written:
        raise click.ClickException("no take found: perform the gesture between rests of about a second")
