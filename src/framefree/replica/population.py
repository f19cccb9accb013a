"""How people differ and how one person varies: body dimensions and joint ranges of the population
(mean, standard deviation) and the trial-to-trial variation of one person's gestures. The
simulated people (:mod:`~framefree.replica.people`) are drawn from these, and the gesture
generator (:mod:`~framefree.replica.gestures`) varies each performance by them.
"""

from __future__ import annotations

import math

__all__ = ["ANTHROPOMETRY", "HESITATION", "VARIATION"]

#: Body dimensions [m] and joint ranges [rad] (mean, std). Elbow-to-palm distance: forearm
#: 0.146 H plus half a hand 0.054 H for a body height H ≈ 1.70 m (Drillis & Contini 1966).
#: Offset of the pronation axis (radius–ulna line) from the palm centre: a few centimetres (the
#: axis leaves the forearm at the ulnar side of the wrist). Pronation + supination range ≈ 160–180°
#: (normal forearm range of motion about 80–90° each way).
ANTHROPOMETRY = {
    "hand_position": ((0.40, -0.20, 1.15), 0.03),  # palm centre at rest, right hand, in front
    "elbow_to_palm": (0.33, 0.02),
    "pronation_axis_offset": (0.03, 0.01),
    "forearm_rotation": (math.radians(165.0), math.radians(10.0)),
    "elbow_flexion": (math.radians(50.0), math.radians(7.0)),
}

#: Trial-to-trial variation (standard deviations unless stated). Log-normal size and speed factors;
#: heading and tilt of the gesture geometry; tilt of the hand; asymmetry of the minimum-jerk profile
#: (exponent of the time warp); mid-path deviation of the hand path relative to its size (hand
#: paths are nearly straight with small curvature, Morasso 1981, Atkeson & Hollerbach 1985);
#: imperfect return to the start; rest and pause durations (uniform ranges) [s].
VARIATION = {
    "size": 0.12,
    "speed": 0.15,
    "stroke_speed": 0.08,
    "heading": math.radians(10.0),
    "tilt": math.radians(8.0),
    "hand_tilt": math.radians(8.0),
    "skew": 0.10,
    "bulge_rel": 0.02,
    "bulge_abs": 0.003,
    "bulge_rot": math.radians(3.0),
    "return_pos": 0.01,
    "return_rot": math.radians(3.0),
    "rest": (0.5, 1.0),
    "pause": (0.1, 0.4),
}

#: A hesitation in mid-stroke (people who hesitate: ``Person.hesitation``): where it begins, as
#: normalized time of the stroke (uniform), and the speed left during it relative to the stroke's
#: speed there (uniform): the hand nearly stops, it does not stand still.
HESITATION = {
    "at": (0.3, 0.7),
    "residual": (0.03, 0.2),
}
