"""Every newcomer's mistake is one line naming the problem, exit status 2, no traceback
(unless ``--debug``); warnings for input that reads but looks wrong."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from cli_helpers import free_port, one_line_error, run


@pytest.fixture
def kettle(kettle_files) -> Path:
    return kettle_files[0]


def test_a_png_given_as_a_pose_file(tmp_path):
    png = Path(__file__).resolve().parents[2] / "docs" / "images" / "replica_gallery.png"
    one_line_error(run("describe", png, "-o", tmp_path), "PNG image, not a pose CSV")
    one_line_error(run("plot", png, "-o", tmp_path / "x.png"), "PNG image, not a pose CSV")


def test_a_png_given_as_a_query_is_not_a_pose_recording(tmp_path):
    """A query that is not a .csv is read as a recording of several trackers: a PNG is named as
    one, not taken for a broken Machete file."""
    from cli_helpers import tiny_dataset

    png = Path(__file__).resolve().parents[2] / "docs" / "images" / "replica_gallery.png"
    tiny_dataset(tmp_path / "models", ("go_left", "open_gripper"), ("go_left",))
    line = one_line_error(run("classify", png, "-m", tmp_path / "models"),
                          "replica_gallery.png", "PNG image, not a pose recording")
    assert "Machete" not in line.split("not a pose recording")[0]


def test_a_binary_file_and_a_folder(tmp_path):
    blob = tmp_path / "blob.bin"
    blob.write_bytes(bytes(range(256)) * 4)
    one_line_error(run("describe", blob, "-o", tmp_path), "blob.bin", "binary data")
    one_line_error(run("describe", tmp_path, "-o", tmp_path), "is a folder, not a pose CSV")


def test_a_header_row_and_skip_header(tmp_path, kettle):
    with_header = tmp_path / "h.csv"
    with_header.write_text("time,px,py,pz,w,i,j,k\n" + kettle.read_text())
    one_line_error(run("describe", with_header, "-o", tmp_path), "looks like a header row",
                   "--skip-header")
    res = run("describe", with_header, "--skip-header", "-o", tmp_path / "out")
    assert res.exit_code == 0, res.output
    res = run("describe", kettle, "-o", tmp_path / "ref")
    assert (tmp_path / "out" / "h_biltsplus.csv").read_text() == (
        tmp_path / "ref" / f"{kettle.stem}_biltsplus.csv"
    ).read_text()


@pytest.mark.parametrize("flag", [[], ["--skip-header"]])
def test_the_natural_header_in_queries_and_model_folders(tmp_path, flag):
    """``t,x,y,z,qw,qx,qy,qz`` is a single-tracker header (not a multi-tracker one), in a query
    and in every file of a --models folder; ``--skip-header`` reaches the model files too."""
    from cli_helpers import tiny_dataset

    plain = tmp_path / "plain"
    tiny_dataset(plain, ("go_left", "open_gripper"), ("go_left",))
    headed = tmp_path / "headed"
    header = "t,x,y,z,qw,qx,qy,qz\n" if not flag else "time,px,py,pz,w,i,j,k\n"
    for f in plain.glob("*/original_1/*.csv"):
        out = headed / f.relative_to(plain)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(header + f.read_text())
    query = headed / "go_left" / "original_1" / "trial_1.csv"
    results = []
    for models in (plain, headed):
        res = run("classify", query, "--models", models, *flag, "--json", tmp_path / "r.json")
        assert res.exit_code == 0, res.output
        results.append(json.loads((tmp_path / "r.json").read_text())["results"])
    assert results[0] == results[1] and results[0][0]["label"] == "go_left"


def test_another_separator_is_named(tmp_path, kettle):
    semi = tmp_path / "semi.csv"
    semi.write_text(kettle.read_text().replace(",", ";"))
    one_line_error(run("describe", semi, "-o", tmp_path), "separated by semicolons")


def test_unwritable_outputs(tmp_path, kettle, kettle_files):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    one_line_error(run("describe", kettle, "-o", blocker / "sub"), "cannot create this output folder",
                   "--out")
    one_line_error(run("plot", kettle, "-o", blocker / "p.png"), "--out")
    models = tmp_path / "models" / "pour"
    models.mkdir(parents=True)
    shutil.copy(kettle, models)
    one_line_error(run("classify", "-m", tmp_path / "models", kettle_files[1], "--json",
                       blocker / "r.json"), "--json")
    one_line_error(run("benchmark", "--out", blocker / "b", "--quiet"), "--out")


def test_millimetres_warn_and_units_fix_it(tmp_path, kettle):
    data = np.loadtxt(kettle, delimiter=",")
    data[:, 1:4] *= 1000
    mm = tmp_path / "mm.csv"
    np.savetxt(mm, data, delimiter=",", fmt="%.17g")
    res = run("describe", mm, "-o", tmp_path / "a")
    assert res.exit_code == 0
    assert "warning: " in res.output and "positions look like millimetres" in res.output
    assert "use --units mm" in res.output
    res = run("describe", mm, "-o", tmp_path / "b", "--units", "mm")
    assert res.exit_code == 0 and "warning" not in res.output
    ref = run("describe", kettle, "-o", tmp_path / "c")
    assert ref.exit_code == 0
    a = np.loadtxt(tmp_path / "b" / "mm_biltsplus.csv", delimiter=",", skiprows=1)
    b = np.loadtxt(tmp_path / "c" / f"{kettle.stem}_biltsplus.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-9)


def test_classify_quat_order_applies_to_queries_not_models(tmp_path, kettle_files, real_dir):
    from framefree import Trajectory

    models = tmp_path / "models"
    (models / "pour").mkdir(parents=True)
    (models / "scoop").mkdir()
    shutil.copy(kettle_files[0], models / "pour")
    shutil.copy(real_dir / "reference_set" / "ip_scooping_motion.csv", models / "scoop")
    query = tmp_path / "scoop_xyzw.csv"
    Trajectory.from_csv(real_dir / "reference_set" / "ip_scooping_motion__tfworld.csv").to_csv(
        query, quat_order="xyzw"
    )
    res = run("classify", "-m", models, query, "--quat-order", "xyzw", "--json", tmp_path / "r.json")
    assert res.exit_code == 0, res.output
    assert "labelled" in res.output or "<label>/*.csv" in res.output
    assert json.loads((tmp_path / "r.json").read_text())["results"][0]["label"] == "scoop"
    # models stored scalar-last need their own option
    xyzw_models = tmp_path / "xyzw_models"
    for label in ("pour", "scoop"):
        (xyzw_models / label).mkdir(parents=True)
        for f in (models / label).glob("*.csv"):
            Trajectory.from_csv(f).to_csv(xyzw_models / label / f.name, quat_order="xyzw")
    res = run("classify", "-m", xyzw_models, "--model-quat-order", "xyzw", query, "--quat-order",
              "xyzw", "--json", tmp_path / "r2.json")
    assert res.exit_code == 0, res.output
    assert json.loads((tmp_path / "r2.json").read_text())["results"][0]["label"] == "scoop"


def test_classify_takes_a_dataset_root_and_says_so(tmp_path, kettle_files, real_dir):
    root = tmp_path / "ds"
    for label, src in (("pour", kettle_files[0]), ("scoop", real_dir / "reference_set" /
                                                    "ip_scooping_motion.csv")):
        for ctx in ("original_1", "other"):
            (root / label / ctx).mkdir(parents=True)
            shutil.copy(src, root / label / ctx / "trial_1.csv")
    res = run("classify", "-m", root, kettle_files[3])
    assert res.exit_code == 0, res.output
    assert "dataset root, context 'original_1'" in res.output and "2 recordings of 2 labels" in res.output
    one_line_error(run("classify", "-m", root, "--model-context", "nope", kettle_files[3]),
                   "no model context folder 'nope'", "--model-context")
    (root / "pour" / "loose.csv").write_text("")
    one_line_error(run("classify", "-m", root, kettle_files[3]), "mixes <label>/*.csv files")


def test_jobs_must_be_at_least_one():
    for jobs in ("0", "-3"):
        res = run("benchmark", "--jobs", jobs, "--quiet")
        assert res.exit_code == 2 and "Traceback" not in res.output
        assert "--jobs" in res.output and "x>=1" in res.output


def test_unreachable_dask_scheduler_fails_fast(tmp_path):
    pytest.importorskip("dask.distributed")
    address = f"tcp://127.0.0.1:{free_port()}"
    one_line_error(
        run("benchmark", "--backend", "dask", "--address", address, "--connect-timeout", "1",
            "--out", tmp_path, "--quiet"),
        address, "no Dask scheduler answered within 1 s",
    )


def test_ray_without_an_address_starts_nothing(tmp_path):
    pytest.importorskip("ray")
    one_line_error(run("benchmark", "--backend", "ray", "--out", tmp_path, "--quiet"),
                   "starts no local Ray cluster")


def test_debug_shows_the_traceback(tmp_path):
    png = Path(__file__).resolve().parents[2] / "docs" / "images" / "replica_gallery.png"
    res = run("--debug", "describe", png, "-o", tmp_path)
    assert res.exit_code != 0
    assert res.exc_info is not None and "PNG image" in str(res.exc_info[1])
