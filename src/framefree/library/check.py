"""Can these gestures be told apart? A report on a vocabulary before it goes live.

Every take is compared with every other by the offline classifier (BILTS+ with screw-path
progress and DTW, the descriptor settings of the recognizer's configuration: :func:`descriptor_for`).

For a take ``i`` of gesture ``g``, ``same_i`` is the distance to its nearest other take of ``g``
and ``other_i(h)`` the distance to the nearest take of gesture ``h``. Leave-one-out 1-NN
recognizes the take iff ``min_h other_i(h) > same_i``.

* **spread** of ``g``: the median of ``same_i`` over its takes (how differently it is performed);
* **margin** of ``g`` against ``h``: the median over ``g``'s takes of ``other_i(h)``, divided by the
  spread of ``g`` — how much farther the other gesture lies than a repetition of the same one. The
  **nearest other gesture** is the one with the smallest margin;
* the same under random changes of world frame, grip, speed and size
  (:func:`~framefree.library.probes.perturbed`): perturbed copies of each take are compared with
  the other (original) takes; a take counts as recognized when all its copies are. The size
  change is what another person brings: a larger or smaller hand path with the same wrist turn,
  which moves gestures that differ only in *how much* they turn per distance towards each other;
* **stop**: the margin of ``g`` against fast wrist rotations
  (:func:`~framefree.library.probes.stop_rotations`), and whether ``g`` itself rotates nearly as
  fast as a stop signal (then the stop threshold, ``stop_margin`` above the fastest gesture, would
  miss slow stop signals);
* **everyday**: the margin of ``g`` against reaching and repositioning moves
  (:func:`~framefree.library.probes.everyday_motions`);
* **direction**: the margin of ``g`` against its nearest other gesture once more, between canonical
  paths that keep the vertical (:class:`~framefree.descriptors.canonical.CanonicalPath`,
  ``invariance="gravity"``). Two gestures that are close under full invariance and far apart
  there are one stroke in two directions (*swipe up*, *swipe left*): more than full invariance
  can tell apart (docs/real-people.md).

* **unlike**: whether a gesture's takes fall into two groups far apart (:attr:`CheckSettings.unlike_ratio`),
  or one take stands apart from the rest: a take that is not the gesture (the move back to the
  start of an open stroke, a false start).

A margin between gestures below :attr:`CheckSettings.fail_margin`, or more than half of a
gesture's takes recognized as another gesture, is a *problem*: the vocabulary should not go live.
A margin below :attr:`CheckSettings.warn_margin`, up to half of the takes recognized as another
gesture (outliers to re-record), a gesture close to stop signals or to everyday motion, or one that
turns nearly as fast as a stop signal is a *warning*: it will work, with lower precision or recall.
Each comes with a concrete advice.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..descriptors.base import Descriptor
from ..descriptors.canonical import CanonicalPath
from ..online.config import RecognizerConfig
from ..online.model_settings import (
    decided_smoothing,
    model_window_spacing,
    orientation_advice,
    rest_advice,
    segment_descriptor,
    smoothing_advice,
)
from ..online.smoothing import smoothed_take
from ..online.stop import sustained_peak_speed
from .probes import everyday_motions, perturbed, slowest_stop_speed, stop_rotations
from .store import TakeSet

__all__ = ["CheckReport", "CheckSettings", "Finding", "GestureCheck", "check_takes", "descriptor_for"]


@dataclass(frozen=True)
class CheckSettings:
    """What :func:`check_takes` tries and when it complains.

    Attributes
    ----------
    warn_margin, fail_margin : float
        Margins below these are a warning / a problem (ratios, see the module docstring).
    unlike_ratio : float
        A gesture's takes split into two groups (or one take and the rest) that lie this many
        times farther apart than the takes within each group are flagged: some of them are not
        the gesture (a move back to the start, a false start, another gesture).
    perturbations : int
        Perturbed copies (random frames, grip, speed and size) per take.
    speed_range : (float, float)
        Speed factors of the perturbed copies (log-uniform).
    size_range : (float, float)
        Size factors of the perturbed copies (log-uniform; 1/1.3–1.3: people's gestures differ in
        size by about ±30 %, from body size and habit, while their wrists turn as far).
    probes_per_take : int
        Stop rotations per take; everyday motions come from the first takes of each gesture.
    probe_quantile : float
        The stop and everyday margins are this quantile over the probe motions (0.1: one in ten
        ordinary motions comes that close), not their minimum, which depends on luck.
    seed : int
        Seed of every random choice (the report is deterministic).
    """

    warn_margin: float = 1.5
    fail_margin: float = 1.15
    unlike_ratio: float = 5.0
    perturbations: int = 4
    speed_range: tuple[float, float] = (0.5, 2.0)
    size_range: tuple[float, float] = (1 / 1.3, 1.3)
    probes_per_take: int = 1
    probe_quantile: float = 0.1
    seed: int = 0


@dataclass(frozen=True)
class Finding:
    """One problem or warning: ``level`` (``"problem"`` or ``"warning"``), the gesture, the advice."""

    level: str
    gesture: str
    message: str


@dataclass
class GestureCheck:
    """Per-gesture results (distances are BILTS+ DTW distances, margins are ratios)."""

    gesture: str
    takes: int
    spread: float
    loo_correct: int
    nearest: str | None
    margin: float
    perturbed_correct: int
    perturbed_nearest: str | None
    perturbed_margin: float
    perturbed_taken_for: str | None
    stop_margin: float
    everyday_margin: float
    everyday_nearest: str
    peak_speed: float


@dataclass
class CheckReport:
    """Everything :func:`check_takes` found.

    Attributes
    ----------
    names, labels : list of str
        The takes.
    distances : ndarray, shape (M, M)
        Take-to-take distances (row: query, column: model; the diagonal is 0).
    predicted : list of str
        Leave-one-out 1-NN label of each take.
    perturbed_predicted : list of str
        Label given to each take's perturbed copies: the take's own gesture if every copy was
        recognized, otherwise the gesture its copies were most often taken for.
    gestures : dict of str to GestureCheck
    findings : list of Finding
    """

    names: list[str]
    labels: list[str]
    distances: np.ndarray
    predicted: list[str]
    perturbed_predicted: list[str]
    gestures: dict[str, GestureCheck]
    findings: list[Finding] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """No problem (warnings allowed)."""
        return not any(f.level == "problem" for f in self.findings)

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly form (without the distance matrix)."""
        return {
            "ok": self.ok,
            "takes": [{"name": n, "gesture": g, "loo": p, "perturbed": pp}
                      for n, g, p, pp in zip(self.names, self.labels, self.predicted,
                                             self.perturbed_predicted, strict=True)],
            "gestures": {g: vars(c) for g, c in self.gestures.items()},
            "findings": [vars(f) for f in self.findings],
        }

    def format(self) -> str:
        """A table per gesture, then the findings, as text."""
        head = (f"{'gesture':<16}{'takes':>5}{'LOO':>6}  {'nearest other':<16}{'margin':>7}  "
                f"{'changed frame/speed/size':<25}{'stop':>6}{'everyday':>9}")
        lines = [head, "-" * len(head)]
        for c in self.gestures.values():
            pert = f"{c.perturbed_correct}/{c.takes} {c.perturbed_margin:5.2f}x"
            lines.append(f"{c.gesture:<16}{c.takes:>5}{f'{c.loo_correct}/{c.takes}':>6}  "
                         f"{c.nearest or '-':<16}{c.margin:>6.2f}x  {pert:<25}{c.stop_margin:>5.1f}x"
                         f"{c.everyday_margin:>8.1f}x")
        lines.append("")
        if not self.findings:
            lines.append("no problems: every gesture is well apart from the others, from stop signals "
                         "and from everyday motion")
        lines += [f"{f.level.upper()}: {f.message}" for f in self.findings]
        return "\n".join(lines)


def descriptor_for(config: RecognizerConfig | None = None, spacing: int | None = None
                   ) -> Descriptor:
    """The offline descriptor the recognizer classifies segments with, its windows ``spacing``
    samples apart (:func:`~framefree.online.model_settings.segment_descriptor`)."""
    return segment_descriptor(config or RecognizerConfig(), spacing)


def _nearest_by_gesture(D: np.ndarray, labels: np.ndarray, gestures: Sequence[str]) -> np.ndarray:
    """(Q, G) smallest distance of each query row to the takes of each gesture (``inf`` if none)."""
    out = np.full((D.shape[0], len(gestures)), np.inf)
    for k, g in enumerate(gestures):
        sel = labels == g
        if sel.any():
            out[:, k] = np.where(np.isfinite(D[:, sel]), D[:, sel], np.inf).min(axis=1)
    return out


def _loo(D: np.ndarray, labels: np.ndarray, gestures: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Per query row: nearest distance by gesture with the query's own take excluded (diagonal)."""
    D = D.astype(float).copy()
    np.fill_diagonal(D, np.inf)
    near = _nearest_by_gesture(D, labels, gestures)
    return near, np.array(gestures)[np.argmin(near, axis=1)]


def _margins(near: np.ndarray, labels: np.ndarray, gestures: list[str], spread: dict[str, float]
             ) -> dict[str, tuple[str | None, float]]:
    """Nearest other gesture and its margin, for each gesture."""
    out: dict[str, tuple[str | None, float]] = {}
    for g in gestures:
        rows = near[labels == g]
        best: tuple[str | None, float] = (None, math.inf)
        for h_idx, h in enumerate(gestures):
            if h == g:
                continue
            m = float(np.median(rows[:, h_idx])) / spread[g]
            if m < best[1]:
                best = (h, m)
        out[g] = best
    return out


def _probe_margin(D: np.ndarray, labels: np.ndarray, g: str, spread: float, q: float) -> float:
    """Quantile ``q`` over probe motions of the distance to the nearest take of ``g``, divided by
    ``g``'s spread."""
    sel = labels == g
    return float(np.quantile(D[:, sel].min(axis=1), q)) / spread if D.size else math.inf


def _as_recognized(takes: TakeSet, config: RecognizerConfig) -> tuple[TakeSet, float]:
    """The takes as the recognizer sees them, smoothed as it would smooth them
    (:func:`~framefree.online.model_settings.decided_smoothing`), and that smoothing [s]."""
    smoothing, _ = decided_smoothing(takes.takes, config)
    if smoothing == 0:
        return takes, 0.0
    return TakeSet(tuple(smoothed_take(tr, smoothing, config.constants.dt) for tr in takes.takes),
                   takes.labels, takes.names), smoothing


def check_takes(
    takes: TakeSet,
    config: RecognizerConfig | None = None,
    settings: CheckSettings | None = None,
    progress: bool = False,
) -> CheckReport:
    """Check that the gestures of a vocabulary can be told apart (see the module docstring).

    Parameters
    ----------
    takes : TakeSet
        At least two takes per gesture.
    config : RecognizerConfig, optional
        Recognizer settings (descriptor scale length and window; stop margin). The takes are
        smoothed as the recognizer would smooth them (``smoothing``, or the takes' noise).
    settings : CheckSettings, optional
    progress : bool
        Show progress bars.

    Returns
    -------
    CheckReport
    """
    s = settings or CheckSettings()
    config = config or RecognizerConfig()
    raw = takes.takes
    takes, smoothing = _as_recognized(takes, config)
    rng = np.random.default_rng(s.seed)
    relative = config.descriptor.relative_window
    desc = descriptor_for(config, model_window_spacing(takes.takes, config) if relative else None)
    labels = np.array(takes.labels)
    gestures = takes.gestures
    base = _describe(desc, takes.takes, progress, "descriptors")
    D = desc.distance_matrix(base, base)
    near, predicted = _loo(D, labels, gestures)
    same = near[np.arange(len(labels)), [gestures.index(g) for g in labels]]
    spread = {g: max(float(np.median(same[labels == g])), 1e-12) for g in gestures}
    margins = _margins(near, labels, gestures, spread)

    Dp, plabels = _perturbed_distances(takes, desc, base, rng, s, progress)
    pnear = _nearest_by_gesture(Dp, labels, gestures)
    ppred = np.array(gestures)[np.argmin(pnear, axis=1)]
    pmargins = _margins(pnear, plabels, gestures, spread)
    per_take = _perturbed_labels(ppred, labels, max(s.perturbations, 1))
    Ds, De, ekinds = _probe_distances(takes, desc, base, rng, s, config, progress)

    checks: dict[str, GestureCheck] = {}
    for g in gestures:
        sel = labels == g
        psel = plabels == g
        ecol = De[:, sel].min(axis=1) if De.size else np.zeros(0)
        checks[g] = GestureCheck(
            g, int(sel.sum()), spread[g], int((predicted[sel] == g).sum()), margins[g][0], margins[g][1],
            int((per_take[sel] == g).sum()), pmargins[g][0], pmargins[g][1],
            _most_common(ppred[psel & (ppred != g)]),
            _probe_margin(Ds, labels, g, spread[g], s.probe_quantile),
            _probe_margin(De, labels, g, spread[g], s.probe_quantile),
            str(ekinds[int(np.argmin(ecol))]) if ecol.size else "-",
            max(sustained_peak_speed(takes.takes[k].t, takes.takes[k].q,
                                     config.constants.stop_window,
                                     config.constants.stop_min_duration)
                for k in np.flatnonzero(sel)),
        )
    report = CheckReport(list(takes.names), list(takes.labels), D, list(predicted),
                         [str(x) for x in per_take], checks)
    report.findings = (_findings(report, s, config) + _unlike_findings(report, s)
                       + _direction_findings(takes, report, s))
    for advice in (rest_advice(takes.takes, config), orientation_advice(takes.takes),
                   smoothing_advice(raw, config, smoothing)):
        if advice is not None:
            report.findings.append(Finding("warning", "", advice))
    return report


def _two_groups(D: np.ndarray) -> tuple[np.ndarray, float]:
    """The best split of takes into two groups (2-medoids, exhaustive) and how far apart the groups
    lie: the median distance between them (for a lone take, the distance to its nearest sibling)
    over the larger of the groups' median inner distances."""
    n = D.shape[0]
    best, cost = np.zeros(n, dtype=bool), math.inf
    for a in range(n):
        for b in range(a + 1, n):
            group = D[:, b] < D[:, a]
            c = float(np.minimum(D[:, a], D[:, b]).sum())
            if c < cost and 0 < group.sum() < n:
                best, cost = group, c
    inner = [float(np.median(D[np.ix_(g, g)][~np.eye(g.sum(), dtype=bool)]))
             for g in (best, ~best) if g.sum() > 1]
    cross = D[np.ix_(best, ~best)]
    # a lone take: its nearest sibling (one far take among many is common luck)
    between = float(cross.min() if min(best.sum(), (~best).sum()) == 1 else np.median(cross))
    return best, between / max(max(inner, default=0.0), 1e-12)


def _unlike_findings(r: CheckReport, s: CheckSettings) -> list[Finding]:
    """Takes unlike their siblings: a gesture whose takes fall into two groups far apart."""
    out: list[Finding] = []
    labels, names = np.array(r.labels), np.array(r.names)
    D = 0.5 * (r.distances + r.distances.T)
    for g in r.gestures:
        idx = np.flatnonzero(labels == g)
        if idx.size < 3:
            continue
        group, ratio = _two_groups(D[np.ix_(idx, idx)])
        if ratio < s.unlike_ratio:
            continue
        small = group if group.sum() <= (~group).sum() else ~group
        odd = ", ".join(names[idx[small]])
        rest = ", ".join(names[idx[~small]])
        removal = " ".join(f"--remove {name}" for name in names[idx[small]])
        out.append(Finding("warning", g, f"the takes of {g} form two groups {ratio:.1f}x apart: "
                                         f"{odd} unlike {rest}. If {odd} are not {g} (a move back to "
                                         f"the start, a false start), remove them (framefree enroll "
                                         f"{removal}) or re-record"))
    return out


def _direction_findings(takes: TakeSet, r: CheckReport, s: CheckSettings) -> list[Finding]:
    """Gestures that full invariance confuses and keeping the vertical separates."""
    close = {g: c.nearest for g, c in r.gestures.items()
             if c.nearest is not None and (c.margin < s.warn_margin or c.loo_correct < c.takes)}
    if not close:
        return []
    path = CanonicalPath("gravity")
    seqs = [path.compute(tr) for tr in takes.takes]
    labels = np.array(takes.labels)
    gestures = takes.gestures
    near, _ = _loo(path.distance_matrix(seqs, seqs), labels, gestures)
    same = near[np.arange(len(labels)), [gestures.index(g) for g in labels]]
    out = []
    for g, h in close.items():
        spread = max(float(np.median(same[labels == g])), 1e-12)
        upright = float(np.median(near[labels == g][:, gestures.index(h)])) / spread
        if upright >= s.warn_margin:
            out.append(Finding(
                "warning", g, f"{g} and {h} differ mainly in direction: full invariance (the live "
                f"recognizer) brings them within {r.gestures[g].margin:.2f}x, keeping the vertical "
                f"{upright:.1f}x apart. Give one of them another shape for live use, or classify "
                "with --invariance gravity (docs/real-people.md)"))
    return out


def _most_common(names: np.ndarray) -> str | None:
    """The most frequent entry (the first in sorted order on a tie); ``None`` if there is none."""
    if names.size == 0:
        return None
    values, counts = np.unique(names, return_counts=True)
    return str(values[int(np.argmax(counts))])


def _perturbed_labels(ppred: np.ndarray, labels: np.ndarray, copies: int) -> np.ndarray:
    """Per take: its own gesture if all its ``copies`` consecutive perturbed copies were
    recognized, otherwise the gesture they were most often taken for."""
    out = labels.astype(object).copy()
    for k, g in enumerate(labels):
        wrong = ppred[k * copies:(k + 1) * copies]
        wrong = wrong[wrong != g]
        if wrong.size:
            out[k] = _most_common(wrong)
    return out.astype(str)


def _perturbed_distances(takes: TakeSet, desc: Descriptor, base: list[np.ndarray], rng: np.random.Generator,
                         s: CheckSettings, progress: bool) -> tuple[np.ndarray, np.ndarray]:
    """Distances (P, M) of perturbed copies of every take to the takes (its own take excluded),
    and the gesture of each copy."""
    pert = [perturbed(tr, rng, speed_range=s.speed_range, size_range=s.size_range)
            for tr in takes.takes for _ in range(s.perturbations)]
    Dp = desc.distance_matrix(_describe(desc, pert, progress, "changed frames, speed and size"), base)
    owner = np.repeat(np.arange(len(takes)), s.perturbations)
    Dp[np.arange(owner.size), owner] = np.inf
    return Dp, np.array(takes.labels)[owner]


def _probe_distances(takes: TakeSet, desc: Descriptor, base: list[np.ndarray], rng: np.random.Generator,
                     s: CheckSettings, config: RecognizerConfig, progress: bool
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Distances of stop rotations (S, M) and of everyday motions (E, M) to the takes, and the kind
    of each everyday motion."""
    labels = np.array(takes.labels)
    stops = [m for tr in takes.takes for m in stop_rotations(tr, rng, s.probes_per_take)]
    Ds = desc.distance_matrix(_describe(desc, stops, progress, "stop rotations"), base)
    everyday = [pr for g in takes.gestures for k in np.flatnonzero(labels == g)[:2]
                for pr in everyday_motions(takes.takes[k], rng, config.descriptor.L)]
    De = desc.distance_matrix(_describe(desc, [tr for _, tr in everyday], progress, "everyday motion"), base)
    return Ds, De, np.array([kind for kind, _ in everyday])


def _describe(desc: Descriptor, trajs: Sequence, progress: bool, what: str) -> list[np.ndarray]:
    from tqdm import tqdm

    return [desc.compute(tr) for tr in tqdm(trajs, desc=what, disable=not progress, leave=False)]


def _findings(r: CheckReport, s: CheckSettings, config: RecognizerConfig) -> list[Finding]:
    out: list[Finding] = []
    k = config.constants
    slowest_stop = slowest_stop_speed(k.stop_window, k.stop_min_duration)
    fastest = max(r.gestures.values(), key=lambda c: c.peak_speed).gesture

    def level(m: float) -> str | None:
        return "problem" if m < s.fail_margin else "warning" if m < s.warn_margin else None

    for g, c in r.gestures.items():
        out += _misrecognized(r, g)
        if c.takes < 3:
            out.append(Finding("warning", g, f"{g} has only {c.takes} takes: record 3–5 for a reliable "
                                             "threshold"))
        if c.nearest is not None and level(c.margin):
            out.append(Finding(level(c.margin), g, f"{g} is within {c.margin:.2f}x of {c.nearest}: make it "
                                                   "more distinct or record more takes"))
        elif c.perturbed_nearest is not None and level(c.perturbed_margin):
            out.append(Finding(level(c.perturbed_margin), g,
                               f"{g} comes within {c.perturbed_margin:.2f}x of {c.perturbed_nearest} when "
                               "frames, grip, speed or size change: make it more distinct"))
        if c.perturbed_correct < c.takes:
            out.append(_not_robust(g, c))
        if c.stop_margin < s.warn_margin:
            out.append(Finding("warning", g, f"{g} is within {c.stop_margin:.2f}x of a stop rotation "
                                             "(fast wrist back-and-forth): give it another shape"))
        if g == fastest and c.peak_speed * k.stop_margin > slowest_stop:
            out.append(Finding("warning", g, f"{g} turns almost as fast as a stop signal (sustained "
                                             f"{c.peak_speed:.1f} rad/s): the stop threshold becomes "
                                             f"{c.peak_speed * k.stop_margin:.1f} rad/s, above the "
                                             f"slowest stop signals ({slowest_stop:.1f} rad/s): "
                                             "perform it more slowly"))
        if c.everyday_margin < s.warn_margin:
            out.append(Finding("warning", g,
                               f"{g} is within {c.everyday_margin:.2f}x of everyday motion "
                               f"({c.everyday_nearest}): it may fire while the hand just moves; "
                               "add a rotation or a distinctive turn"))
    return out


def _not_robust(g: str, c: GestureCheck) -> Finding:
    """Takes whose perturbed copies are taken for another gesture."""
    other = c.perturbed_taken_for
    advice = (f" (taken for {other}): if {g} and {other} differ mainly in amount — how far the hand "
              f"goes or how far the wrist turns — other people will blur them; make {g} differ in "
              "shape, or add takes of a second person" if other else "")
    return Finding("warning", g, f"{c.takes - c.perturbed_correct} of {c.takes} takes of {g} are not "
                                 f"recognized after a change of frames, grip, speed or size{advice}")


def _misrecognized(r: CheckReport, g: str) -> list[Finding]:
    """Takes recognized as another gesture: up to half of a gesture's takes are outliers (a warning:
    re-record or remove them); more mean the gesture is not a group of its own (a problem)."""
    miss = [(n, p) for n, lab, p in zip(r.names, r.labels, r.predicted, strict=True) if lab == g and p != g]
    n = r.gestures[g].takes
    if not miss:
        return []
    others = ", ".join(sorted({p for _, p in miss}))
    if len(miss) > n / 2:
        return [Finding("problem", g, f"{len(miss)} of {n} takes of {g} are nearer to {others} than to "
                                      f"the other takes of {g}: make {g} more distinct")]
    names = [name for name, _ in miss]
    which = f"take {names[0]} is" if len(names) == 1 else f"takes {', '.join(names)} are"
    them = "it" if len(names) == 1 else "them"
    removal = " ".join(f"--remove {name}" for name in names)
    return [Finding("warning", g, f"{which} nearer to {others} than to the other takes of {g}: re-record "
                                  f"{them}, or remove {them} (framefree enroll {removal})")]
