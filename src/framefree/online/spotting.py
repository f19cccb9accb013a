"""Segment spotting: candidate gestures from movement units, classified offline-identically.

Every time a movement unit ends (:mod:`framefree.online.segmentation`), the candidate segments that
end with it are formed: the last unit alone, the last two, ... up to ``max_units`` units, as long
as the candidate lasts at most ``max_duration`` seconds and no rest inside it is longer than
``max_pause`` (a gesture's own pause at its reversal). Each candidate is cut out of the pose buffer
with a short margin and classified exactly as the offline 1-NN classifier classifies a recording
(:class:`~framefree.online.segment_classifier.SegmentClassifier`: the same descriptor object and
the same DTW distance), so a gesture seen live gets the label it would get offline.

A candidate is *accepted* when the distance to its nearest model is below the threshold τ of that
model's gesture; its *ratio* is distance / τ. The best accepted candidate is kept pending while
the hand may still be inside a longer gesture: a later candidate that contains it and has a lower
ratio replaces it (a whole out-and-back wins over its first half). The pending candidate fires when
the hand has rested ``confirm`` seconds after it, or when the next unit ends without a better
candidate, or at the latest ``max_wait`` seconds after its end.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Sequence

import numpy as np

from .admission import GestureLimits
from .candidate import Candidate, candidate_spans, refuse_tails
from .hand_direction import (
    OFF_CONE_FACTOR,
    DirectionTable,
    farther,
    hand_direction,
    hand_turn,
    to_weigh,
    weighed,
)
from .proportions import ProportionTable, proportions
from .returns import ReturnGuard
from .segment_classifier import SegmentClassifier
from .segmentation import PoseBuffer, Unit
from .span_shape import closure, corner_count, corner_rest, travel, turn_kinds
from .vertical import verticality

__all__ = ["Candidate", "SegmentClassifier", "Spotter", "candidate_spans"]


class Spotter(GestureLimits):
    """Candidate generation, classification and the pending/fire decision.

    Parameters
    ----------
    classifier : SegmentClassifier
    model_thresholds : ndarray, shape (M,)
        τ of each model's gesture.
    max_units : int
        Most units in a candidate.
    max_duration : float
        Longest candidate [s].
    max_pause : float
        Longest rest inside a candidate [s].
    pause_ratio : float
        Longest rest inside a candidate relative to the mean duration of the units around it.
    min_pause : float
        Rest [s] always allowed inside a candidate.
    margin : int
        Uniform samples added before and after a candidate when it is cut out.
    confirm : float
        Rest [s] after a pending candidate before it fires.
    max_wait : float
        Latest firing time [s] after a pending candidate's end.
    closure_limits : ndarray, shape (M,), optional
        Largest :func:`~framefree.online.span_shape.closure` a candidate may have to be accepted
        as each model's gesture (default: no limit).
    L : float
        Scale length of the screw path [m] (for the closure).
    size_limits : ndarray, shape (M, 2), optional
        Smallest and largest size [m] a candidate may have to be accepted as each model's gesture
        (default: no limit).
    return_error : float
        How far [m of screw path] from its start a person may end a gesture that returns, whatever
        the demonstrations did: a candidate whose last pose is this close to its first passes
        the closure limit (default 0: the closure limits alone decide).
    opening_limits : ndarray, shape (M,), optional
        Smallest closure a candidate may have to be accepted as each model's gesture: an open
        stroke's candidate must not come back to its start (default: no limit).
    corner_limits : ndarray, shape (M,), optional
        Most corners a candidate may have to be accepted as each model's gesture (default: no
        limit). A *corner* is a turn of the hand's heading (:func:`~framefree.online.span_shape.turn_angle`)
        of more than ``corner_angle`` degrees between two of the candidate's units: a square
        drawn in the air has three, a circle none, whether or not its drawer hesitated.
    corner_angle : float
        Smallest turn [deg] between two units that counts as a corner.
    forbidden_turns : ndarray of int, shape (M,), optional
        :func:`~framefree.online.span_shape.turn_kinds` bits a candidate must not show to be
        accepted as each model's gesture (default: none): a triangle never turns back at a
        corner, a Z always does.
    up : ndarray, shape (3,), optional
        The world's vertical (default: unknown, no vertical limit applies).
    vertical_limits : ndarray, shape (M, 2), optional
        Smallest and largest :func:`~framefree.online.vertical.verticality` a candidate may have
        to be accepted as each model's gesture, used when ``up`` is given (default: no limit).
    one_go : ndarray of bool, shape (M,), optional
        Whether each model's gesture is drawn in one go: a candidate is accepted as such a
        gesture only if its longest rest at a corner
        (:func:`~framefree.online.span_shape.corner_rest`) lasts at most ``min_pause``
        (default: none is; only the limits above, common to all rests).
    travel_limits : ndarray, shape (M,), optional
        Shortest travel [m] of the hand's position
        (:func:`~framefree.online.span_shape.travel`) a candidate may have to be accepted as each
        model's gesture (default: no limit).
    presmooth : int
        Gaussian window [samples] of the positions before their travel is measured.
    model_gestures : sequence of str, shape (M,), optional
        The gesture of each model. When given, a pending candidate is kept when the motion goes
        on into a longer candidate of the same gesture that contains it and fits worse: the
        gesture ended where the pending candidate ends (default: each longer candidate replaces
        it, see :meth:`on_unit`).
    unseen : ndarray of bool, shape (M,), optional
        Whether each model's gesture is one the tracker does not follow
        (:func:`~framefree.online.thresholds.unseen_gestures`): no candidate is accepted as it,
        and a candidate nearest it is refused rather than given to another gesture (default:
        none).
    returns : bool
        Refuse the way back after a fired gesture as that gesture again
        (:class:`~framefree.online.returns.ReturnGuard`; default: off).
    brief_starts : bool
        Also start candidates after a rest shorter than ``rest_before`` (the speed dipped below
        the rest level): they are accepted only where no candidate after a full rest is, and
        fire only after the hand rests (``confirm``), never after ``max_wait`` alone (default:
        off).
    valley_starts : bool
        Also start candidates at a unit that follows the previous one without a rest (a speed
        minimum between two strokes, or a stroke that settled), in the tier of the brief starts
        (default: off). On real streams a gesture often begins straight out of other motion.
    direction_limits : ndarray, shape (M, 4), optional
        Each model's cone of hand directions (:mod:`~framefree.online.hand_direction`): mean
        direction (3,) in the tracker's frame and largest angle [deg], NaN for none; a candidate
        outside a model's cone counts ``OFF_CONE_FACTOR`` times farther from it (default: no
        cone).
    rotation_limits : ndarray, shape (M, 4), optional
        The same for the axis about which the hand turns
        (:func:`~framefree.online.hand_direction.hand_turn`); a candidate outside either of a
        model's cones counts ``OFF_CONE_FACTOR`` times farther from it (default: no cone).
    cone_factor : float
        How many times farther a candidate outside a cone counts (default ``OFF_CONE_FACTOR``;
        infinite, i.e. refused, for takes in a fixed frame:
        :func:`~framefree.online.hand_direction.cone_factor`).
    proportion_limits : sequence of (list of (float, float)) or None, shape (M,), optional
        Per model, the stroke length ratios a candidate with its takes' corners must keep
        (:class:`~framefree.online.proportions.ProportionTable`; default: no limit).
    """

    def __init__(
        self,
        classifier: SegmentClassifier,
        model_thresholds: np.ndarray,
        max_units: int = 3,
        max_duration: float = 6.0,
        max_pause: float = 1.0,
        margin: int = 5,
        confirm: float = 0.2,
        max_wait: float = 1.0,
        closure_limits: np.ndarray | None = None,
        L: float = 0.1,
        size_limits: np.ndarray | None = None,
        pause_ratio: float = math.inf,
        min_pause: float = 0.0,
        return_error: float = 0.0,
        opening_limits: np.ndarray | None = None,
        fire_on_motion: bool = True,
        rest_before: float = 0.0,
        corner_limits: np.ndarray | None = None,
        corner_angle: float = 60.0,
        forbidden_turns: np.ndarray | None = None,
        up: np.ndarray | None = None,
        vertical_limits: np.ndarray | None = None,
        one_go: np.ndarray | None = None,
        travel_limits: np.ndarray | None = None,
        presmooth: int = 5,
        model_gestures: Sequence[str] | None = None,
        unseen: np.ndarray | None = None,
        returns: bool = False,
        brief_starts: bool = False,
        proportion_limits: Sequence[Sequence[tuple[float, float]] | None] | None = None,
        direction_limits: np.ndarray | None = None,
        valley_starts: bool = False,
        rotation_limits: np.ndarray | None = None,
        cone_factor: float = OFF_CONE_FACTOR,
    ) -> None:
        self.classifier = classifier
        self.directions = DirectionTable(direction_limits, len(classifier.models), cone_factor)
        self.rotations = DirectionTable(rotation_limits, len(classifier.models), cone_factor)
        #: the way back after a fired gesture is refused as that gesture (None: not watched)
        self.returns = ReturnGuard() if returns else None
        n_models = len(classifier.models)
        self.proportions = ProportionTable(proportion_limits or [None] * n_models)
        self.unseen = (np.zeros(n_models, dtype=bool) if unseen is None
                       else np.asarray(unseen, dtype=bool).reshape(n_models))
        #: index of each model's gesture (M,), or None (every model a gesture of its own)
        self.model_gestures = (None if model_gestures is None else
                               np.unique(np.asarray(model_gestures), return_inverse=True)[1]
                               .reshape(n_models))
        self.travel_limits = (np.zeros(n_models) if travel_limits is None
                              else np.asarray(travel_limits, dtype=np.float64).reshape(n_models))
        self.presmooth = int(presmooth)
        self.one_go = (np.zeros(n_models, dtype=bool) if one_go is None
                       else np.asarray(one_go, dtype=bool).reshape(n_models))
        self.up = None if up is None else np.asarray(up, dtype=np.float64).reshape(3)
        self.vertical_limits = (np.tile([0.0, 1.0], (n_models, 1)) if vertical_limits is None
                                else np.asarray(vertical_limits, dtype=np.float64).reshape(n_models, 2))
        self.forbidden_turns = (np.zeros(len(classifier.models), dtype=np.int64)
                                if forbidden_turns is None
                                else np.asarray(forbidden_turns, dtype=np.int64))
        self.corner_limits = (np.full(len(classifier.models), np.inf) if corner_limits is None
                              else np.asarray(corner_limits, dtype=np.float64))
        self.corner_angle = float(corner_angle)
        #: search the candidates after an accepted one only for a better one (False: each in full)
        self.tighten = True
        self.fire_on_motion = bool(fire_on_motion)
        self.rest_before = float(rest_before)
        self.brief_starts = bool(brief_starts)
        self.valley_starts = bool(valley_starts)
        self.return_error = float(return_error)
        self.opening_limits = (np.zeros(len(classifier.models)) if opening_limits is None
                               else np.asarray(opening_limits, dtype=np.float64))
        self.model_thresholds = np.asarray(model_thresholds, dtype=np.float64)
        self.max_units = int(max_units)
        self.max_duration = float(max_duration)
        self.max_pause = float(max_pause)
        self.pause_ratio = float(pause_ratio)
        self.min_pause = float(min_pause)
        self.margin = int(margin)
        self.confirm = float(confirm)
        self.max_wait = float(max_wait)
        self.closure_limits = (np.ones(n_models) if closure_limits is None
                               else np.asarray(closure_limits, dtype=np.float64))
        self.L = float(L)
        self.size_limits = (np.tile([0.0, np.inf], (n_models, 1)) if size_limits is None
                            else np.asarray(size_limits, dtype=np.float64).reshape(n_models, 2))
        #: every candidate classified, in order, when a list is set here (a diagnosis: unbounded)
        self.log: list[Candidate] | None = None
        self.units: deque[Unit] = deque(maxlen=max(1, self.max_units))
        self.rests: deque[float] = deque(maxlen=max(1, self.max_units))  # rest [s] before each unit
        self.reset()

    def reset(self) -> None:
        """Forget units and the pending candidate."""
        self.units.clear()
        self.rests.clear()
        self._last_end_t = -math.inf
        self.pending: Candidate | None = None
        self.consumed = -1  # candidates must start after this running index
        self.last_distances: np.ndarray | None = None
        #: (end time [s], distances (M,)) of every candidate classified since the owner cleared it
        self.evaluated: list[tuple[float, np.ndarray]] = []
        if self.returns is not None:
            self.returns.reset()

    def discard_before(self, index: int) -> None:
        """Drop the pending candidate and every unit that started before ``index`` (after a stop
        signal or an event: that motion is spoken for)."""
        self.pending = None
        self.consumed = max(self.consumed, index)
        while self.units and self.units[0].start < index:
            self.units.popleft()
            self.rests.popleft()

    def candidates(self, buffer: PoseBuffer) -> list[Candidate]:
        """Classify every candidate that ends with the latest unit.

        Unless the pending candidate may fire on motion (``fire_on_motion``, which looks at every
        accepted candidate), only the best accepted one of them matters: once one is accepted with
        ratio ρ, a later one is accepted only below ρ (a tie goes to the earlier one, as
        ``min`` does), so its search may stop as soon as it cannot beat ρ. The candidate chosen
        is the one the full search chooses. Candidates that start after a full rest and those
        that start after a brief dip below the rest level (``brief_starts``) are two tiers, each
        with its own ρ: any accepted one of the first wins over the second (:meth:`on_unit`),
        and the tail of a candidate from a full rest is refused
        (:func:`~framefree.online.candidate.refuse_tails`)."""
        out: list[Candidate] = []
        bar = brief_bar = 1.0  # ratio a candidate must stay below to be accepted
        last = self.units[-1]
        after = max(self.consumed, buffer.oldest + self.margin - 1)
        for first, n in candidate_spans(list(self.units), self.max_units, self.max_duration,
                                        self.max_pause, after, self.pause_ratio, self.min_pause):
            rest = self.rests[len(self.units) - n]
            if not self.may_start_after(rest):
                continue  # it starts in the middle of a motion
            full = rest >= self.rest_before
            lo_index = max(first.start - self.margin, buffer.oldest)
            times, poses = buffer.slice(lo_index, last.end + self.margin)
            # the margin after the unit may not be in the buffer yet: cut the unit out exactly
            inner = first.start - lo_index
            inside = poses[inner:inner + last.end - first.start + 1]
            c = closure(inside, self.L)
            corners, turns = self.corners_and_turns(n)
            v = math.nan if self.up is None else verticality(inside, self.up)
            span = list(self.units)[len(self.units) - n:]
            pause = corner_rest(span, self.corner_angle)
            moved = travel(inside, self.presmooth) if self.travel_limits.any() else math.inf
            shares = (proportions(span, self.corner_angle) if self.proportions.active
                      else np.zeros(0))
            way = hand_direction(inside) if self.directions.active else None
            axis = hand_turn(inside) if self.rotations.active else None
            # each model's cones' factor (M,): outside either cone counts farther
            scale = np.maximum(self.directions.factors(way), self.rotations.factors(axis))
            tier = bar if full else brief_bar
            d, size, may_accept = self._classify(times, poses, c, tier, corners, turns, v,
                                                 pause, moved, shares, scale)
            unweighed = to_weigh(d, scale, self.exact_search(times, poses, may_accept))
            d = weighed(unweighed, scale)
            self.last_distances = d
            self.evaluated.append((last.end_t, d))
            j = int(np.argmin(d))
            ratio = float(d[j] / self.model_thresholds[j])
            ok = ratio < tier and bool(self.admissible(j, np.array([c]), np.array([size]),
                                                       corners, turns, v, pause, moved,
                                                       [shares])[0])
            outranked = ok and self.outranked(j, unweighed, scale, c, size, corners, turns, v, pause,
                                              moved, shares)
            ok = ok and not outranked
            back = (self.returns is not None
                    and self.returns.is_return(self._gesture(j), first.start, inside))
            ok = ok and not back
            if not ok and full and self.needs_exact_nearest(out, n):
                # its nearest gesture decides whether the part before it is a tail: a refused
                # candidate's pruned values are bounds, so search it in full
                d = farther(self.classifier.distances(times, poses)[0], scale)
                j = int(np.argmin(d))
                ratio = float(d[j] / self.model_thresholds[j])
            if ok and self.tighten and not self.fire_on_motion:
                bar, brief_bar = (ratio, brief_bar) if full else (bar, ratio)
            out.append(Candidate(first.start, last.end, first.start_t, last.end_t, j, float(d[j]),
                                 ratio, n, c, size, ok, corners, turns, v, pause, moved, back,
                                 full, proportions=tuple(shares.tolist()),
                                 direction=() if way is None else tuple(way.tolist()),
                                 outranked=outranked))
        return refuse_tails(out, self._gesture)

    def exact_search(self, times: np.ndarray, poses: np.ndarray, may_accept: bool
                     ) -> Callable[[], np.ndarray] | None:
        """Every model's exact distance on demand (for
        :func:`~framefree.online.hand_direction.to_weigh`) where the search was pruned and the
        candidate may be accepted; None where its distances are exact or it is refused anyway."""
        if not (self.classifier.pruning and may_accept):
            return None
        return lambda: self.classifier.distances(times, poses)[0]

    def needs_exact_nearest(self, batch: list[Candidate], n: int) -> bool:
        """Whether the candidate of ``n`` units, refused, needs its exact nearest model: the
        search is pruned and the previous candidate of ``batch`` is an accepted one of ``n - 1``
        units after a brief dip, a tail if this one is nearest the same gesture
        (:func:`~framefree.online.candidate.refuse_tails`)."""
        if not (self.classifier.pruning and batch):
            return False
        part = batch[-1]
        return part.accepted and not part.after_rest and part.n_units == n - 1

    def may_start_after(self, rest: float) -> bool:
        """Whether a candidate may start after a rest of ``rest`` [s] (0: a deep speed minimum
        between two strokes): a full rest, with ``brief_starts`` any dip below the rest level,
        and with ``valley_starts`` no rest at all."""
        return (rest >= self.rest_before or (self.brief_starts and rest > 0.0)
                or (self.valley_starts and rest <= 0.0))

    def corners_and_turns(self, n: int) -> tuple[int, int]:
        """Corners between the last ``n`` units (turns sharper than :attr:`corner_angle`) and which
        ways they turn (:func:`~framefree.online.span_shape.turn_kinds`)."""
        span = list(self.units)[len(self.units) - n:]
        return corner_count(span, self.corner_angle), turn_kinds(span, self.corner_angle)

    def _classify(self, times: np.ndarray, poses: np.ndarray, closure_: float, bar: float = 1.0,
                  corners: int = 0, turns: int = 0, vertical: float = math.nan,
                  pause: float = 0.0, moved: float = math.inf,
                  shares: np.ndarray | None = None, scale: np.ndarray | None = None
                  ) -> tuple[np.ndarray, float, bool]:
        """Distances (M,) of a candidate to the models, its size [m], and whether it may be
        accepted. Pruned, only models
        whose gesture admits the candidate's closure, size and corners can accept it, so the others get
        threshold 0, the others ``bar`` times theirs (over their cone's factor ``scale`` (M,)
        for the candidate's hand direction; None: 1), and a candidate that no gesture
        admits is not searched at all (distances ``inf``). Either way the decision is the full
        search's. The flag is False where every pruned value (a distance or a lower bound of it)
        lies at or above its model's bound: then the candidate is refused whichever model is
        nearest, and its distances stay bounds (True without pruning)."""
        clf = self.classifier
        if not clf.pruning:
            return (*clf.distances(times, poses), True)
        out = clf.describe(times, poses)
        if out is None:
            return np.full(len(clf.models), math.inf), 0.0, False
        descriptor, size = out
        admits = self.admitting_models(closure_, size, corners, turns, vertical, pause, moved,
                                       shares)
        # a model whose cone does not hold the candidate's direction must be that much nearer
        below = bar * self.model_thresholds if scale is None else bar * self.model_thresholds / scale
        accept_below = np.where(admits, below, 0.0)
        d = clf.search_described(descriptor, accept_below)
        return d, size, bool(np.any(d < accept_below))

    def add_unit(self, unit: Unit) -> None:
        """Keep a unit that ended, with the rest [s] the hand held before it."""
        self.units.append(unit)
        self.rests.append(unit.start_t - self._last_end_t)
        self._last_end_t = unit.end_t
        if self.returns is not None:
            self.returns.unit_started(unit.start)

    def _gesture(self, model: int) -> int:
        """Index of a model's gesture (the model itself where gestures are not known)."""
        return model if self.model_gestures is None else int(self.model_gestures[model])

    def on_unit(self, unit: Unit, buffer: PoseBuffer) -> Candidate | None:
        """A unit ended: update the pending candidate; return a candidate to fire now, if any."""
        self.add_unit(unit)
        classified = self.candidates(buffer)
        if self.log is not None:
            self.log.extend(classified)
        accepted = [c for c in classified if c.accepted]
        # a candidate after a full rest wins over one after a brief dip
        best = min([c for c in accepted if c.after_rest] or accepted, key=lambda c: c.ratio,
                   default=None)
        pend = self.pending
        if pend is None:
            self.pending = best
            return None
        if best is not None and best.ratio < pend.ratio:
            self.pending = best
            return None
        # the motion went on without a better candidate
        if not self.fire_on_motion:  # a gesture ends in rest: the pending one was part of more
            if not self.continues(pend, best):  # unless the same gesture only went on
                self.pending = best
            return None
        self.pending = None  # the pending one was complete
        later = [c for c in accepted if c.start > pend.end]
        self.pending = min(later, key=lambda c: c.ratio, default=None)
        return pend

    def continues(self, pending: Candidate, longer: Candidate | None) -> bool:
        """Whether ``longer``, accepted after ``pending`` without fitting better, is the same
        gesture carried on: it contains ``pending`` and its model is of the same gesture (needs
        :attr:`model_gestures`). Then the hand only moved on after the gesture, and the pending
        candidate stays; another gesture, or none, replaces it as before."""
        if self.model_gestures is None or longer is None:
            return False
        G = self.model_gestures
        return bool(G[longer.model] == G[pending.model] and longer.start <= pending.start
                    and longer.end >= pending.end)

    def step(self, t: float, resting: bool, unit: Unit | None, buffer: PoseBuffer
             ) -> Candidate | None:
        """One uniform pose at time ``t`` [s]: the unit that ended with it, if any, then the
        pending candidate's timer; return the candidate that fires, whose motion is then spoken
        for."""
        fired = self.on_unit(unit, buffer) if unit is not None else None
        if fired is None:
            fired = self.poll(t, resting)
        if fired is not None:
            self.discard_before(fired.end + 1)
            if self.returns is not None:
                _, poses = buffer.slice(fired.start, fired.end)
                self.returns.fired(self._gesture(fired.model), fired.closure, poses, fired.end,
                                   [u.start for u in self.units])
        return fired

    def poll(self, t: float, resting: bool) -> Candidate | None:
        """Called for every uniform pose: fire the pending candidate when its time has come."""
        pend = self.pending
        if pend is None:
            return None
        waited = t - pend.end_t
        rested = t - self.rest_start(pend)
        if ((resting and rested >= self.confirm)
                or (waited >= self.longest_wait(pend) and pend.after_rest)):
            self.pending = None
            return pend
        return None

    def rest_start(self, pending: Candidate) -> float:
        """Time [s] from which the confirming rest after ``pending`` counts: its end."""
        return pending.end_t

    def longest_wait(self, pending: Candidate) -> float:
        """Longest wait [s] after ``pending``'s end while the hand moves on: ``max_wait``."""
        return self.max_wait
