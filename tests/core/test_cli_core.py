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
