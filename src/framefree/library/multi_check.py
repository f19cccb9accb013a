"""Can these gestures of several trackers be told apart? :func:`check_takes` for a vocabulary
made with a controller in each hand.

Every take is compared with every other by the offline classifier the live
:class:`~framefree.online.multi.MultiRecognizer` uses (``NearestNeighborClassifier`` with the
library's invariance), and the report has the single-tracker check's columns and rules
(:mod:`framefree.library.check`: leave-one-out 1-NN, spread, margins, the same under changes of
world frame, grip, speed and size, takes unlike their siblings, too few takes, a gesture turning
nearly as fast as a stop signal).

What differs: a change of world frame keeps the vertical with ``invariance="gravity"`` (a turn
about it and a shift; the vertical is what that invariance relies on), and is any rotation with
``"full"``; every tracker gets the same world change and size change (about the trackers' mean
starting position: the hands keep their places relative to each other) and a grip of its own.
Stop rotations and everyday motions are single-hand probes and are not tried (their columns say
``-``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.multitrajectory import MultiTrajectory
from ..core.trajectory import Trajectory
from ..online.config import RecognizerConfig
from ..online.stop import sustained_peak_speed
from .check import (
    CheckReport,
    CheckSettings,
    GestureCheck,
    _findings,
    _loo,
    _margins,
    _most_common,
    _nearest_by_gesture,
    _perturbed_labels,
    _unlike_findings,
)
from .multi_library import MultiTakeSet
from .probes import PERIOD, random_frame

__all__ = ["MultiCheckReport", "check_multi_takes", "perturbed_multi"]


@dataclass
class MultiCheckReport(CheckReport):
    """:class:`~framefree.library.check.CheckReport` of a vocabulary of several trackers (stop and
    everyday margins are ``inf``: not probed)."""

    trackers: tuple[str, ...] = ()
    invariance: str = "gravity"

    def to_dict(self) -> dict[str, Any]:
        out = super().to_dict()
        out.update(trackers=list(self.trackers), invariance=self.invariance)
        for c in out["gestures"].values():
            c["stop_margin"] = c["everyday_margin"] = None
        return out

    def format(self) -> str:
        """A table per gesture, then the findings, as text."""
        head = (f"{'gesture':<22}{'takes':>5}{'LOO':>6}  {'nearest other':<22}{'margin':>7}  "
                f"{'changed frame/grip/speed/size':<30}")
        lines = [f"{len(self.trackers)} trackers ({', '.join(self.trackers)}), invariance "
                 f"{self.invariance}; stop and everyday probes are for one tracker and not tried",
                 head, "-" * len(head)]
        for c in self.gestures.values():
            pert = f"{c.perturbed_correct}/{c.takes} {c.perturbed_margin:5.2f}x"
            lines.append(f"{c.gesture:<22}{c.takes:>5}{f'{c.loo_correct}/{c.takes}':>6}  "
                         f"{c.nearest or '-':<22}{c.margin:>6.2f}x  {pert:<30}")
        lines.append("")
        if not self.findings:
            lines.append("no problems: every gesture is well apart from the others")
        lines += [f"{f.level.upper()}: {f.message}" for f in self.findings]
        return "\n".join(lines)


def _world(rng: np.random.Generator, up: np.ndarray, offset: float, invariance: str) -> np.ndarray:
    """A random change of world frame (4, 4): any rotation (``full``) or a turn about ``up``
    (``gravity``), and a shift of ``offset`` [m]."""
    T = random_frame(rng, offset)
    if invariance == "gravity":
        a = rng.uniform(-math.pi, math.pi)
        K = np.array([[0, -up[2], up[1]], [up[2], 0, -up[0]], [-up[1], up[0], 0]])
        T[:3, :3] = np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K
    return T


def perturbed_multi(sample: MultiTrajectory, rng: np.random.Generator, invariance: str = "gravity",
                    world_offset: float = 1.0, body_offset: float = 0.05,
                    speed_range: tuple[float, float] = (0.5, 2.0),
                    size_range: tuple[float, float] = (1.0, 1.0)) -> MultiTrajectory:
    """A take of several trackers in a random world frame, with a random grip of each tracker, at a
    random speed and size (see the module docstring).

    Parameters
    ----------
    sample : MultiTrajectory
    rng : numpy.random.Generator
    invariance : {"gravity", "full"}
        ``gravity``: the world turns about the vertical only.
    world_offset, body_offset : float
        Shift [m] of the world origin and of each tracker in the hand.
    speed_range, size_range : (float, float)
        Factors drawn log-uniformly; the time axis is divided by the speed and every tracker
        resampled at 50 Hz; positions are scaled about the trackers' mean first position.
    """
    speed = math.exp(rng.uniform(math.log(speed_range[0]), math.log(speed_range[1])))
    size = math.exp(rng.uniform(math.log(size_range[0]), math.log(size_range[1])))
    centre = np.mean([tr.p[0] for tr in sample.trackers], axis=0)
    world = _world(rng, np.asarray(sample.up), world_offset, invariance)
    out = []
    for tr in sample.trackers:
        scaled = Trajectory(tr.t, centre + size * (tr.p - centre), tr.q, source=tr.source)
        moved = scaled.transformed(world=world, body=random_frame(rng, body_offset))
        out.append(moved.time_scaled(1.0 / speed).resampled(PERIOD))
    t = out[0].t
    trackers = tuple(Trajectory(t, tr.p, tr.q, source=tr.source) for tr in out)
    return MultiTrajectory(trackers, sample.names, world[:3, :3] @ sample.up,
                           f"{sample.source} (frames changed, speed x{speed:.2f}, size x{size:.2f})")


def check_multi_takes(takes: MultiTakeSet, invariance: str = "gravity",
                      config: RecognizerConfig | None = None, settings: CheckSettings | None = None
                      ) -> MultiCheckReport:
    """Check that the gestures of a vocabulary of several trackers can be told apart.

    Parameters
    ----------
    takes : MultiTakeSet
        At least two takes per gesture for a margin.
    invariance : {"gravity", "full"}
        Of the offline classifier (the library's).
    config : RecognizerConfig, optional
        For the stop detector's window and margin (the "turns almost as fast as a stop" finding).
    settings : CheckSettings, optional

    Returns
    -------
    MultiCheckReport
        ``distances`` (M, M) are the classifier's take-to-take distances.
    """
    from ..classifier import NearestNeighborClassifier

    s = settings or CheckSettings()
    config = config or RecognizerConfig()
    rng = np.random.default_rng(s.seed)
    labels = np.array(takes.labels)
    gestures = takes.gestures
    clf = NearestNeighborClassifier(invariance=invariance).fit(list(takes.takes), list(labels))
    D = clf.distance_matrix(list(takes.takes))
    near, predicted = _loo(D, labels, gestures)
    same = near[np.arange(len(labels)), [gestures.index(g) for g in labels]]
    spread = {g: max(float(np.median(same[labels == g][np.isfinite(same[labels == g])]))
                     if np.isfinite(same[labels == g]).any() else 1e-12, 1e-12) for g in gestures}
    margins = _margins(near, labels, gestures, spread)

    copies = max(s.perturbations, 1)
    pert = [perturbed_multi(tk, rng, invariance, speed_range=s.speed_range, size_range=s.size_range)
            for tk in takes.takes for _ in range(copies)]
    Dp, owner = clf.distance_matrix(pert), np.repeat(np.arange(len(takes)), copies)
    Dp[np.arange(owner.size), owner] = np.inf
    plabels = labels[owner]
    pnear = _nearest_by_gesture(Dp, labels, gestures)
    ppred = np.array(gestures)[np.argmin(pnear, axis=1)]
    pmargins = _margins(pnear, plabels, gestures, spread)
    per_take = _perturbed_labels(ppred, labels, copies)

    checks: dict[str, GestureCheck] = {}
    for g in gestures:
        sel = labels == g
        psel = plabels == g
        peak = max(sustained_peak_speed(tr.t, tr.q, config.constants.stop_window,
                                        config.constants.stop_min_duration)
                   for k in np.flatnonzero(sel) for tr in takes.takes[k].trackers)
        checks[g] = GestureCheck(
            g, int(sel.sum()), spread[g], int((predicted[sel] == g).sum()), margins[g][0],
            margins[g][1], int((per_take[sel] == g).sum()), pmargins[g][0], pmargins[g][1],
            _most_common(ppred[psel & (ppred != g)]), math.inf, math.inf, "-", peak)
    report = MultiCheckReport(list(takes.names), list(takes.labels), D, list(predicted),
                              [str(x) for x in per_take], checks, [], takes.trackers, invariance)
    report.findings = _findings(report, s, config) + _unlike_findings(report, s)
    return report
