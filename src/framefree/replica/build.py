"""The synthetic HPM replica: 7 gestures × (12 paper + 4 stress) contexts × 5 trials, plus labelled
streams, written in the dataset layout and cached on demand."""

from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from ..core.trajectory import Trajectory
from ..datasets.layout import GESTURES, REPLICA_CONTEXTS, STREAMS_DIR
from .contexts import OTHER_PERSON, apply_context
from .gestures import default_world, synthesize_gesture
from .motion import make_pose, rot
from .people import person
from .recording import write_recording
from .streams import make_stream, save_stream

__all__ = ["N_TRIALS", "REPLICA_VERSION", "cache_dir", "make_replica", "replica_path"]

#: Format version of the replica; the cache key also holds a hash of the generator's source
#: (:func:`generator_fingerprint`), so a cached replica is never reused after the code changed.
REPLICA_VERSION = 1
#: Modules whose source defines the replica's content.
_GENERATOR_MODULES = (
    "activities", "build", "contexts", "gestures", "motion", "people", "population", "recording",
    "streams",
)
#: Trials per gesture and context.
N_TRIALS = 5
#: Variation of the user's stance between the trials of one session: position [m], heading [rad].
STANCE_STD = (0.05, np.radians(5.0))


def cache_dir() -> Path:
    """``$FRAMEFREE_CACHE`` if set, else ``~/.cache/framefree``."""
    env = os.environ.get("FRAMEFREE_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "framefree"


def generator_fingerprint() -> str:
    """Eight hex digits of a hash of the generator's source files (part of the cache key)."""
    h = hashlib.sha256()
    here = Path(__file__).resolve().parent
    for name in _GENERATOR_MODULES:
        h.update((here / f"{name}.py").read_bytes())
    return h.hexdigest()[:8]


def _rng(seed: int, *keys: int) -> np.random.Generator:
    return np.random.default_rng([int(seed), *keys])


def make_replica(out_dir: str | Path, seed: int = 0, n_streams: int = 3) -> Path:
    """Generate the replica into ``out_dir``.

    Writes ``<out>/<gesture>/<context>/trial_k.csv`` (k = 1..5) and
    ``<out>/streams/stream_<i>.csv`` with ``stream_<i>_labels.csv`` (i = 1..n_streams).

    Every trial is a separate recording of the same person in one session (same tracker world, small
    changes of stance, a different grip each time); every context is made from the trial's
    *Original 1* recording by :func:`~framefree.replica.apply_context`. Stored quaternions carry
    SDK-like sign flips. Deterministic given ``seed``.

    Parameters
    ----------
    out_dir : str or Path
        Created if missing; existing files are overwritten.
    seed : int
    n_streams : int
        Number of continuous streams.

    Returns
    -------
    Path
        ``out_dir``.
    """
    out = Path(out_dir)
    world = default_world(_rng(seed, 0))
    for gi, gesture in enumerate(GESTURES):
        for k in range(1, N_TRIALS + 1):
            rng = _rng(seed, 1, gi, k)
            stance = make_pose(rot([0, 0, 1], rng.normal(0.0, STANCE_STD[1])),
                               [*rng.normal(0.0, STANCE_STD[0], 2), 0.0])
            orig = synthesize_gesture(gesture, rng, world=world @ stance, source=f"{gesture}/trial_{k}")
            for ci, context in enumerate(REPLICA_CONTEXTS):
                if context == "other_person":
                    traj = _other_person_trial(gesture, seed, gi, k, world)
                else:
                    traj = apply_context(orig, context, _rng(seed, 2, gi, k, ci))
                write_recording(out / gesture / context / f"trial_{k}.csv", traj, _rng(seed, 3, gi, k, ci))
    for i in range(1, n_streams + 1):
        traj, segments = make_stream(seed * 1000 + i)
        save_stream(out / STREAMS_DIR / f"stream_{i}.csv", traj, segments, _rng(seed, 4, i))
    return out


def _other_person_trial(
    gesture: str, seed: int, gi: int, k: int, world: np.ndarray
) -> Trajectory:
    """Trial ``k`` of ``gesture`` recorded by the second person (:data:`OTHER_PERSON`): the same
    tracker world, their own stance, style and grip (random draws of their own)."""
    rng = _rng(seed, 5, gi, k)
    stance = make_pose(
        rot([0, 0, 1], rng.normal(0.0, STANCE_STD[1])), [*rng.normal(0.0, STANCE_STD[0], 2), 0.0]
    )
    return synthesize_gesture(
        gesture,
        rng,
        world=world @ stance,
        source=f"{gesture}/other_person/trial_{k}",
        person=person(OTHER_PERSON),
    )


def replica_path(seed: int = 0) -> Path:
    """Path of the cached replica for ``seed``, generating it first if needed (a few seconds).

    The replica lives in :func:`cache_dir` under ``hpm-replica-v<version>-<fingerprint>-seed<seed>``
    (the fingerprint hashes the generator's source, so a replica made by other code is never
    reused); it is
    written to a temporary folder beside it and renamed, so a half-written replica is never used
    and concurrent callers are safe.

    Examples
    --------
    >>> ds = load_dataset(replica_path())          # doctest: +SKIP
    >>> traj, segments = load_stream(replica_path() / "streams" / "stream_1.csv")  # doctest: +SKIP
    """
    base = cache_dir()
    final = base / f"hpm-replica-v{REPLICA_VERSION}-{generator_fingerprint()}-seed{int(seed)}"
    if final.is_dir():
        return final
    base.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{final.name}-", dir=base))
    try:
        make_replica(tmp, seed)
        try:
            tmp.rename(final)
        except OSError:
            if not final.is_dir():
                raise
    finally:
        if tmp.exists():
            shutil.rmtree(tmp, ignore_errors=True)
    return final

