"""The protocol end to end on a tiny dataset, and the backends running the same task functions."""

from __future__ import annotations

import contextlib
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from framefree import Trajectory, get_descriptor
from framefree.benchmark import (
    BackendUnavailableError,
    MethodSpec,
    load_benchmark_data,
    make_backend,
    run_benchmark,
)
from framefree.benchmark.backends import RayBackend, SerialBackend
from framefree.benchmark.protocol import (
    evaluate_task,
    predict_from_distances,
    reparameterize_task,
    resample_task,
)
from framefree.errors import DatasetError

ROWS = [MethodSpec("bilts+", "screw"), MethodSpec("bilts", "angle")]


@pytest.fixture(scope="module")
def tiny(tiny_root: Path):
    return load_benchmark_data(tiny_root, "original_1")


@pytest.fixture(scope="module")
def serial_result(tiny):
    return run_benchmark(tiny, ROWS, SerialBackend())


def test_sets(tiny) -> None:
    assert tiny.gestures == ["helix", "pour", "scoop"]
    assert tiny.contexts == ["original_2", "first_half", "body_frame_1", "world_frame_1"]
    assert len(tiny.models) == 9 and all(r.context == "original_1" for r in tiny.models)
    assert [r.gesture for r in tiny.models] == ["helix"] * 3 + ["pour"] * 3 + ["scoop"] * 3
    assert len(tiny.train) == 3 * 4 * 2 and {r.name for r in tiny.train} == {"trial_1", "trial_2"}
    assert len(tiny.test) == 3 * 4 and {r.name for r in tiny.test} == {"trial_3"}


def test_missing_model_context(tiny_root: Path) -> None:
    with pytest.raises(DatasetError, match="'nope'"):
        load_benchmark_data(tiny_root, "nope")


def test_end_to_end(serial_result, tiny) -> None:
    res = serial_result
    assert [r.spec.key for r in res.rows] == ["bilts+:screw", "bilts:angle"]
    assert res.counts == {"models": 9, "train": 24, "test": 12}
    for row in res.rows:
        assert len(row.grid) == 25
        assert row.train_ratio == max(g["train_ratio"] for g in row.grid)
        # the selected point is the first maximum in (x, L) scan order
        first = next(g for g in row.grid if g["train_ratio"] == row.train_ratio)
        x_name = "ds_scale"
        assert row.trained == {x_name: first["x"], "L": first["L"]}
        assert list(row.per_context) == tiny.contexts
        assert set(row.pooled) == {"body_frame", "world_frame"}
        assert row.pooled["body_frame"] == row.per_context["body_frame_1"]
        assert row.confusion.shape == (3, 4) and row.confusion.sum() == 12
        assert row.seconds > 0
    # the bi-invariant BILTS+ recognizes these three distinct motions in every frame
    bp = res.rows[0]
    assert bp.per_context["original_2"] == 100.0
    assert bp.per_context["body_frame_1"] == 100.0
    assert bp.per_context["world_frame_1"] == 100.0
    assert bp.train_ratio >= 90.0
    assert res.timing["descriptors"] > 0 and res.timing["matching"] > 0


def test_tasks_match_direct_classification(tiny) -> None:
    """The cached pipeline (resample → reparameterize → descriptor) equals descriptor.compute()."""
    trials = tiny.models + tiny.test[:3]
    P = resample_task([r.data for r in trials])
    inputs = reparameterize_task(P, "screw", 0.5)
    params = {"progress": "screw", "L": 0.5, "ds_scale": 0.09}
    (pr,) = evaluate_task("bilts+", [params], inputs[:9], inputs[9:])
    desc = get_descriptor("bilts+", **params)
    direct = [desc.compute(Trajectory.from_array(r.data)) for r in trials]
    np.testing.assert_allclose(
        pr.distances, desc.distance_matrix(direct[9:], direct[:9]), rtol=1e-9
    )
    assert pr.distances.shape == (3, 9)


def test_failed_descriptor_counts_as_wrong() -> None:
    d = np.array([[np.inf, np.inf], [2.0, 1.0], [1.0, 1.0]])
    assert predict_from_distances(d, ["a", "b"]) == [None, "b", "a"]  # ties: first model


def test_joblib_processes_give_the_same_result(tiny, serial_result) -> None:
    with make_backend("joblib", jobs=2) as bk:
        res = run_benchmark(tiny, ROWS[:1], bk)
    ref = serial_result.rows[0]
    row = res.rows[0]
    assert row.trained == ref.trained
    assert row.grid == ref.grid
    assert row.per_context == ref.per_context


def test_missing_extras_fail_clearly() -> None:
    for name in ("dask", "ray"):
        try:
            __import__(name)
        except ImportError:
            with pytest.raises(BackendUnavailableError, match=rf"framefree\[{name}\]"):
                make_backend(name, jobs=2)
    with pytest.raises(ValueError, match="unknown backend"):
        make_backend("spark")


class _FakeRay(types.ModuleType):
    """Just enough of Ray's API (init/remote/wait/get) to run tasks in this process."""

    def __init__(self) -> None:
        super().__init__("ray")
        self.started = False
        self.calls = 0

    def is_initialized(self) -> bool:
        return self.started

    def init(self, **kwargs) -> None:
        self.started = True

    def shutdown(self) -> None:
        self.started = False

    def remote(self, fn):
        fake = self

        class _Remote:
            def remote(self, *args):
                fake.calls += 1
                return ("ref", fn(*args))

        return _Remote()

    def wait(self, refs, num_returns=1):
        return refs[:num_returns], refs[num_returns:]

    def get(self, ref):
        return ref[1]


def test_same_task_functions_run_on_a_cluster_api(tiny, serial_result, monkeypatch) -> None:
    fake = _FakeRay()
    fake.started = True  # framefree joins a session the caller started (it starts none itself)
    monkeypatch.setitem(sys.modules, "ray", fake)
    with make_backend("ray", jobs=2) as bk:
        assert isinstance(bk, RayBackend)
        res = run_benchmark(tiny, ROWS[:1], bk)
    assert fake.calls > 0 and fake.started
    assert res.rows[0].grid == serial_result.rows[0].grid
    assert res.rows[0].per_context == serial_result.rows[0].per_context


def test_builtin_layout_scanner_agrees_with_dataset_loader(tiny_root: Path, tiny) -> None:
    from framefree.benchmark.data import _records_from_layout, build_benchmark_data

    own = build_benchmark_data(_records_from_layout(tiny_root), "original_1", str(tiny_root))
    for a, b in ((own.models, tiny.models), (own.train, tiny.train), (own.test, tiny.test)):
        assert [(r.gesture, r.context, r.name) for r in a] == [
            (r.gesture, r.context, r.name) for r in b
        ]
        np.testing.assert_array_equal(a[0].data, b[0].data)
    assert own.contexts == tiny.contexts


@pytest.mark.parametrize(
    ("method", "progress", "extra"),
    [
        ("dhb", "angle", "lam"),
        ("isa", "screw", "lam"),
        ("dsrf", "arclength", None),
        ("bilts", "angle", "ds_scale"),
    ],
)
def test_cached_pipeline_equals_compute_for_every_family(tiny, method, progress, extra) -> None:
    """Shared representations (DHB/eFS/ISA), arclength-normalized RRV/DSRF and BILTS all match
    ``compute`` on the trajectory at several parameter points of one task."""
    trials = tiny.models[::3] + tiny.test[:2]
    inputs = reparameterize_task(resample_task([r.data for r in trials]), progress, 0.3)
    xs = {"lam": [0.01, 10.0], "ds_scale": [0.05, 0.3], None: [None]}[extra]
    points = [{"progress": progress, "L": 0.3, **({extra: x} if extra else {})} for x in xs]
    results = evaluate_task(method, points, inputs[:3], inputs[3:])
    for params, pr in zip(points, results, strict=True):
        desc = get_descriptor(method, **params)
        direct = [desc.compute(Trajectory.from_array(r.data)) for r in trials]
        np.testing.assert_allclose(
            pr.distances, desc.distance_matrix(direct[3:], direct[:3]), rtol=1e-9
        )


def test_dsrf_prealign_undoes_a_world_rotation(tiny) -> None:
    from framefree.benchmark.figures import prealign

    m = next(r for r in tiny.models if r.gesture == "pour")
    q = next(r for r in tiny.test if r.gesture == "pour" and r.context == "world_frame_1")
    desc = get_descriptor("dsrf", progress="angle")
    A = desc.compute(Trajectory.from_array(m.data))
    B = desc.compute(Trajectory.from_array(q.data))
    assert np.linalg.norm(prealign(desc, A, B) - B) < 0.5 * np.linalg.norm(A - B)
    bp = get_descriptor("bilts+")
    assert prealign(bp, A, B) is A


def test_presmooth_extension_is_applied_before_progress(tiny) -> None:
    from framefree.core.progress import uniform_time_poses

    data = tiny.models[0].data
    raw, smooth = resample_task([data])[0], resample_task([data], presmooth=10)[0]
    np.testing.assert_allclose(
        smooth, uniform_time_poses(Trajectory.from_array(data), presmooth=10)
    )
    assert np.abs(raw - smooth).max() > 1e-4
    res = run_benchmark(tiny, [MethodSpec("dsrf", "angle")], SerialBackend(), presmooth=10)
    assert res.rows[0].per_context["original_2"] == 100.0
    assert res.settings["presmooth"] == 10


class _FakeFuture:
    def __init__(self, value) -> None:
        self.value = value

    def result(self):
        return self.value


def _fake_dask(submitted: list) -> tuple[types.ModuleType, types.ModuleType]:
    """Just enough of ``dask.distributed`` (Client.submit, as_completed) to run tasks here."""

    class Client:
        def __init__(self, address=None, **kwargs) -> None:
            self.closed = False

        def submit(self, fn, *args, pure=True):
            submitted.append(fn)
            return _FakeFuture(fn(*args))

        def close(self) -> None:
            self.closed = True

    dist = types.ModuleType("dask.distributed")
    dist.Client = Client
    dist.as_completed = lambda futures: reversed(list(futures))  # any completion order
    dask = types.ModuleType("dask")
    dask.distributed = dist
    dask.config = types.SimpleNamespace(set=lambda *args, **kwargs: contextlib.nullcontext())
    return dask, dist


def test_same_task_functions_run_on_dask_api(tiny, serial_result, monkeypatch) -> None:
    submitted: list = []
    dask, dist = _fake_dask(submitted)
    monkeypatch.setitem(sys.modules, "dask", dask)
    monkeypatch.setitem(sys.modules, "dask.distributed", dist)
    with make_backend("dask", jobs=2) as bk:
        res = run_benchmark(tiny, ROWS[:1], bk)
    assert submitted and res.backend.startswith("dask")
    assert res.rows[0].grid == serial_result.rows[0].grid
    assert res.rows[0].per_context == serial_result.rows[0].per_context
