"""`framefree describe` and `framefree classify` from the command line."""

from __future__ import annotations

import json
import shutil

import numpy as np
from click.testing import CliRunner

from framefree.cli import cli


def test_help_reads_well():
    result = CliRunner().invoke(cli, ["--help"])
    assert result.exit_code == 0
    assert "describe" in result.output and "classify" in result.output
    sub = CliRunner().invoke(cli, ["describe", "--help"])
    assert "--ds-scale" in sub.output and "Scale length" in sub.output


def test_describe_writes_descriptor_csv(tmp_path, kettle_files):
    result = CliRunner().invoke(
        cli, ["describe", str(kettle_files[0]), "-o", str(tmp_path), "--L", "0.3"]
    )
    assert result.exit_code == 0, result.output
    out = tmp_path / f"{kettle_files[0].stem}_biltsplus.csv"
    header = out.read_text().splitlines()[0].split(",")
    assert header[0] == "Lw_prev_x" and header[-1] == "sigma_v_3"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape[1] == 24 and np.isfinite(data).all()


def test_classify_against_labelled_folder(tmp_path, kettle_files, real_dir):
    models = tmp_path / "models"
    (models / "pour").mkdir(parents=True)
    (models / "scoop").mkdir()
    shutil.copy(kettle_files[0], models / "pour")
    shutil.copy(real_dir / "reference_set" / "ip_scooping_motion.csv", models / "scoop")
    queries = [
        str(kettle_files[3]),
        str(real_dir / "reference_set" / "ip_scooping_motion__tfworld.csv"),
    ]
    js = tmp_path / "out.json"
    result = CliRunner().invoke(cli, ["classify", "-m", str(models), *queries, "--json", str(js)])
    assert result.exit_code == 0, result.output
    labels = [r["label"] for r in json.loads(js.read_text())["results"]]
    assert labels == ["pour", "scoop"]


def test_bad_input_is_one_clear_line_and_nonzero_exit(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("0,1,2,3,4,5,6,7\n0.02,1,2,x,4,5,6,7\n")
    result = CliRunner().invoke(cli, ["describe", str(bad)])
    assert result.exit_code == 2
    assert f"{bad}, row 2: column 4: 'x' is not a number" in result.output
    assert "Traceback" not in result.output
    still = tmp_path / "still.csv"
    still.write_text("".join(f"{0.02 * k},0.1,0.2,0.3,1,0,0,0\n" for k in range(50)))
    result = CliRunner().invoke(cli, ["describe", str(still)])
    assert result.exit_code == 2 and "no screw progress" in result.output


def test_a_motionless_recording_has_no_progress_even_presmoothed(tmp_path):
    """Pre-smoothing (the recommended settings) leaves rounding noise on a motionless recording;
    it is still refused as motionless, not described as noise."""
    import numpy as np
    import pytest

    from framefree import NearestNeighborClassifier, Trajectory
    from framefree.errors import DegenerateMotionError

    t = 0.02 * np.arange(50)
    still = Trajectory(t, np.tile([0.1, 0.2, 0.3], (50, 1)), np.tile([1.0, 0, 0, 0], (50, 1)))
    with pytest.raises(DegenerateMotionError, match="no screw progress"):
        NearestNeighborClassifier().build_descriptor().compute(still)
    with pytest.raises(DegenerateMotionError, match="no screw progress"):
        NearestNeighborClassifier.paper().build_descriptor().compute(still)


def test_classify_defaults_are_the_recommended_settings(tmp_path, kettle_files):
    """``classify`` builds NearestNeighborClassifier()'s descriptor unless told ``--preset paper``."""
    import shutil

    from framefree import NearestNeighborClassifier

    models = tmp_path / "models" / "pour"
    models.mkdir(parents=True)
    for f in kettle_files[:2]:
        shutil.copy(f, models)
    shutil.copytree(models, tmp_path / "models" / "pour_too")
    shown = {}
    for preset in ("recommended", "paper"):
        js = tmp_path / f"{preset}.json"
        flag = [] if preset == "recommended" else ["--preset", "paper"]
        res = CliRunner().invoke(cli, ["classify", "-m", str(tmp_path / "models"),
                                       str(kettle_files[3]), *flag, "--json", str(js)])
        assert res.exit_code == 0, res.output
        shown[preset] = json.loads(js.read_text())["descriptor"]
    assert shown["recommended"] == repr(NearestNeighborClassifier().build_descriptor())
    assert shown["paper"] == repr(NearestNeighborClassifier.paper().build_descriptor())
