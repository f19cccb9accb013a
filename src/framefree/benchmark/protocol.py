"""The offline training/testing protocol of the paper (docs/algorithms/table1-protocol.md) as pure
task functions, and the results of a run.

The sets (models, training and test queries) are built in :mod:`framefree.benchmark.data` (and
re-exported here). For every method/progress row, the grid is
searched for the point with the highest pooled training recognition ratio (ties: smallest x, then
smallest L, docs/algorithms/table1-protocol.md), and the test trials are classified with that point.

Work is organized so that nothing is computed twice:

1. every trial is resampled at 50 Hz once (:func:`resample_task`);
2. each trial is reparameterized once per (progress, L) that some row needs
   (:func:`reparameterize_task`); L matters only for screw-path progress;
3. per grid point, each descriptor is computed once from those poses, then the query × model
   distance matrix (:func:`evaluate_task`; one task = the x values of one L, or one test point).

All three task functions are pure (numpy arrays and small values in, results out), so any
:class:`~framefree.benchmark.backends.Backend` runs them: in-process, joblib processes, or Dask/Ray.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..classifier import round_significant
from ..core.progress import cumulative_progress, reparameterize_poses, uniform_time_poses
from ..core.trajectory import Trajectory
from ..descriptors.base import Descriptor, get_descriptor
from ..errors import FramefreeError
from .data import (
    DEFAULT_MODEL_CONTEXT,
    BenchmarkData,
    TrialRecord,
    build_benchmark_data,
    is_training_trial,
    load_benchmark_data,
)
from .grids import MethodSpec
from .metrics import context_groups, mean_std, pooled_ratio, ratios_by_context

__all__ = [
    "DEFAULT_MODEL_CONTEXT",
    "BenchmarkData",
    "BenchmarkResult",
    "DescriptorInput",
    "PointResult",
    "RowResult",
    "TrialRecord",
    "build_benchmark_data",
    "evaluate_task",
    "is_training_trial",
    "load_benchmark_data",
    "predict_from_distances",
    "reparameterize_task",
    "resample_task",
    "select_best",
]


#: trials per resampling / reparameterization task
CHUNK = 40


# ------------------------------------------------------------------------------------------ tasks
@dataclass(frozen=True)
class DescriptorInput:
    """What a descriptor is computed from, for one trial.

    Attributes
    ----------
    poses : ndarray or None
        ``(N, 4, 4)`` poses at equidistant progress (standard pipeline), or None.
    ds : float
        Progress step of ``poses`` [m or rad].
    arclength : float
        Total arclength ℓ [m] of the 50 Hz trajectory (the normalization of the global
        descriptors).
    error : str or None
        Why no descriptor can be computed (e.g. no progress of this type); then the trial gets no
        class and counts as misrecognized.
    """

    poses: np.ndarray | None = None
    ds: float = float("nan")
    arclength: float = float("nan")
    error: str | None = None


def resample_task(arrays: Sequence[np.ndarray], presmooth: int | None = None) -> list[np.ndarray]:
    """Resample trials at 50 Hz with ScLERP (docs/algorithms/progress.md).

    Parameters
    ----------
    arrays : sequence of ndarray, each (N_i, 8)
        Trials ``t, x, y, z, qw, qx, qy, qz``.
    presmooth : int, optional
        framefree extension, off by default: Gaussian-smooth the 50 Hz poses with this window
        [samples] before any progress is computed
        (:func:`~framefree.core.progress.uniform_time_poses`).

    Returns
    -------
    list of ndarray, each (M_i, 4, 4)
    """
    return [uniform_time_poses(Trajectory.from_array(a), presmooth=presmooth) for a in arrays]


def reparameterize_task(
    poses_list: Sequence[np.ndarray], progress: str, L: float, n: int = 50
) -> list[DescriptorInput]:
    """Reparameterize 50 Hz pose sequences at ``n`` equidistant progress values (docs/algorithms/progress.md).

    Parameters
    ----------
    poses_list : sequence of ndarray, each (M_i, 4, 4)
    progress : {"arclength", "angle", "screw"}
    L : float
        Scale length [m] of screw-path progress (ignored otherwise).
    n : int
        Number of progress samples.

    Returns
    -------
    list of DescriptorInput
        With ``poses`` (n, 4, 4), ``ds`` and the 50 Hz arclength, or ``error`` for a trial
        without progress of this type.
    """
    out = []
    for P in poses_list:
        ell = float(cumulative_progress(P, "arclength")[-1])
        try:
            rep = reparameterize_poses(P, progress, L, n)
        except FramefreeError as exc:
            out.append(DescriptorInput(error=str(exc)))
        else:
            out.append(DescriptorInput(poses=rep.poses, ds=rep.ds, arclength=ell))
    return out


@dataclass
class PointResult:
    """Classification distances of one grid point.

    Attributes
    ----------
    params : dict
        Descriptor constructor arguments.
    distances : ndarray, shape (n_queries, n_models)
        Normalized distances; ``inf`` where a descriptor could not be computed.
    descriptor_seconds, matching_seconds : float
        Time spent computing descriptors and distance matrices.
    failures : list of str
        One message per trial whose descriptor failed (model or query).
    """

    params: dict[str, Any]
    distances: np.ndarray
    descriptor_seconds: float
    matching_seconds: float
    failures: list[str] = field(default_factory=list)


def _describe(
    desc: Descriptor,
    inp: DescriptorInput,
    round_digits: int | None,
    cache: dict[int, np.ndarray | str] | None = None,
    key: int = 0,
) -> np.ndarray | str:
    """Descriptor (K, F) of one input, or the reason it cannot be computed.

    With ``cache``, descriptors that declare ``shares_representation`` compute their
    representation once per input (``key``) and only re-weight it per grid point.
    """
    if inp.error is not None:
        return inp.error
    errors = (FramefreeError, FloatingPointError, np.linalg.LinAlgError)
    try:
        if cache is not None and desc.shares_representation:
            raw = cache.get(key)
            if raw is None:
                try:
                    raw = desc.representation(inp.poses, inp.ds, inp.arclength)
                except errors as exc:
                    raw = str(exc)
                cache[key] = raw
            if isinstance(raw, str):
                return raw
            d = desc.weight(raw)
        else:
            d = desc.from_reparameterized(inp.poses, inp.ds, inp.arclength)
    except errors as exc:
        return str(exc)
    d = np.asarray(d, dtype=np.float64)
    if not np.isfinite(d).all():
        return "descriptor has non-finite values"
    if round_digits is not None:
        d = round_significant(d, round_digits)
    return d


def evaluate_task(
    method: str,
    points: Sequence[dict[str, Any]],
    models: Sequence[DescriptorInput],
    queries: Sequence[DescriptorInput],
    threads: int | None = None,
    round_digits: int | None = None,
) -> list[PointResult]:
    """Descriptors and query × model distances at each of several parameter points.

    Parameters
    ----------
    method : str
        Registered descriptor name.
    points : sequence of dict
        Descriptor constructor arguments (``progress``, ``L``, ``lam`` / ``ds_scale``); all points
        of one call share the inputs (same progress, and same L for screw-path progress), so
        descriptors whose parameters only weight a shared representation (DHB, eFS, ISA) compute
        that representation once per trial.
    models, queries : sequence of DescriptorInput
        Inputs of the model and query trials.
    threads : int, optional
        Numba threads for the distance kernels in this worker (None: unchanged).
    round_digits : int, optional
        Round descriptors to this many significant digits, as the reference's CSV storage
        (docs/algorithms/dtw.md).

    Returns
    -------
    list of PointResult
        One per point, in order.
    """
    if threads is not None:
        import numba

        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
    out = []
    cache: dict[int, np.ndarray | str] = {}  # representations shared by the points of this task
    nm = len(models)
    for params in points:
        desc = get_descriptor(method, **params)
        t0 = time.perf_counter()
        md = [_describe(desc, m, round_digits, cache, i) for i, m in enumerate(models)]
        qd = [_describe(desc, q, round_digits, cache, nm + i) for i, q in enumerate(queries)]
        t1 = time.perf_counter()
        mi = [i for i, d in enumerate(md) if not isinstance(d, str)]
        qi = [i for i, d in enumerate(qd) if not isinstance(d, str)]
        dist = np.full((len(queries), len(models)), np.inf)
        if mi and qi:
            sub = desc.distance_matrix([qd[i] for i in qi], [md[i] for i in mi])
            sub = np.asarray(sub, dtype=np.float64)
            sub = np.where(np.isfinite(sub), sub, np.inf)
            dist[np.ix_(qi, mi)] = sub
        t2 = time.perf_counter()
        failures = [f"model {i}: {d}" for i, d in enumerate(md) if isinstance(d, str)]
        failures += [f"query {i}: {d}" for i, d in enumerate(qd) if isinstance(d, str)]
        out.append(PointResult(dict(params), dist, t1 - t0, t2 - t1, failures))
    return out


# ------------------------------------------------------------------------------------- selection
def predict_from_distances(distances: np.ndarray, model_labels: Sequence[str]) -> list[str | None]:
    """1-NN labels: the first model with the smallest distance (docs/algorithms/dtw.md); None if all
    are infinite.

    Parameters
    ----------
    distances : ndarray, shape (n_queries, n_models)
    model_labels : sequence of str, shape (n_models,)
    """
    d = np.asarray(distances, dtype=np.float64)
    out: list[str | None] = []
    for row in d:
        if not np.isfinite(row).any():
            out.append(None)
        else:
            out.append(model_labels[int(np.argmin(row))])
    return out


def select_best(scores: Sequence[tuple[float | None, float, float]]) -> int:
    """Index of the selected grid point (docs/algorithms/table1-protocol.md).

    Parameters
    ----------
    scores : sequence of (x, L, score)
        One entry per grid point, in any order; ``x`` may be None (no x parameter).

    Returns
    -------
    int
        Index of the highest score; ties go to the smallest x, then the smallest L (the first
        maximum of MATLAB's column-major scan of the L × x grid).
    """
    if not scores:
        raise ValueError("empty grid")
    best = None
    best_key = None
    for i, (x, L, s) in enumerate(scores):
        key = (-float(s), -math.inf if x is None else float(x), float(L))
        if best_key is None or key < best_key:
            best, best_key = i, key
    return int(best)  # type: ignore[arg-type]


# --------------------------------------------------------------------------------------- results
@dataclass
class RowResult:
    """Outcome of one method/progress row.

    Attributes
    ----------
    spec : MethodSpec
    trained : dict
        Selected parameters (``lam`` / ``ds_scale`` and/or ``L``), empty when nothing is trained.
    params : dict
        Full descriptor arguments used for testing.
    train_ratio : float
        Pooled training recognition ratio [%] at the selected point.
    grid : list of dict
        Every grid point: ``{"x", "L", "train_ratio"}``.
    per_context : dict
        Test recognition ratio [%] per query context (Table I order).
    pooled : dict
        Pooled columns (``body_frame``, ``world_frame``) [%].
    mean, std : float
        Over the individual test contexts, from RRs rounded to 0.1 (docs/algorithms/table1-protocol.md).
    overall : float
        Recognition ratio over all test trials [%].
    confusion : ndarray, shape (n_gestures, n_gestures + 1)
        Test counts, rows = true gesture, columns = recognized gesture (last: none).
    confusion_by_context : dict
        The same per context.
    descriptor_seconds, matching_seconds : float
        Compute time spent on this row (summed over workers).
    failures : list of str
        Descriptor failures at the selected point on the test set.
    """

    spec: MethodSpec
    trained: dict[str, float]
    params: dict[str, Any]
    train_ratio: float
    grid: list[dict[str, Any]]
    per_context: dict[str, float]
    pooled: dict[str, float]
    mean: float
    std: float
    overall: float
    confusion: np.ndarray
    confusion_by_context: dict[str, np.ndarray]
    descriptor_seconds: float = 0.0
    matching_seconds: float = 0.0
    failures: list[str] = field(default_factory=list)
    test_predictions: list[str | None] = field(default_factory=list)

    @property
    def seconds(self) -> float:
        """Descriptor plus matching time [s]."""
        return self.descriptor_seconds + self.matching_seconds


@dataclass
class BenchmarkResult:
    """All rows plus the run's bookkeeping.

    Attributes
    ----------
    rows : list of RowResult
    gestures, contexts : list of str
    model_context : str
    data_root : str
    counts : dict
        Numbers of models, training and test trials.
    timing : dict
        Wall-clock seconds per stage (``load``, ``resample``, ``reparameterize``, ``grid``,
        ``test``, ``total``) and compute seconds (``descriptors``, ``matching``).
    backend : str
    test_labels, test_contexts, test_names : list of str
        The test queries, in the order of each row's predictions.
    settings : dict
        Options that change the numbers: ``round_digits``, ``presmooth``, ``n_samples``.
    """

    rows: list[RowResult]
    gestures: list[str]
    contexts: list[str]
    model_context: str
    data_root: str
    counts: dict[str, int]
    timing: dict[str, float]
    backend: str
    test_labels: list[str] = field(default_factory=list)
    test_contexts: list[str] = field(default_factory=list)
    test_names: list[str] = field(default_factory=list)
    settings: dict[str, Any] = field(default_factory=dict)


def score_row(
    spec: MethodSpec,
    params: dict[str, Any],
    predictions: Sequence[str | None],
    data: BenchmarkData,
) -> dict[str, Any]:
    """Test metrics of one row from its test predictions (docs/algorithms/table1-protocol.md)."""
    from .metrics import confusion_matrix

    labels = [r.gesture for r in data.test]
    ctxs = [r.context for r in data.test]
    per_ctx = ratios_by_context(labels, predictions, ctxs)
    per_ctx = {c: per_ctx[c] for c in data.contexts if c in per_ctx}
    groups = context_groups(list(per_ctx))
    pooled = {g: pooled_ratio(labels, predictions, ctxs, members) for g, members in groups.items()}
    mean, std = mean_std(per_ctx)
    ok = [a == b for a, b in zip(labels, predictions, strict=True)]
    overall = 100.0 * float(np.mean(ok)) if ok else float("nan")
    conf = confusion_matrix(labels, predictions, data.gestures)
    conf_ctx = {}
    for c in per_ctx:
        sel = [i for i, x in enumerate(ctxs) if x == c]
        conf_ctx[c] = confusion_matrix(
            [labels[i] for i in sel], [predictions[i] for i in sel], data.gestures
        )
    return {
        "per_context": per_ctx,
        "pooled": pooled,
        "mean": mean,
        "std": std,
        "overall": overall,
        "confusion": conf,
        "confusion_by_context": conf_ctx,
    }
