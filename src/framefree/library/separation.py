"""Whether the calibration found a gap between a gesture's takes and motion that is no gesture.

When a library is enrolled, every gesture's threshold τ_g is placed between ``P_g``, how far its
worst take lies from the others (left out in turn), and ``N_g``, how near motion that is no
gesture comes (another gesture's take, holding still and reaching moves, random shapes drawn in
the air; :mod:`framefree.online.thresholds`). Where ``P_g < N_g`` there is a gap and τ_g lies in
it. Where not, the gesture is *not separated*: some of its own takes lie farther from the others
than some non-gesture motion does, τ_g is their geometric midpoint, and live the gesture will be
missed now and then and fire on other motion now and then, whatever its threshold.

It happens to simple shapes taught by one person (a check mark: two strokes and one corner, which
any motion that goes one way and turns the other resembles once the world frame is ignored;
docs/online-history.md, *Session 40*) and to dictionaries of many people's examples, whose worst
take is some person's unusual performance (three of SFINGE3D's four swipes). ``framefree enroll``
marks such gestures (:attr:`GestureLibrary.unseparated`) and ``framefree check`` explains them
(:func:`separation_findings`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .check import Finding

if TYPE_CHECKING:
    from .store import GestureLibrary

__all__ = ["separation_findings"]


def separation_findings(library: GestureLibrary) -> list[Finding]:
    """A warning for each gesture that is not separated (:attr:`GestureLibrary.unseparated`),
    with its worst take's leave-one-out distance ``P_g``, the non-gesture motion's ``N_g`` and
    the threshold between them."""
    calibration = library.calibration or {}
    out = []
    for g in library.unseparated:
        worst = calibration["positives_max"][g]
        if worst is None:  # no take is found among the others: the gesture is not followed
            continue
        nearest = calibration["negatives_quantile"][g]
        tau = calibration["thresholds"][g]
        out.append(Finding(
            "warning", g,
            f"{g} is not apart from motion that is no gesture: its worst take lies {worst:.3g} "
            f"from the other takes, but other motion (another gesture's take, a reach, a shape drawn "
            f"in the air) comes within {nearest:.3g} of them; its threshold {tau:.3g} lies "
            f"between the two, so live some {g}s will be missed and some other motion taken for "
            f"one. A turn of the hand or another stroke sets a gesture apart; in a dictionary of "
            f"many people's examples the most unusual ones decide"))
    return out
