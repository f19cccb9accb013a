"""The cached replica: generated once, atomically, reused; deterministic from the seed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from framefree.datasets import load_dataset
from framefree.replica import REPLICA_VERSION, generator_fingerprint, make_replica, replica_path


def test_replica_path_generates_once_and_reuses(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setenv("FRAMEFREE_CACHE", str(tmp_path / "cache"))
    p = replica_path(seed=3)
    assert p.name == f"hpm-replica-v{REPLICA_VERSION}-{generator_fingerprint()}-seed3"
    assert p.parent == tmp_path / "cache"
    assert len(list(p.glob("*/*/trial_*.csv"))) == 560  # 7 gestures × 16 contexts × 5 trials
    assert len(list((p / "streams").glob("stream_*_labels.csv"))) == 3
    assert [x.name for x in p.parent.iterdir()] == [p.name]  # no temporary folder left behind
    stamp = (p / "go_up" / "original_1" / "trial_1.csv").stat().st_mtime_ns
    assert replica_path(seed=3) == p
    assert (p / "go_up" / "original_1" / "trial_1.csv").stat().st_mtime_ns == stamp


def test_same_seed_same_files(replica_root: Path, tmp_path: Path) -> None:
    again = make_replica(tmp_path / "again", seed=7, n_streams=0)
    for rel in ("go_home/original_1/trial_2.csv", "open_gripper/combination/trial_5.csv"):
        np.testing.assert_array_equal(np.loadtxt(replica_root / rel, delimiter=","),
                                      np.loadtxt(again / rel, delimiter=","))
    other = make_replica(tmp_path / "other", seed=8, n_streams=0)
    a = load_dataset(again).trials[0].trajectory
    b = load_dataset(other).trials[0].trajectory
    assert len(a) != len(b) or not np.allclose(a.p, b.p)
