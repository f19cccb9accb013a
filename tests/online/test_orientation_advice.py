"""Takes without orientation: a sensor of positions only (a skeleton's wrist joint, a marker)
writes one quaternion throughout. The recognizer still works on the hand's path, but the stop
signal cannot be made and a gesture and its mirror image cannot be told apart, so `enroll`,
`check`, `live` and `evaluate-stream` say so in one line. Real Vive recordings."""

from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from framefree.cli import cli
from framefree.core.trajectory import Trajectory
from framefree.online.model_settings import STILL_ORIENTATION, orientation_advice
from real_data import shipped_right_controller


def with_quaternion(traj: Trajectory, q: np.ndarray) -> Trajectory:
    """``traj``'s positions with one quaternion (w, x, y, z) throughout."""
    return Trajectory(traj.t, traj.p, np.tile(q, (len(traj), 1)))


@pytest.fixture(scope="module")
def vive() -> tuple[list[Trajectory], list[str]]:
    """The right controller's recordings of the shipped real people."""
    return shipped_right_controller()


def test_real_six_dof_takes_get_no_note(vive):
    trajs, _ = vive
    assert orientation_advice(trajs) is None


def test_the_same_takes_without_orientation_get_the_note(vive):
    trajs, _ = vive
    advice = orientation_advice([with_quaternion(t, np.array([1.0, 0, 0, 0])) for t in trajs])
    assert advice is not None
    assert "no orientation" in advice and "stop signal" in advice and "mirror image" in advice
    assert "--no-hand-frame" in advice  # cones of the sensor's frame refuse (v33)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(
    lambda v: np.linalg.norm(v) > 0.1))
def test_any_constant_quaternion_is_no_orientation(q):
    q = np.asarray(q) / np.linalg.norm(q)
    t = np.linspace(0.0, 1.0, 50)
    traj = with_quaternion(Trajectory(t, np.column_stack([t, 0 * t, 0 * t]),
                                      np.tile([1.0, 0, 0, 0], (50, 1))), q)
    assert orientation_advice([traj, traj]) is not None


@pytest.mark.parametrize("degrees, noted", [(0.5, True), (2.0, False)])
def test_one_take_that_turns_more_than_the_tolerance_is_enough(degrees, noted):
    assert math.degrees(STILL_ORIENTATION) == pytest.approx(1.0)
    t = np.linspace(0.0, 1.0, 50)
    p = np.column_stack([t, 0 * t, 0 * t])
    still = Trajectory(t, p, np.tile([1.0, 0, 0, 0], (50, 1)))
    half = np.radians(degrees) * t / 2  # about z, from 0 to `degrees`
    turning = Trajectory(t, p, np.column_stack([np.cos(half), 0 * t, 0 * t, np.sin(half)]))
    assert (orientation_advice([still, turning]) is not None) is noted


def test_no_takes_no_note():
    assert orientation_advice([]) is None


def test_enroll_and_check_note_takes_without_orientation(vive, tmp_path):
    trajs, labels = vive
    takes = tmp_path / "takes"
    for k, (tr, g) in enumerate(zip(trajs, labels, strict=True)):
        if g in ("cartwheel_left", "cartwheel_right", "golf_swing"):
            with_quaternion(tr, np.array([1.0, 0, 0, 0])).to_csv(takes / g / "own" / f"{k:02d}.csv")
    lib = tmp_path / "lib.npz"
    res = CliRunner().invoke(cli, ["enroll", str(takes), "-o", str(lib)])
    assert res.exit_code == 0, res.output
    assert "note: the takes hold no orientation" in res.output
    res = CliRunner().invoke(cli, ["check", str(lib), "--out", str(tmp_path / "report")])
    assert "the takes hold no orientation" in res.output
    # the mirror cartwheels are named as lying near each other
    assert "nearer to cartwheel_right than to the other takes of cartwheel_left" in res.output or \
        "nearer to cartwheel_left than to the other takes of cartwheel_right" in res.output


def test_evaluate_stream_notes_models_without_orientation(vive, tmp_path):
    trajs, labels = vive
    models = tmp_path / "models"
    identity = np.array([1.0, 0, 0, 0])
    for k, (tr, g) in enumerate(zip(trajs, labels, strict=True)):
        (models / g).mkdir(parents=True, exist_ok=True)
        with_quaternion(tr, identity).to_csv(models / g / f"{k:02d}.csv")
    stream = tmp_path / "stream.csv"
    with_quaternion(trajs[0], identity).to_csv(stream)
    (tmp_path / "stream_labels.csv").write_text(f"label,start_t,end_t\n{labels[0]},"
                                                f"{trajs[0].t[0]:.3f},{trajs[0].t[-1]:.3f}\n")
    res = CliRunner().invoke(cli, ["evaluate-stream", "--models", str(models), "--stream",
                                   str(stream)])
    assert res.exit_code == 0, res.output
    assert "note: the takes hold no orientation" in res.output
