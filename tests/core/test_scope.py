"""Queries far outside the models' range (far longer, larger or slower than any model) are said
``no_gesture`` with a warning by ``classify``, not given a confident label; ``describe`` says when
it reduces a long recording to few samples."""

from __future__ import annotations

import json

import pytest

from cli_helpers import run, tiny_dataset
from framefree import Trajectory
from framefree.scope import model_scope, out_of_scope


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    root = tmp_path_factory.mktemp("scope")
    tiny_dataset(root, ("go_left", "open_gripper"), ("go_left",))
    return root


def _variants(tiny, tmp_path):
    """A model-like query and its far longer (and slower) and far larger versions, as files."""
    base = Trajectory.from_csv(tiny / "go_left" / "original_1" / "trial_1.csv")
    out = {"plain": base, "long": base.time_scaled(2000.0),
           "large": base.path_scaled(11.0).time_scaled(3.0)}
    paths = {}
    for name, traj in out.items():
        paths[name] = tmp_path / f"{name}.csv"
        traj.to_csv(paths[name])
    return out, paths


def test_out_of_scope_names_the_reason(tiny, tmp_path):
    trajs, _ = _variants(tiny, tmp_path)
    models = [Trajectory.from_csv(f) for f in sorted(tiny.glob("*/original_1/*.csv"))]
    scope = model_scope(models)
    assert out_of_scope(trajs["plain"], scope) is None
    assert "far longer than any gesture" in out_of_scope(trajs["long"], scope)
    assert "h, the longest model" in out_of_scope(trajs["long"], scope)
    assert "far larger than any gesture" in out_of_scope(trajs["large"], scope)
    slow = trajs["plain"].time_scaled(20.0)
    slow = Trajectory(slow.t[::20], slow.p[::20], slow.q[::20])
    assert "far slower" in out_of_scope(slow, scope) or "far longer" in out_of_scope(slow, scope)


def test_classify_says_no_gesture_for_an_implausible_query(tiny, tmp_path):
    _, paths = _variants(tiny, tmp_path)
    res = run("classify", paths["plain"], paths["long"], paths["large"], "--models", tiny,
              "--json", tmp_path / "r.json")
    assert res.exit_code == 0, res.output
    rows = {r["query"]: r for r in json.loads((tmp_path / "r.json").read_text())["results"]}
    assert rows[str(paths["plain"])]["label"] == "go_left"
    for name in ("long", "large"):
        row = rows[str(paths[name])]
        assert row["label"] == "no_gesture" and row["out_of_scope"] and row["margin"] is None
        assert f"warning: {paths[name]}: " in res.stderr
    forced = run("classify", paths["long"], "--models", tiny, "--force", "--json", tmp_path / "f.json")
    assert forced.exit_code == 0, forced.output
    (row,) = json.loads((tmp_path / "f.json").read_text())["results"]
    assert row["label"] == "go_left" and row["out_of_scope"] is None


def test_describe_says_when_it_reduces_a_recording(tiny, tmp_path):
    _, paths = _variants(tiny, tmp_path)
    res = run("describe", paths["plain"], "-o", tmp_path / "d")
    assert res.exit_code == 0 and "note:" not in res.stderr
    assert "poses over" in res.stdout
    base = Trajectory.from_csv(paths["plain"])
    dense = base.resampled(dt=float(base.t[1] - base.t[0]) / 20.0)  # 20 times the poses
    dense.to_csv(tmp_path / "dense.csv")
    res = run("describe", tmp_path / "dense.csv", "-o", tmp_path / "d")
    assert res.exit_code == 0, res.output
    assert f"note: {tmp_path / 'dense.csv'}: {len(dense)} poses" in res.stderr
    assert "a descriptor describes one gesture" in res.stderr
