"""A live view of the recognizer in rerun: ``framefree live --view rerun`` / ``--save FILE.rrd``.

The view only reads what the recognizer exposes after each pose; it never changes it. Logged on
the timeline ``source_time`` (the pose source's clock, seconds):

* ``world/tracker`` — the tracker as a moving frame (axes) in 3-D, its path as points
  (``world/path``); with several trackers, ``world/<name>`` and ``world/<name>/path`` for each
  (the recognizer's ``tracker_names``);
* ``speed/motion`` — the frame-free motion speed the recognizer cuts movement units on, and
  ``speed/cut`` — a mark where a unit ended and candidates were classified;
* ``distance/<gesture>`` — the nearest model's distance of each classified candidate, beside
  ``threshold/<gesture>`` — that gesture's decision threshold (a gesture fires below it);
* ``stop/angular_speed`` and ``stop/threshold`` — the stop detector's input and its level;
* ``events`` — every event as a text log line (label, distance, threshold).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FramefreeError
from .viewer import start_viewer

__all__ = ["RerunView"]

_MISSING = "the live view needs rerun: pip install 'framefree[view]'"
TIMELINE = "source_time"


class RerunView:
    """Log a recognizer's state to rerun, to a spawned viewer or to an ``.rrd`` file.

    Parameters
    ----------
    recognizer : Recognizer
        Read after every pose (``gestures``, ``gesture_thresholds``, ``observations``,
        ``segmenter.speed``, ``stop.angular_speed``, ``stop_threshold`` where it has them).
    save : str or Path, optional
        Write the recording to this ``.rrd`` file instead of opening a viewer.
    spawn : bool
        Open a rerun viewer (ignored when ``save`` is given): one listening on ``127.0.0.1`` only,
        started by :func:`~framefree.view.viewer.start_viewer`, which fails fast with one line
        where no viewer can start (no display, say).
    port : int, optional
        The viewer's port on ``127.0.0.1`` (a viewer already listening there is reused).
    url : str, optional
        A viewer already started (``start_viewer``'s URL): connect to it instead of starting one.
    """

    #: Longest wait for the viewer to take the last data when the view closes [s]; a viewer
    #: closed early must never hold the command.
    FLUSH_TIMEOUT = 2.0
    #: The thresholds are constant lines: logged at the first pose, then at most once per this
    #: many seconds of source time, and at the last pose (logging them with every pose took
    #: half the time of ``--save``) [s]
    CONSTANT_EVERY = 0.5

    def __init__(self, recognizer: Any, save: str | Path | None = None, spawn: bool = True,
                 port: int | None = None, url: str | None = None) -> None:
        try:
            import rerun as rr
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self.rr = rr
        self.rec_ = recognizer
        self.gestures = list(recognizer.gestures)
        self._gidx = np.array([self.gestures.index(s) for s in recognizer.labels])
        self.thresholds = {g: float(v) for g, v in recognizer.gesture_thresholds.items()}
        names = tuple(getattr(recognizer, "tracker_names", ()))
        #: entity paths of each tracker's frame and path
        self.entities = ([(f"world/{n}", f"world/{n}/path") for n in names] if len(names) > 1
                         else [("world/tracker", "world/path")])
        if save is not None or not spawn:
            url = None
        elif url is None:
            url = start_viewer(port)
        self.stream = rr.RecordingStream("framefree")
        if save is not None:
            self.stream.save(str(save))
        elif url is not None:
            self.stream.connect_grpc(url)
        self._viewer = url is not None and save is None
        #: source time the constant lines were last logged at, and the last pose's time [s]
        self._constants_t = -math.inf
        self._last_t = -math.inf
        self._static()

    def _static(self) -> None:
        rr, s = self.rr, self.stream
        s.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        for g in self.thresholds:
            s.log(f"threshold/{g}", rr.SeriesLines(names=f"{g} threshold", widths=1.0), static=True)
            s.log(f"distance/{g}", rr.SeriesPoints(names=f"{g} distance", marker_sizes=4.0),
                  static=True)

    def update(self, t: float, p: np.ndarray, q: np.ndarray, events: list[Any]) -> None:
        """Log one pose (position (3,) [m], quaternion (4,) ``(w, x, y, z)``; several trackers:
        (n, 3) and (n, 4), a lost tracker's row NaN) and its events."""
        rr, s, rec = self.rr, self.stream, self.rec_
        s.set_time(TIMELINE, duration=float(t))
        P, Q = np.asarray(p, dtype=float).reshape(-1, 3), np.asarray(q, dtype=float).reshape(-1, 4)
        for (frame, path), pj, qj in zip(self.entities, P, Q, strict=True):
            if not (np.isfinite(pj).all() and np.isfinite(qj).all()):
                continue
            s.log(frame, rr.Transform3D(translation=pj, quaternion=rr.Quaternion(
                xyzw=[qj[1], qj[2], qj[3], qj[0]])), rr.TransformAxes3D(0.1))
            s.log(path, rr.Points3D([pj], radii=0.003))
        speed = getattr(getattr(rec, "segmenter", None), "speed", math.nan)
        if math.isfinite(speed):
            s.log("speed/motion", rr.Scalars(speed))
        stop = getattr(getattr(rec, "stop", None), "angular_speed", math.nan)
        if math.isfinite(stop):
            s.log("stop/angular_speed", rr.Scalars(stop))
        self._last_t = float(t)
        if not 0.0 <= t - self._constants_t < self.CONSTANT_EVERY:  # (a restarted clock too)
            self._constants(float(t))
        self._observations(getattr(rec, "observations", ()))
        self.log_events(events)

    def _constants(self, t: float) -> None:
        """The threshold lines at source time ``t`` [s]."""
        rr, s = self.rr, self.stream
        s.set_time(TIMELINE, duration=t)
        self._constants_t = t
        stop = getattr(self.rec_, "stop_threshold", None)
        if stop is not None and math.isfinite(float(stop)):
            s.log("stop/threshold", rr.Scalars(float(stop)))
        for g, th in self.thresholds.items():
            s.log(f"threshold/{g}", rr.Scalars(th))

    def log_events(self, events: list[Any]) -> None:
        """Log events as text lines at their times (also those a background classifier hands
        over only when the stream has ended)."""
        rr, s = self.rr, self.stream
        for ev in events:
            s.set_time(TIMELINE, duration=float(ev.time))
            d = ev.dissimilarity
            th = self.thresholds.get(ev.label)
            text = ev.label if d < 0 or th is None else f"{ev.label}  distance {d:.4g} ≤ threshold {th:.4g}"
            s.log("events", rr.TextLog(f"{ev.time:.2f} s  {text}",
                                       level="WARN" if ev.label == "stop" else "INFO"))

    def _observations(self, observations: Any) -> None:
        """Each classified candidate: the nearest model of each gesture, and a cut mark."""
        rr, s = self.rr, self.stream
        for when, distances in observations:
            row = np.full(len(self.gestures), np.inf)
            np.minimum.at(row, self._gidx, np.asarray(distances, dtype=float))
            s.set_time(TIMELINE, duration=float(when))
            s.log("speed/cut", rr.Scalars(0.0))
            for g, d in zip(self.gestures, row, strict=True):
                if math.isfinite(d):
                    s.log(f"distance/{g}", rr.Scalars(d))

    def close(self) -> None:
        """Flush and close the recording; a viewer gets at most :attr:`FLUSH_TIMEOUT` seconds
        (one line on stderr says when it did not take the last data)."""
        if self._constants_t < self._last_t:  # the lines reach the last pose
            self._constants(self._last_t)
        try:
            if self._viewer:
                self.stream.flush(timeout_sec=self.FLUSH_TIMEOUT)
            else:
                self.stream.flush()
        except RuntimeError as exc:  # the viewer was closed or is gone
            print(f"warning: the rerun viewer did not take the last data ({exc})",
                  file=sys.stderr)
        self.stream.disconnect()
