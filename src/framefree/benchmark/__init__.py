"""The offline benchmark: the paper's training/testing protocol and its Table I.

Typical use::

    from framefree.benchmark import TABLE1_ROWS, load_benchmark_data, make_backend, run_benchmark
    data = load_benchmark_data("path/to/hpm", model_context="original_1")
    with make_backend("joblib", jobs=2) as backend:
        result = run_benchmark(data, TABLE1_ROWS, backend)

or, from a shell, ``framefree benchmark --data path/to/hpm``.
"""

from .backends import BACKENDS, Backend, BackendUnavailableError, make_backend
from .grids import L_VALUES, RECOMMENDED, TABLE1_ROWS, MethodSpec, parse_methods
from .metrics import mean_std, pooled_ratio, ratios_by_context
from .paper import PAPER_TABLE1
from .protocol import (
    DEFAULT_MODEL_CONTEXT,
    BenchmarkData,
    BenchmarkResult,
    RowResult,
    build_benchmark_data,
    evaluate_task,
    is_training_trial,
    load_benchmark_data,
    reparameterize_task,
    resample_task,
    select_best,
)
from .runner import run_benchmark

__all__ = [
    "BACKENDS",
    "DEFAULT_MODEL_CONTEXT",
    "L_VALUES",
    "PAPER_TABLE1",
    "RECOMMENDED",
    "TABLE1_ROWS",
    "Backend",
    "BackendUnavailableError",
    "BenchmarkData",
    "BenchmarkResult",
    "MethodSpec",
    "RowResult",
    "build_benchmark_data",
    "evaluate_task",
    "is_training_trial",
    "load_benchmark_data",
    "make_backend",
    "mean_std",
    "parse_methods",
    "pooled_ratio",
    "ratios_by_context",
    "reparameterize_task",
    "resample_task",
    "run_benchmark",
    "select_best",
]
