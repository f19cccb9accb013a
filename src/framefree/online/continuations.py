"""How long a longer gesture may still be going on after a shorter one seems complete.

A gesture can begin the way another one does: with two controllers, a *right-left-right combo*
opens with a right *hook*. When the hook is accepted and pending, the spotter waits for a rest
before it fires, but at most ``max_wait`` (1 s) after the hook's end while the hands move on; a
combo's remaining strokes take longer than that, so the hook fired while the combo was under
way (v19 to v23 on the Machete sessions: 9 combos of 30 missed, each also a false *hook*).

The takes say how long the wait must be. :func:`continuation_waits` runs the recognizer, as
built, over each take as if it were a stream and looks at every candidate it accepts inside the
take as *another* gesture: a hook inside a combo's take ends some time before the take's motion
does. The longest such time, plus the confirming rest ``confirm``, is how long a pending
candidate of that gesture may have to wait for the longer gesture to end; a gesture found inside
no other gesture's take keeps ``max_wait``. The values are learned with the other values of the
recognizer (:class:`~framefree.online.learned.LearnedSettings.continuations`) and stored in a
gesture library.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from .evaluation import stream_rows

__all__ = ["continuation_waits"]


def continuation_waits(recognizer: Any, samples: Sequence[Any], labels: Sequence[str]
                       ) -> dict[str, float]:
    """Per gesture, the longest time [s] from the end of a candidate accepted as that gesture
    inside a take of another gesture to the end of that take's motion, plus ``confirm``
    (0 for a gesture accepted inside no other gesture's take).

    Parameters
    ----------
    recognizer : Recognizer or MultiRecognizer
        Built on ``samples`` (inline: no background worker); it is reset before and after.
    samples : sequence of Trajectory or MultiTrajectory
        The takes, one gesture performance each.
    labels : sequence of str
        Their gestures.

    Returns
    -------
    dict of str to float
        Every gesture of ``recognizer.labels`` [s].
    """
    from tqdm import tqdm

    spotter = recognizer.spotter
    confirm = float(recognizer.config.confirm)
    waits = dict.fromkeys(recognizer.gestures, 0.0)
    takes = tqdm(list(zip(samples, labels, strict=True)), desc="timing the takes", unit="take",
                 leave=False, disable=None)  # a bar on a terminal only
    for sample, gesture in takes:
        recognizer.reset()
        spotter.log = log = []
        try:
            for t, p, q in zip(*stream_rows(sample), strict=True):
                recognizer.push(float(t), p, q)
            recognizer.finish()
        finally:
            spotter.log = None
        if not log:
            continue
        end = max(c.end_t for c in log)
        for c in log:
            other = recognizer.labels[c.model]
            if c.accepted and other != gesture and c.end_t < end:
                waits[other] = max(waits[other], end - c.end_t + confirm)
    recognizer.reset()
    return {g: round(w, 6) for g, w in waits.items()}
