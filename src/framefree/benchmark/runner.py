"""The benchmark driver: the protocol's stages, each over every row at once.

:func:`run_benchmark` plans the work (:func:`plan_work`), then runs four stages on a backend —
50 Hz resampling (once per trial and pre-smoothing window), reparameterization (once per trial,
window, progress type and, for screw progress, L), the grid search on the training trials and the
test at each row's selected point — and assembles one :class:`~.protocol.RowResult` per row. The
protocol itself (sets, tie rule, metrics) is described in ``docs/algorithms/table1-protocol.md``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..descriptors.base import available_descriptors
from .backends import Backend, SerialBackend
from .grids import MethodSpec
from .protocol import (
    CHUNK,
    BenchmarkData,
    BenchmarkResult,
    DescriptorInput,
    PointResult,
    RowResult,
    evaluate_task,
    predict_from_distances,
    reparameterize_task,
    resample_task,
    score_row,
    select_best,
)

__all__ = ["WorkPlan", "plan_work", "run_benchmark"]

#: (pre-smoothing window or 0, progress type, L or 0): what a reparameterization depends on
RepKey = tuple[int, str, float]
#: (x, L, training ratio [%]) of one grid point
Score = tuple[float | None, float, float]


@dataclass
class WorkPlan:
    """Everything the stages need to know up front.

    Attributes
    ----------
    methods : list of MethodSpec
    presmooth : list of int
        Effective pre-smoothing window of each row (0: none).
    rep_keys : list of RepKey
        Distinct reparameterizations needed, in first-use order.
    grid_jobs : list of (row, L, points)
        One grid task per row and L: the points ``(x, L)`` of that L.
    chunks : list of range
        Trial index ranges of one resampling / reparameterization task.
    idx_models, idx_train, idx_test : list of int
        Positions of the models, training and test trials in ``data.all_trials``.
    """

    methods: list[MethodSpec]
    presmooth: list[int]
    rep_keys: list[RepKey] = field(default_factory=list)
    grid_jobs: list[tuple[int, float, list[tuple[float | None, float]]]] = field(
        default_factory=list
    )
    chunks: list[range] = field(default_factory=list)
    idx_models: list[int] = field(default_factory=list)
    idx_train: list[int] = field(default_factory=list)
    idx_test: list[int] = field(default_factory=list)

    def rep_key(self, row: int, L: float) -> RepKey:
        """The reparameterization row ``row`` uses at scale length ``L``."""
        spec = self.methods[row]
        return (
            self.presmooth[row],
            spec.progress,
            float(L) if spec.reparameterization_uses_L else 0.0,
        )

    @property
    def windows(self) -> list[int]:
        """Distinct pre-smoothing windows (0: none), in first-use order."""
        return list(dict.fromkeys(k[0] for k in self.rep_keys))

    def n_tasks(self) -> int:
        """Number of tasks of all stages (for a progress bar)."""
        n = len(self.chunks)
        return (
            n * len(self.windows) + n * len(self.rep_keys) + len(self.grid_jobs) + len(self.methods)
        )


def plan_work(
    data: BenchmarkData, methods: Sequence[MethodSpec], presmooth: int | None
) -> WorkPlan:
    """Plan the tasks of every stage.

    Parameters
    ----------
    data : BenchmarkData
    methods : sequence of MethodSpec
    presmooth : int, optional
        Window of the rows that do not set their own.
    """
    methods = list(methods)
    missing = sorted({m.method for m in methods} - set(available_descriptors()))
    if missing:
        raise ValueError(f"descriptor(s) not registered: {', '.join(missing)}")
    windows = [int(m.presmooth if m.presmooth is not None else presmooth or 0) for m in methods]
    plan = WorkPlan(methods, windows)
    for ri, spec in enumerate(methods):
        for L in spec.L_values:
            plan.grid_jobs.append((ri, L, [(x, L) for x in spec.x_values]))
            if plan.rep_key(ri, L) not in plan.rep_keys:
                plan.rep_keys.append(plan.rep_key(ri, L))
    n_models, n_train, n_all = len(data.models), len(data.train), len(data.all_trials)
    plan.chunks = [range(i, min(n_all, i + CHUNK)) for i in range(0, n_all, CHUNK)]
    plan.idx_models = list(range(n_models))
    plan.idx_train = list(range(n_models, n_models + n_train))
    plan.idx_test = list(range(n_models + n_train, n_all))
    return plan


def _resample_stage(
    data: BenchmarkData, plan: WorkPlan, backend: Backend, tick: Callable[[int], None]
) -> dict[int, list[np.ndarray]]:
    """50 Hz poses of every trial, once per pre-smoothing window."""
    trials = data.all_trials
    out = {w: [None] * len(trials) for w in plan.windows}
    tasks, where = [], []
    for w in plan.windows:
        for ch in plan.chunks:
            tasks.append(([trials[i].data for i in ch], w or None))
            where.append((w, ch))
    for k, res in backend.run(resample_task, tasks):
        w, ch = where[k]
        for i, P in zip(ch, res, strict=True):
            out[w][i] = P
        tick(1)
    return out  # type: ignore[return-value]


def _reparameterize_stage(
    poses50: dict[int, list[np.ndarray]],
    plan: WorkPlan,
    backend: Backend,
    tick: Callable[[int], None],
    n_samples: int,
) -> dict[RepKey, list[DescriptorInput]]:
    """Every trial at equidistant progress, once per needed reparameterization."""
    n_all = len(next(iter(poses50.values()))) if poses50 else 0
    reps = {key: [DescriptorInput()] * n_all for key in plan.rep_keys}
    tasks, where = [], []
    for key in plan.rep_keys:
        w, progress, L = key
        for ch in plan.chunks:
            L_rep = L if L > 0 else 0.3  # any L: only screw progress uses it
            tasks.append(([poses50[w][i] for i in ch], progress, L_rep, n_samples))
            where.append((key, ch))
    for k, res in backend.run(reparameterize_task, tasks):
        key, ch = where[k]
        for i, inp in zip(ch, res, strict=True):
            reps[key][i] = inp
        tick(1)
    return reps


def _evaluation_task(
    plan: WorkPlan,
    reps: dict[RepKey, list[DescriptorInput]],
    row: int,
    points: list[tuple[float | None, float]],
    queries: list[int],
    threads: int | None,
    round_digits: int | None,
) -> tuple:
    """Arguments of one :func:`evaluate_task` call: the points of one row and one L."""
    spec = plan.methods[row]
    src = reps[plan.rep_key(row, points[0][1])]
    return (
        spec.method,
        [spec.params(x, L) for x, L in points],
        [src[i] for i in plan.idx_models],
        [src[i] for i in queries],
        threads,
        round_digits,
    )


def _grid_stage(
    data: BenchmarkData,
    plan: WorkPlan,
    reps: dict[RepKey, list[DescriptorInput]],
    backend: Backend,
    tick: Callable[[int], None],
    round_digits: int | None,
    seconds: np.ndarray,
) -> list[list[Score]]:
    """Pooled training recognition ratio of every grid point of every row.

    ``seconds`` (rows × 2: descriptors, matching) is increased by the compute time spent.
    """
    tasks = [
        _evaluation_task(plan, reps, ri, pts, plan.idx_train, backend.task_threads, round_digits)
        for ri, _, pts in plan.grid_jobs
    ]
    model_labels = [r.gesture for r in data.models]
    train_labels = [r.gesture for r in data.train]
    scores: list[list[Score]] = [[] for _ in plan.methods]
    for k, res in backend.run(evaluate_task, tasks):
        ri, L, pts = plan.grid_jobs[k]
        for (x, _), pr in zip(pts, res, strict=True):
            pred = predict_from_distances(pr.distances, model_labels)
            ok = sum(a == b for a, b in zip(pred, train_labels, strict=True))
            scores[ri].append((x, L, 100.0 * ok / len(train_labels) if train_labels else 0.0))
            seconds[ri] += (pr.descriptor_seconds, pr.matching_seconds)
        tick(1)
    return scores


def _selected_point(spec: MethodSpec, scores: list[Score]) -> Score:
    """The grid point chosen by the tie rule (the first point when there is no training set)."""
    if not scores:
        scores = [(x, L, float("nan")) for x, L in spec.grid()]
    return scores[select_best([(x, L, 0.0 if math.isnan(s) else s) for x, L, s in scores])]


def _test_stage(
    plan: WorkPlan,
    reps: dict[RepKey, list[DescriptorInput]],
    selected: list[Score],
    backend: Backend,
    tick: Callable[[int], None],
    round_digits: int | None,
    seconds: np.ndarray,
) -> list[PointResult]:
    """Distances of the test trials at each row's selected point."""
    tasks = [
        _evaluation_task(
            plan, reps, ri, [(x, L)], plan.idx_test, backend.task_threads, round_digits
        )
        for ri, (x, L, _) in enumerate(selected)
    ]
    out: list[PointResult | None] = [None] * len(tasks)
    for k, res in backend.run(evaluate_task, tasks):
        out[k] = res[0]
        seconds[k] += (res[0].descriptor_seconds, res[0].matching_seconds)
        tick(1)
    return out  # type: ignore[return-value]


def _row_result(
    data: BenchmarkData,
    spec: MethodSpec,
    scores: list[Score],
    best: Score,
    test: PointResult,
    seconds: np.ndarray,
) -> RowResult:
    """Assemble one row from its grid scores and its test distances."""
    x, L, score = best
    pred = predict_from_distances(test.distances, [r.gesture for r in data.models])
    scan = sorted(scores, key=lambda e: (-math.inf if e[0] is None else e[0], e[1]))
    return RowResult(
        spec=spec,
        trained=spec.trained(x, L),
        params=test.params,
        train_ratio=score,
        grid=[{"x": gx, "L": gL, "train_ratio": s} for gx, gL, s in scan],
        descriptor_seconds=float(seconds[0]),
        matching_seconds=float(seconds[1]),
        failures=test.failures,
        test_predictions=pred,
        **score_row(spec, test.params, pred, data),
    )


def run_benchmark(
    data: BenchmarkData,
    methods: Sequence[MethodSpec],
    backend: Backend | None = None,
    progress: Callable[[int], None] | None = None,
    on_total: Callable[[int], None] | None = None,
    round_digits: int | None = None,
    n_samples: int = 50,
    presmooth: int | None = None,
) -> BenchmarkResult:
    """Run the protocol for each row.

    Parameters
    ----------
    data : BenchmarkData
        Models, training and test trials (:func:`~.protocol.load_benchmark_data`).
    methods : sequence of MethodSpec
        Rows to compute (e.g. :data:`~framefree.benchmark.grids.TABLE1_ROWS`).
    backend : Backend, optional
        Where tasks run; default in-process.
    progress : callable, optional
        Called with the number of tasks just finished (e.g. ``tqdm.update``).
    on_total : callable, optional
        Called once with the number of tasks (to size a progress bar).
    round_digits : int, optional
        Round descriptors to this many significant digits, as the reference's CSV storage;
        default full precision.
    n_samples : int
        Progress samples per trajectory (50).
    presmooth : int, optional
        framefree extension, off by default (not the paper's protocol): Gaussian-smooth the 50 Hz
        poses with this window [samples] before progress, for rows without their own window.

    Returns
    -------
    BenchmarkResult
    """
    backend = backend or SerialBackend()
    tick = progress or (lambda n: None)
    plan = plan_work(data, methods, presmooth)
    (on_total or (lambda n: None))(plan.n_tasks())
    timing: dict[str, float] = {}
    t_start = t = time.perf_counter()
    poses50 = _resample_stage(data, plan, backend, tick)
    timing["resample"], t = time.perf_counter() - t, time.perf_counter()
    reps = _reparameterize_stage(poses50, plan, backend, tick, n_samples)
    timing["reparameterize"], t = time.perf_counter() - t, time.perf_counter()
    seconds = np.zeros((len(plan.methods), 2))
    scores = _grid_stage(data, plan, reps, backend, tick, round_digits, seconds)
    timing["grid"], t = time.perf_counter() - t, time.perf_counter()
    selected = [_selected_point(s, sc) for s, sc in zip(plan.methods, scores, strict=True)]
    tests = _test_stage(plan, reps, selected, backend, tick, round_digits, seconds)
    timing["test"] = time.perf_counter() - t
    rows = [
        _row_result(data, spec, scores[ri], selected[ri], tests[ri], seconds[ri])
        for ri, spec in enumerate(plan.methods)
    ]
    timing["descriptors"] = float(seconds[:, 0].sum())
    timing["matching"] = float(seconds[:, 1].sum())
    timing["total"] = time.perf_counter() - t_start
    return BenchmarkResult(
        rows=rows,
        gestures=list(data.gestures),
        contexts=list(data.contexts),
        model_context=data.model_context,
        data_root=data.root,
        counts={"models": len(data.models), "train": len(data.train), "test": len(data.test)},
        timing=timing,
        backend=backend.describe(),
        test_labels=[r.gesture for r in data.test],
        test_contexts=[r.context for r in data.test],
        test_names=[r.name for r in data.test],
        settings={"round_digits": round_digits, "presmooth": presmooth, "n_samples": n_samples},
    )
