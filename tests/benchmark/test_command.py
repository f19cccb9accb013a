"""``framefree benchmark`` on a dataset folder written by someone else in the same layout."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from framefree.cli import cli

from .conftest import RX90, RZ180, pose, write_dataset

#: other gesture, context and trial names than HPM's; a different model context
FOREIGN_CONTEXTS = {
    "reference": (None, None, 1.0),
    "repeat": (None, None, 1.0),
    "body_frame_a": (None, pose(RX90, (0, 0.05, 0)), 1.0),
    "world_frame_a": (pose(RZ180, (1.0, 0, 0)), None, 1.0),
    "world_frame_b": (pose(RX90, (0, 0, 1.0)), None, 1.0),
    "tilted_table": (pose(RX90, (0.2, 0.1, 0)), None, 1.0),
}


@pytest.fixture(scope="module")
def foreign_root(tmp_path_factory: pytest.TempPathFactory, real_dir: Path) -> Path:
    root = tmp_path_factory.mktemp("someone_elses_data")
    write_dataset(
        root,
        real_dir,
        FOREIGN_CONTEXTS,
        trial_names=("rec1", "rec2", "rec3", "rec4"),
        gestures={"wave": "ip_pouring_motion.csv", "spiral": "syn_helix_screw_wobble.csv"},
        seed=7,
    )
    return root


def test_command_on_foreign_layout(foreign_root: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    extra_json = tmp_path / "elsewhere" / "bench.json"
    res = CliRunner().invoke(
        cli,
        [
            "benchmark",
            "--data", str(foreign_root),
            "--model-context", "reference",
            "--methods", "bilts+:screw,dsrf:angle",
            "--jobs", "1",
            "--out", str(out),
            "--json", str(extra_json),
            "--quiet",
        ],
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "| BILTS+ | screw path |" in res.output
    # every context on disk is evaluated; the body/world-frame contexts are also pooled
    js = json.loads((out / "results.json").read_text())
    assert js == json.loads(extra_json.read_text())
    assert js["gestures"] == ["spiral", "wave"]
    assert js["contexts"] == [
        "body_frame_a",
        "repeat",
        "tilted_table",
        "world_frame_a",
        "world_frame_b",
    ]
    assert js["counts"] == {"models": 8, "train": 2 * 5 * 2, "test": 2 * 5 * 2}
    for row in js["rows"]:
        assert {
            "method",
            "progress",
            "trained_parameters",
            "per_context",
            "mean",
            "std",
            "seconds",
        } <= set(row)
        assert set(row["per_context"]) == set(js["contexts"])
        assert set(row["pooled"]) == {"body_frame", "world_frame"}
        assert all(0 <= v <= 100 for v in row["per_context"].values())
    bp = js["rows"][0]
    assert (bp["method"], bp["progress"]) == ("bilts+", "screw")
    assert set(bp["trained_parameters"]) == {"ds_scale", "L"}
    assert js["rows"][1]["trained_parameters"] == {}  # DSRF with angle progress trains nothing
    # Markdown in the paper's layout with the paper's numbers in parentheses; CSV; figures
    md = (out / "table1.md").read_text()
    assert "Δ{b}" in md and "Δ{w}" in md and "tilted_table" in md and "(100 ± 0.0)" in md
    with (out / "table1.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [r["method"] for r in rows] == ["bilts+", "dsrf"]
    assert rows[0]["paper_mean"] == "100.0"
    for name in ("heatmap.png", "alignment.png", "confusion/bilts+_screw.png".replace("+", "plus")):
        assert (out / name).stat().st_size > 1000


def test_command_rejects_unknown_method(foreign_root: Path, tmp_path: Path) -> None:
    res = CliRunner().invoke(
        cli,
        [
            "benchmark",
            "--data",
            str(foreign_root),
            "--methods",
            "nosuch:screw",
            "--out",
            str(tmp_path),
        ],
    )
    assert res.exit_code != 0
    assert "nosuch" in res.output


def test_command_reports_missing_model_context(foreign_root: Path, tmp_path: Path) -> None:
    res = CliRunner().invoke(
        cli,
        [
            "benchmark",
            "--data",
            str(foreign_root),
            "--methods",
            "bilts+:screw",
            "--out",
            str(tmp_path),
        ],
    )
    assert res.exit_code == 2
    assert "original_1" in res.output


def test_command_context_subset_recommended_row_and_early(
    foreign_root: Path, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    res = CliRunner().invoke(
        cli,
        [
            "benchmark",
            "--data", str(foreign_root),
            "--model-context", "reference",
            "--contexts", "repeat,world_frame_a",
            "--methods", "recommended",
            "--early",
            "--jobs", "1",
            "--no-figures",
            "--out", str(out),
            "--quiet",
        ],
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    js = json.loads((out / "results.json").read_text())
    assert js["contexts"] == ["repeat", "world_frame_a"]
    assert js["counts"] == {"models": 8, "train": 2 * 2 * 2, "test": 2 * 2 * 2}
    # --early adds the faithful BILTS+ row beside the recommended one
    assert [r["method"] for r in js["rows"]] == ["recommended", "bilts+"]
    rec = js["rows"][0]
    assert rec["descriptor"] == "bilts+" and rec["label"].startswith("framefree (recommended)")
    assert rec["descriptor_parameters"]["open_end"] is True
    assert rec["descriptor_parameters"]["presmooth"] == 5
    assert "| framefree (recommended) | screw path |" in res.output
    early = json.loads((out / "early.json").read_text())
    assert early["fractions"] == [0.25, 0.5, 0.75, 1.0]
    assert set(early["rows"]) == {"recommended", "bilts+:screw"}
    for key, row in early["rows"].items():
        # at 100 % the early classification is the test classification of the row
        ref = next(
            r
            for r in js["rows"]
            if (r["method"] if r["method"] == "recommended" else f"{r['method']}:{r['progress']}")
            == key
        )
        assert row["overall"][-1] == pytest.approx(ref["overall"])
    assert (out / "early.png").stat().st_size > 1000


def test_command_reports_unknown_context(foreign_root: Path, tmp_path: Path) -> None:
    res = CliRunner().invoke(
        cli,
        [
            "benchmark",
            "--data", str(foreign_root),
            "--model-context", "reference",
            "--contexts", "repeat,sideways",
            "--methods", "bilts+:screw",
            "--out", str(tmp_path),
        ],
    )  # fmt: skip
    assert res.exit_code == 2
    assert "sideways" in res.output and "Traceback" not in res.output
