"""What the live commands do differently when the models hold several trackers.

``framefree live`` and ``framefree evaluate-stream`` build a
:class:`~framefree.online.multi.MultiRecognizer` when ``--models`` is a folder of multi-tracker
recordings (:func:`~framefree.datasets.multi_models.find_multi_models`); a stream or source then
has to bring the same trackers. Trackers are matched by name when the stream's names are the
models' names, otherwise by position (said on stderr once). Everything else — outputs, stop
signal, the per-gesture table — is the single-tracker path's.
"""

from __future__ import annotations

import time
from typing import Any

import click
import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..errors import FramefreeError

__all__ = ["check_trackers", "library_multi_recognizer", "match_trackers", "multi_recognizer",
           "n_trackers"]

#: Settings of the command line that a recognizer of several trackers does not use.
_UNUSED = ("resolution", "latency_min", "ds_scale", "hand_frame")


def n_trackers(rec: Any) -> int:
    """How many trackers a recognizer takes (1 for the single-tracker ones)."""
    return int(getattr(rec, "n_trackers", 1))


def multi_recognizer(found: Any, method: str, gestures: list[str] | None,
                     overrides: dict[str, Any], models: str, invariance: str = "gravity") -> Any:
    """A :class:`~framefree.online.multi.MultiRecognizer` over the multi-tracker model recordings
    ``found`` (a :class:`~framefree.datasets.multi_models.MultiModelSet`), warmed up."""
    from ..online.multi import MultiRecognizer

    if method != "segments":
        raise FramefreeError(f"{models}: the paper's recognizer takes one tracker; these models "
                             "have several (use --method segments)")
    given = [k for k in _UNUSED if k in overrides]
    if given:
        names = ", ".join("--" + k.replace("_", "-") for k in given)
        verb = "does" if len(given) == 1 else "do"
        raise FramefreeError(f"{names} {verb} not apply to models of several trackers")
    samples, labels = found.samples, found.labels
    if gestures:
        missing = [g for g in gestures if g not in set(labels)]
        if missing:
            raise FramefreeError(f"{models}: no model recordings of {', '.join(missing)} (it has "
                                 f"{', '.join(sorted(set(labels)))})")
        keep = [k for k, g in enumerate(labels) if g in gestures]
        samples, labels = [samples[k] for k in keep], [labels[k] for k in keep]
    if len(set(labels)) < 2:
        raise FramefreeError(f"{models}: recordings of {len(set(labels))} gesture(s); models of "
                             "several trackers need at least two gestures (each threshold is "
                             "measured against the others)")
    click.echo(found.description, err=True)
    click.echo("building the gesture models (several trackers) and calibrating ...", err=True)
    t0 = time.perf_counter()
    rec = MultiRecognizer.from_samples(samples, labels, invariance=invariance, **overrides)
    rec.warmup()
    taus = ", ".join(f"{g} {rec.gesture_thresholds[g]:.4g}" for g in rec.gestures)
    click.echo(f"{len(rec.labels)} models, {len(rec.gestures)} gestures, {rec.n_trackers} trackers "
               f"({', '.join(rec.tracker_names)}), invariance {invariance}, thresholds {taus}, stop above "
               f"{rec.stop_threshold:.3g} rad/s ({time.perf_counter() - t0:.1f} s)", err=True)
    from ..online.model_settings import smoothing_advice

    advice = smoothing_advice([tr for smp in samples for tr in smp.trackers], rec.config,
                              rec.learned_.smoothing)
    if advice is not None:
        click.echo(f"note: {advice}", err=True)
    return rec


def library_multi_recognizer(path: str) -> Any:
    """A :class:`~framefree.online.multi.MultiRecognizer` from a gesture library file of several
    trackers (``framefree enroll`` of multi-tracker takes): nothing recalibrated, warmed up."""
    from ..library.multi_library import load_multi_library

    click.echo(f"loading gesture library {path} (several trackers) ...", err=True)
    t0 = time.perf_counter()
    lib = load_multi_library(path)
    rec = lib.recognizer()
    rec.warmup()
    taus = ", ".join(f"{g} {rec.gesture_thresholds[g]:.4g}" for g in rec.gestures)
    click.echo(f"{len(rec.labels)} models, {len(rec.gestures)} gestures, {rec.n_trackers} trackers "
               f"({', '.join(rec.tracker_names)}), invariance {lib.invariance}, thresholds {taus}, "
               f"stop above {rec.stop_threshold:.3g} rad/s ({time.perf_counter() - t0:.1f} s)",
               err=True)
    return rec


def check_trackers(several: bool, have: int, where: str) -> None:
    """Before the models are built: one clear error when a stream or source of ``have`` trackers
    cannot go with the models (``several``: they hold several trackers)."""
    if have > 1 and not several:
        raise FramefreeError(f"{where}: {have} trackers, but the models have one; give models "
                             "of the same trackers (a folder of multi-tracker recordings)")
    if have == 1 and several:
        raise FramefreeError(f"{where}: 1 tracker, but the models have several; give a stream "
                             "of the same trackers (framefree's multi-tracker CSV, docs/io.md)")


def match_trackers(rec: Any, sample: Any, where: str) -> Any:
    """``sample`` with its trackers in the recognizer's order (a Trajectory for a single-tracker
    recognizer); one clear error when the numbers of trackers differ."""
    want = n_trackers(rec)
    have = sample.n_trackers if isinstance(sample, MultiTrajectory) else 1
    if want != have:
        if want == 1:
            raise FramefreeError(f"{where}: {have} trackers, but the models have one; give models "
                                 "of the same trackers (a folder of multi-tracker recordings)")
        raise FramefreeError(f"{where}: {have} tracker(s), but the models have {want} "
                             f"({', '.join(rec.tracker_names)}); give a stream of the same trackers "
                             "(framefree's multi-tracker CSV, docs/io.md)")
    if want == 1:
        return sample
    names = tuple(rec.tracker_names)
    if set(sample.names) == set(names):
        return MultiTrajectory(tuple(sample[n] for n in names), names, sample.up, sample.source)
    pairs = ", ".join(f"{a} as {b}" for a, b in zip(sample.names, names, strict=True))
    click.echo(f"{where}: tracker names differ from the models'; matched by position: {pairs}",
               err=True)
    return sample


def stacked(sample: MultiTrajectory) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Times (N,), positions (N, n_trackers, 3) and quaternions (N, n_trackers, 4)."""
    return (sample.t, np.stack([tr.p for tr in sample.trackers], axis=1),
            np.stack([tr.q for tr in sample.trackers], axis=1))
