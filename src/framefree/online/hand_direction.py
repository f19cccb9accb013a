"""Which way the hand moves and turns in the tracker's frame: evidence a frame-free descriptor
cannot see.

Frame-free recognition does not see how the tracker sits in the hand, and so cannot see which way
the hand moves relative to itself: a straight stroke to the palm's side and one to the back of the
hand are the same motion to it. Where every take and every live stream put the tracker's frame on
the hand about the same way — the palm pose of a hand tracker, a controller held by its handle —
that direction is a property of the gesture. On real continuous hand tracking (SFINGE3D) it is
what tells a swipe from a free stroke of the same shape: the dictionary's *swipe left*s all move
within 58° of one direction of the palm, and the free strokes that passed for swipes moved 72–123°
away from their class's direction, while the descriptor's distance does not separate them
(docs/online-history.md, v26).

*The hand direction* of a motion is the sum of its position steps expressed in the tracker's frame
at each step, ``Σ R_kᵀ Δp_k``, over the steps at least :data:`FAST_STEP` times as long as its
longest one (the stroke, not the noise of the rests around it), as a unit vector. A change of the
world frame (``T → W T``) leaves it unchanged; a change of the tracker's place in the hand
(``T → T G``) turns it by ``Gᵀ``.

*A gesture's cone* lies around the mean direction of its takes, learned only where the takes
agree more than random directions would: the Rayleigh test of uniformity on the sphere
(``3 n R̄²`` is χ² with 3 degrees of freedom for ``n`` uniform directions with mean resultant
length ``R̄``) must reject at :data:`SIGNIFICANCE`, and the takes must be many: at least
``SpottingConstants.cone_takes`` (20). One person's takes agree on the way they move in that
person's hand, and that agreement says nothing of how another person holds the tracker: on the
Machete right controller, a cone fitted to one person's five takes of a gesture holds 32 % of
another person's takes (its nominal coverage is 99 %), one fitted to two people's 76 %, to five
people's 94 % (docs/online-history.md, *v30*). A significance level alone cannot keep one
person's takes out: five takes never pass it (the most they reach is p = 0.0018), but ten takes
of a check mark from one person set a cone of 24–28° that other people's check marks miss. A
benchmark's dictionary of many people's examples (36 per swipe in SFINGE3D, 25 per gesture in a
Machete fold) sets its cones. The cone's half-angle is the one that holds :data:`COVERAGE` of
a von Mises–Fisher distribution fitted to the takes (concentration κ from ``R̄``, Banerjee et
al. 2005), so a gesture performed more loosely gets a wider cone than its takes' spread alone
would give.

*The hand's turn* is the same kind of evidence for rotation (v29): the axis of the largest turn
of the tracker from its first pose, expressed in that first pose's frame (the axis of
``R_0ᵀ R_k`` at the ``k`` where its angle is largest), as a unit vector, and none where the hand
turns less than :data:`MIN_TURN`. A change of the world frame leaves it unchanged, a change of
the tracker's place in the hand turns it by ``Gᵀ``, and a bi-invariant descriptor sees neither
this axis nor its sense. On SFINGE3D the dictionary's *swipe left*s turn the palm 66–123° (5–95 %)
about axes within 34° of their mean for 90 % of them (44° at most), while two motions of other
classes that fired as swipes turned it about axes 122° and 153° from their swipe's
(docs/online-history.md, v29). Its cones are learned, and weigh a candidate, as the hand
direction's: a candidate outside either of a model's cones
counts :data:`OFF_CONE_FACTOR` times farther from it.

*A sensor of positions only* (a skeleton's wrist joint, a marker; v32) writes one orientation
throughout, so the tracker never turns and its frame is the sensor's own. There the turn of the
motion is the turn of its *path* (:func:`path_turn`): the axis about which the hand's path runs
round, with its sense, from the signed area that the path sweeps. A planar gesture and its mirror
image (a circle drawn clockwise and anticlockwise, the Machete cartwheels) differ by a rotation,
which no frame-free distance sees; their paths run round opposite axes of the sensor's frame.

*The cone is evidence, not a gate* (v27): a motion that moves outside a gesture's cone counts as
:data:`OFF_CONE_FACTOR` times farther from that gesture's models, so it is taken for the gesture
only where it matches that much more closely. A tracker turned in the hand since the takes then
costs only the performances near their threshold, where a hard limit (v26) lost half of them; a
free stroke that merely has a swipe's shape, the other way in the hand, no longer passes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ..core.trajectory import Trajectory

__all__ = ["COVERAGE", "FAST_STEP", "FIXED_FRAME_FACTOR", "MIN_TURN", "OFF_CONE_FACTOR",
           "SIGNIFICANCE", "DirectionTable", "cone_factor", "direction_limit", "farther",
           "fixed_frame", "hand_direction", "hand_turn", "path_turn", "rayleigh_p", "to_weigh",
           "weighed"]

#: Steps at least this fraction of a motion's longest step make its hand direction (chosen on
#: SFINGE3D's sequences 1–18 and the Machete development people among 0, 0.3 and 0.5:
#: docs/online-history.md, v26).
FAST_STEP = 0.3
#: The Rayleigh test's level: takes whose directions a uniform distribution would give with
#: higher probability set no limit.
SIGNIFICANCE = 1e-3
#: Fraction of the fitted von Mises–Fisher distribution inside a gesture's cone.
COVERAGE = 0.99
#: A motion outside a gesture's cone counts this many times farther from its models, so it must
#: match 1 / OFF_CONE_FACTOR of the gesture's threshold (chosen on SFINGE3D's sequences 1–18 and
#: the Machete development people: docs/online-history.md, v27).
OFF_CONE_FACTOR = 1.5
#: The same factor for takes whose tracker never turns (:func:`fixed_frame`, a sensor of
#: positions only): the cones are then directions of the sensor's own frame, which the takes
#: and the stream share, and a motion outside a gesture's cone is not that gesture (v33).
FIXED_FRAME_FACTOR = math.inf


def hand_direction(poses: np.ndarray, fast_step: float = FAST_STEP) -> np.ndarray | None:
    """The direction (3,) in which a motion moves in the tracker's frame, or None (no motion).

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4)
        The motion's poses (world from tracker), uniformly sampled.
    fast_step : float
        Steps shorter than this fraction of the longest one are left out.

    Returns
    -------
    ndarray of shape (3,) or None
        Unit vector ``Σ R_kᵀ Δp_k / |Σ R_kᵀ Δp_k|`` over the kept steps; None when the motion
        has fewer than two poses, does not move, or comes back exactly along its way.
    """
    poses = np.asarray(poses, dtype=np.float64)
    if poses.ndim != 3 or poses.shape[0] < 2:
        return None
    steps = np.diff(poses[:, :3, 3], axis=0)
    lengths = np.linalg.norm(steps, axis=1)
    longest = float(lengths.max())
    if not longest > 0.0:
        return None
    kept = lengths >= fast_step * longest
    in_hand = np.einsum("nji,nj->i", poses[:-1][kept, :3, :3], steps[kept])
    norm = float(np.linalg.norm(in_hand))
    return in_hand / norm if norm > 1e-12 * longest else None


#: A hand that turns less than this [deg] from its first pose has no axis of turn: the wobble of
#: a hand that moves without turning it (v29).
MIN_TURN = 20.0


def hand_turn(poses: np.ndarray, min_angle: float = MIN_TURN) -> np.ndarray | None:
    """The axis (3,) of a motion's largest turn of the tracker from its first pose, in that
    pose's frame, or None (it turns less than ``min_angle``); for a tracker whose orientation
    never changes (a sensor of positions only), the axis about which its path turns
    (:func:`path_turn`).

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4)
        The motion's poses (world from tracker).
    min_angle : float
        Smallest turn [deg] that has an axis.

    Returns
    -------
    ndarray of shape (3,) or None
        Unit axis of ``R_0ᵀ R_k`` at the pose ``k`` farthest in angle from the first one, turning
        by the right-hand rule; None when the motion has fewer than two poses or turns less
        than ``min_angle``.
    """
    poses = np.asarray(poses, dtype=np.float64)
    if poses.ndim != 3 or poses.shape[0] < 2:
        return None
    relative = np.einsum("ji,njk->nik", poses[0, :3, :3], poses[:, :3, :3])
    if np.abs(relative - np.eye(3)).max() < STILL_TRACKER:
        return path_turn(poses, min_angle)
    cos = np.clip((np.trace(relative, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    k = int(np.argmin(cos))  # the largest angle
    if math.degrees(math.acos(float(cos[k]))) < min_angle:
        return None
    R = relative[k]
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    norm = float(np.linalg.norm(axis))
    if norm < 1e-9:  # a half turn: the axis is the eigenvector of R + I, either sense
        B = R + np.eye(3)
        axis = B[:, int(np.argmax(np.linalg.norm(B, axis=0)))]
        norm = float(np.linalg.norm(axis))
    return axis / norm


#: A tracker whose rotation matrices differ from the first by less than this (in every entry)
#: over a motion does not turn at all: a sensor of positions only, which writes one quaternion
#: throughout. A hand-held tracker turns by far more: by at least 0.0076 (largest entry) within
#: every half second of SFINGE3D's development streams, 0.012 in the Machete right controller's
#: 330 takes (half-second windows a quarter window apart).
STILL_TRACKER = 1e-6


def path_turn(poses: np.ndarray, min_angle: float = MIN_TURN,
              fast_step: float = FAST_STEP) -> np.ndarray | None:
    """The axis (3,) about which a motion's path runs round, in the tracker's frame, or None
    (the path goes straight).

    The steps ``s_k = R_kᵀ Δp_k`` at least ``fast_step`` times as long as the longest one sweep
    the signed area ``Σ (c_k − c̄) × s_k`` (``c_k``: the running sum of the steps, ``c̄`` its
    mean); its direction is the axis, turning by the right-hand rule. Like :func:`hand_turn`, a
    change of the world frame leaves it unchanged and a change of the tracker's place in the
    hand turns it by ``Gᵀ``; a mirror image of the path runs round the opposite axis.

    Parameters
    ----------
    poses : ndarray, shape (n, 4, 4)
        The motion's poses (world from tracker), uniformly sampled.
    min_angle : float
        Smallest turn [deg] of the path's heading, from its first kept step to any other, that
        has an axis (a straight stroke's wobble has none).
    fast_step : float
        Steps shorter than this fraction of the longest one are left out.

    Returns
    -------
    ndarray of shape (3,) or None
        Unit axis; None for fewer than three poses, no motion, a heading that turns less than
        ``min_angle``, or no area swept.
    """
    poses = np.asarray(poses, dtype=np.float64)
    if poses.ndim != 3 or poses.shape[0] < 3:
        return None
    steps = np.einsum("nji,nj->ni", poses[:-1, :3, :3], np.diff(poses[:, :3, 3], axis=0))
    lengths = np.linalg.norm(steps, axis=1)
    longest = float(lengths.max())
    if not longest > 0.0:
        return None
    kept = lengths >= fast_step * longest
    headings = steps[kept] / lengths[kept, None]
    turned = float(np.clip(headings @ headings[0], -1.0, 1.0).min())
    if math.degrees(math.acos(turned)) < min_angle:
        return None
    along = np.cumsum(steps, axis=0)
    area = np.cross(along[kept] - along.mean(axis=0), steps[kept]).sum(axis=0)
    norm = float(np.linalg.norm(area))
    return area / norm if norm > 1e-12 * longest**2 else None


def fixed_frame(trajectories: Sequence[Trajectory]) -> bool:
    """Whether no take ever turns its tracker: every rotation of each take differs from the
    take's first by less than :data:`STILL_TRACKER` in every entry, as a sensor of positions
    only writes one orientation throughout. The frame of such takes is the sensor's own: the
    cones learned in it are directions of the room, which the stream shares as long as the
    sensor stands where the takes were recorded, not of the hand, which may hold a tracker
    another way (v33)."""
    for tr in trajectories:
        R = tr.rotations()
        if np.abs(np.einsum("ji,njk->nik", R[0], R) - np.eye(3)).max() >= STILL_TRACKER:
            return False
    return bool(len(trajectories))


def cone_factor(fixed: bool | None) -> float:
    """How many times farther a motion outside a cone counts: :data:`FIXED_FRAME_FACTOR` for
    takes in a fixed frame (:func:`fixed_frame`), else :data:`OFF_CONE_FACTOR` (``None``: a
    library saved before v33, which keeps the factor it was learned with)."""
    return FIXED_FRAME_FACTOR if fixed else OFF_CONE_FACTOR


def farther(distances: np.ndarray, factors: np.ndarray | float) -> np.ndarray:
    """``distances`` times ``factors`` (broadcast), where an infinite factor gives infinity even
    for a zero distance: a motion outside a cone of a fixed frame is never that gesture."""
    distances = np.asarray(distances, dtype=np.float64)
    factors = np.broadcast_to(np.asarray(factors, dtype=np.float64), distances.shape)
    out = np.full(distances.shape, np.inf)
    np.multiply(distances, factors, out=out, where=np.isfinite(factors))
    return out


def rayleigh_p(n: int, mean_length: float) -> float:
    """P-value of the Rayleigh test of uniformity on the sphere: the probability that ``n``
    uniform unit vectors have a mean resultant length of at least ``mean_length``
    (``3 n R̄²`` ~ χ²₃, its survival function)."""
    z = 3.0 * n * mean_length**2
    return float(math.erfc(math.sqrt(z / 2.0)) + math.sqrt(2.0 * z / math.pi) * math.exp(-z / 2.0))


def direction_limit(directions: Sequence[np.ndarray], significance: float = SIGNIFICANCE,
                    coverage: float = COVERAGE) -> tuple[np.ndarray, float] | None:
    """A gesture's cone: the mean direction (3,) of its takes' hand directions and the largest
    angle [deg] from it that a candidate may have, or None where the takes do not agree.

    Parameters
    ----------
    directions : sequence of ndarray, shape (3,)
        Unit hand directions of the gesture's takes (:func:`hand_direction`).
    significance : float
        Level of the Rayleigh test (:func:`rayleigh_p`) the takes must pass.
    coverage : float
        Fraction of the von Mises–Fisher distribution fitted to them that the cone holds.
    """
    if len(directions) < 2:
        return None
    D = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    total = D.sum(axis=0)
    resultant = float(np.linalg.norm(total)) / D.shape[0]
    if rayleigh_p(D.shape[0], resultant) >= significance:
        return None
    if resultant >= 1.0 - 1e-9:  # identical directions: a cone of no width
        return total / np.linalg.norm(total), 0.0
    kappa = resultant * (3.0 - resultant**2) / (1.0 - resultant**2)
    # P(cos θ < c) = (e^{κc} − e^{−κ}) / (e^{κ} − e^{−κ}) for a vMF on the sphere; solved for
    # 1 − coverage in a form that does not overflow for a large κ
    c = 1.0 + math.log((1.0 - coverage) * (1.0 - math.exp(-2.0 * kappa))
                       + math.exp(-2.0 * kappa)) / kappa
    return total / np.linalg.norm(total), math.degrees(math.acos(max(-1.0, min(1.0, c))))


class DirectionTable:
    """Every model's cone, for the spotter and its calibration: ``limits`` (M, 4) holds each
    model's mean direction and largest angle [deg] (NaN angle: no cone); a motion outside a
    model's cone counts ``factor`` times farther from it."""

    def __init__(self, limits: np.ndarray | None, n_models: int,
                 factor: float = OFF_CONE_FACTOR) -> None:
        table = (np.full((n_models, 4), np.nan) if limits is None
                 else np.asarray(limits, dtype=np.float64).reshape(n_models, 4))
        self.mean = np.nan_to_num(table[:, :3])
        self.cos = np.where(np.isnan(table[:, 3]), -2.0, np.cos(np.radians(table[:, 3])))
        self.factor = float(factor)
        #: whether any model has a cone (else no candidate's direction needs measuring)
        self.active = bool(np.isfinite(table[:, 3]).any())

    def passes(self, j: int | slice, direction: np.ndarray | None) -> np.ndarray | bool:
        """Whether a candidate moving along ``direction`` (3,) lies in the cone of model(s)
        ``j`` (None: not measured, passes)."""
        if direction is None:
            return True
        return self.mean[j] @ np.asarray(direction, dtype=np.float64) >= self.cos[j]

    def factors(self, direction: np.ndarray | None) -> np.ndarray:
        """How many times farther (M,) a candidate moving along ``direction`` (3,) counts from
        each model: 1 inside its cone, ``factor`` outside."""
        inside = np.broadcast_to(np.asarray(self.passes(slice(None), direction), dtype=bool),
                                 self.cos.shape)
        return np.where(inside, 1.0, self.factor)


def to_weigh(distances: np.ndarray, scale: np.ndarray,
             exact: Callable[[], np.ndarray] | None = None) -> np.ndarray:
    """The distances (M,) that :func:`weighed` weighs: ``distances`` as given, or, when they
    are a pruned search's (``exact`` given: exact for the nearest model only) and that model
    lies outside its cone, every model's exact distance (``exact()``), since another may be
    nearest once weighed."""
    if exact is not None and scale[int(np.argmin(distances))] != 1.0:
        return exact()
    return distances


def weighed(distances: np.ndarray, scale: np.ndarray,
            exact: Callable[[], np.ndarray] | None = None) -> np.ndarray:
    """A candidate's distances (M,) to the models, each times its cone's factor ``scale`` (M,)
    (:meth:`DirectionTable.factors`; an infinite factor gives infinity): :func:`to_weigh`'s
    distances, weighed."""
    if (scale == 1.0).all():
        return distances
    return farther(to_weigh(distances, scale, exact), scale)
