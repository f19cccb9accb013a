"""The hand's return after a gesture: a stroke that takes the hand back is not the gesture again.

After a swipe the hand usually comes back to where it is comfortable, and the way back is the
same stroke reversed. A frame-free descriptor often finds a reversed stroke as near the gesture's
models as the gesture itself (on the real SFINGE3D streams, the way back after a *swipe left*
lay at 0.88–0.91 τ of *swipe left*), so the way back fired as a second gesture. A real repeat of a
gesture goes the same way as the first; only its return goes back.

:class:`ReturnGuard` remembers the gesture that fired last and refuses, as that same gesture, the
candidate that starts with the next movement unit and ends nearer to where the fired gesture began
than to where it ended, when the fired gesture ended far from where it began (closure at least
:data:`OPEN_CLOSURE`: a circle has no way back). Positions only, compared with each other: no
world frame enters.
"""

from __future__ import annotations

import numpy as np

__all__ = ["OPEN_CLOSURE", "ReturnGuard"]

#: Closure (screw path from first to last pose over the path) from which a fired gesture counts
#: as one that leads somewhere, so that the way back is told from it: more than halfway open.
OPEN_CLOSURE = 0.5


class ReturnGuard:
    """Which candidate is the way back after the gesture that fired last.

    Attributes
    ----------
    gesture : int or None
        Index of the gesture that fired last (``None``: nothing fired, or it was closed).
    began, ended : ndarray, shape (3,)
        Where it began and ended [m].
    next_start : int or None
        Running index where the first movement unit after it started (``None``: not yet).
    """

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """Forget the last gesture."""
        self.gesture: int | None = None
        self.began = np.zeros(3)
        self.ended = np.zeros(3)
        self.fired_end = -1
        self.next_start: int | None = None

    def fired(self, gesture: int, closure: float, poses: np.ndarray, end: int,
              later_starts: list[int]) -> None:
        """A gesture fired: index ``gesture``, its ``closure``, its poses (n, 4, 4) and last
        running index ``end``; ``later_starts``: the starts of units already held after it."""
        self.reset()
        if closure < OPEN_CLOSURE or len(poses) < 2:
            return
        self.gesture = gesture
        self.began = poses[0, :3, 3].copy()
        self.ended = poses[-1, :3, 3].copy()
        self.fired_end = end
        self.next_start = min(later_starts, default=None)

    def unit_started(self, start: int) -> None:
        """A movement unit starting at running index ``start`` was kept."""
        if self.gesture is not None and self.next_start is None and start > self.fired_end:
            self.next_start = start

    def is_return(self, gesture: int, start: int, poses: np.ndarray) -> bool:
        """Whether a candidate of ``gesture`` starting at running index ``start`` with poses
        (n, 4, 4) is the way back after the last gesture."""
        if self.gesture is None or gesture != self.gesture or start != self.next_start:
            return False
        end = poses[-1, :3, 3]
        return bool(np.linalg.norm(end - self.began) < np.linalg.norm(end - self.ended))
