"""The vocabulary check: passes the HPM seven, flags a confusable pair, probes, figures."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from framefree.core import se3
from framefree.library import (
    CheckReport,
    CheckSettings,
    TakeSet,
    check_takes,
    descriptor_for,
    everyday_motions,
    perturbed,
    plot_distance_map,
    plot_take_gallery,
    slowest_stop_speed,
    stop_rotations,
)
from framefree.online import Recognizer, RecognizerConfig
from framefree.online.model_settings import model_window_spacing
from framefree.online.stop import sustained_peak_speed
from framefree.replica import synthesize_gesture

from .conftest import scaled


@pytest.fixture(scope="module")
def hpm_report(hpm_takes: TakeSet) -> CheckReport:
    return check_takes(hpm_takes)


@pytest.fixture(scope="module")
def confusable(hpm_takes: TakeSet) -> tuple[TakeSet, CheckReport]:
    """The HPM seven plus a straight line only 20 % longer than go_left, from 5 new performances."""
    rng = np.random.default_rng(5)
    longer = tuple(scaled(synthesize_gesture("go_left", rng), 1.2, f"long {k}") for k in range(5))
    extra = TakeSet(longer, ("go_left_long",) * 5, tuple(f"go_left_long/own/trial_{k + 1}" for k in range(5)))
    vocab = hpm_takes + extra
    return vocab, check_takes(vocab)


def test_hpm_seven_pass(hpm_report: CheckReport) -> None:
    assert hpm_report.ok, hpm_report.format()
    assert not [f for f in hpm_report.findings if f.level == "problem"]
    assert sum(p == g for p, g in zip(hpm_report.predicted, hpm_report.labels, strict=True)) >= 30
    for c in hpm_report.gestures.values():
        assert c.loo_correct > c.takes / 2
        assert c.margin >= 1.5 and c.nearest in hpm_report.gestures and c.nearest != c.gesture
        # every copy of every take is recognized after frames, grip, speed and size change
        assert c.perturbed_correct == c.takes and c.perturbed_taken_for is None


def test_confusable_pair_is_flagged(confusable: tuple[TakeSet, CheckReport]) -> None:
    _, report = confusable
    assert not report.ok
    pair = {"go_left", "go_left_long"}
    assert report.gestures["go_left"].nearest == "go_left_long"
    assert report.gestures["go_left_long"].nearest == "go_left"
    problems = [f for f in report.findings if f.level == "problem" and f.gesture in pair]
    assert problems and all(set(f.message.split()) & pair for f in problems)
    assert any("within" in f.message and "go_left_long" in f.message and "more distinct" in f.message
               for f in report.findings)
    # the other gestures keep their verdicts
    assert report.gestures["go_down"].margin > 5


def test_report_table_and_dict(confusable: tuple[TakeSet, CheckReport]) -> None:
    vocab, report = confusable
    text = report.format()
    assert "go_left_long" in text and "PROBLEM" in text
    d = report.to_dict()
    assert d["ok"] is False and len(d["takes"]) == len(vocab)
    assert set(d["gestures"]) == set(vocab.gestures)
    np.testing.assert_allclose(np.diag(report.distances), 0.0, atol=1e-12)


def test_distances_are_the_recognizers(hpm_takes: TakeSet) -> None:
    """The check classifies with the recognizer's own descriptor settings."""
    cfg = RecognizerConfig()
    few = hpm_takes.without(["go_up", "go_down", "go_home", "open_gripper", "close_gripper"])
    taus = dict.fromkeys(few.gestures, 1.0)
    rec = Recognizer.from_trajectories(list(few.takes), list(few.labels), cfg, gesture_thresholds=taus,
                                       stop_threshold=10.0)
    # the recognizer fixes its window spacing from the takes, as the check does
    assert rec.learned_.window_spacing == model_window_spacing(list(few.takes), cfg)
    desc = descriptor_for(rec.config, rec.learned_.window_spacing)
    mine = [desc.compute(tr) for tr in few.takes]
    for a, b in zip(mine, rec.classifier.models, strict=True):
        np.testing.assert_array_equal(a, b)


def test_perturbed_copy_changes_frames_and_speed(hpm_takes: TakeSet) -> None:
    take = hpm_takes.takes[0]
    rng = np.random.default_rng(1)
    copy = perturbed(take, rng, speed_range=(2.0, 2.0 + 1e-12))
    assert copy.duration == pytest.approx(take.duration / 2.0, abs=0.03)
    assert not np.allclose(copy.p[0], take.p[0])
    desc = descriptor_for()
    d_self = desc.distance_matrix([desc.compute(copy)], [desc.compute(take)])[0, 0]
    d_other = desc.distance_matrix([desc.compute(copy)], [desc.compute(hpm_takes.takes[-1])])[0, 0]
    assert d_self < d_other


def test_stop_probes_are_fast_and_everyday_probes_are_not(hpm_takes: TakeSet) -> None:
    rng = np.random.default_rng(2)
    take = hpm_takes.takes[3]
    slowest = slowest_stop_speed()
    for stop in stop_rotations(take, rng, 3):
        assert sustained_peak_speed(stop.t, stop.q) >= 0.9 * slowest
    kinds = [k for k, _ in everyday_motions(take, rng)]
    assert kinds[:2] == ["reach", "reach and return"] and "moves" in kinds
    for _, tr in everyday_motions(take, rng):
        assert sustained_peak_speed(tr.t, tr.q) < 0.8 * slowest


def test_figures(confusable: tuple[TakeSet, CheckReport], tmp_path: Path) -> None:
    vocab, report = confusable
    a = plot_distance_map(report, tmp_path / "d.png")
    b = plot_take_gallery(vocab, tmp_path / "sub" / "g.png")
    for f in (a, b):
        assert f.is_file() and f.stat().st_size > 10_000


def test_stop_probes_follow_the_simulated_people() -> None:
    from framefree.library import probes
    from framefree.replica.streams import STOP_SIGNAL

    assert probes.STOP_AMPLITUDE == pytest.approx(STOP_SIGNAL["amplitude"])
    assert probes.STOP_STROKE == pytest.approx(STOP_SIGNAL["stroke"])


def test_a_gesture_that_differs_only_in_amount_is_flagged(hpm_takes: TakeSet) -> None:
    """A push with a quarter twist is *open gripper*'s forearm screw with less turn: the takes tell
    them apart, but a person with a longer or shorter push does not (measured live, it costs
    *open gripper* 5-10 points); the size probe lets the check see it."""
    rng = np.random.default_rng(8)
    twist = tuple(synthesize_gesture("push_twist", rng) for _ in range(5))
    vocab = hpm_takes + TakeSet(twist, ("push_twist",) * 5,
                                tuple(f"push_twist/own/trial_{k + 1}" for k in range(5)))
    report = check_takes(vocab)
    assert report.gestures["push_twist"].loo_correct == 5  # apart as demonstrated
    flagged = [f for f in report.findings if "change of frames, grip, speed or size" in f.message
               and {"push_twist", "open_gripper"} <= set(f.message.replace(",", " ").replace(")", " ")
                                                         .split())]
    assert flagged and all("in amount" in f.message for f in flagged), report.format()
    without_size = check_takes(vocab, settings=CheckSettings(size_range=(1.0, 1.0)))
    assert all(c.perturbed_correct == c.takes for c in without_size.gestures.values())


def test_size_change_scales_the_path_and_keeps_the_turn(hpm_takes: TakeSet) -> None:
    take = hpm_takes.takes[2]
    same, larger = (perturbed(take, np.random.default_rng(3), body_offset=0.0, speed_range=(1.0, 1.0),
                              size_range=(f, f + 1e-12)) for f in (1.0, 1.3))
    travel = [float(np.linalg.norm(np.diff(tr.p, axis=0), axis=1).sum()) for tr in (same, larger)]
    assert travel[1] == pytest.approx(1.3 * travel[0], rel=0.01)
    turn = [float(np.linalg.norm(se3.vector_from_rotation(
        tr.rotations()[:-1].transpose(0, 2, 1) @ tr.rotations()[1:]), axis=1).sum())
            for tr in (same, larger)]
    assert turn[1] == pytest.approx(turn[0], rel=0.01)


def test_one_stroke_in_two_directions_needs_the_vertical(hpm_takes: TakeSet) -> None:
    """go_left turned upright is go_left to full invariance, and another gesture to gravity."""
    rng = np.random.default_rng(11)
    upright = []
    for _ in range(5):
        tr = synthesize_gesture("go_left", rng)
        W = np.eye(4)
        W[:3, :3] = se3.rotation_from_vector(np.array([[np.pi / 2, 0.0, 0.0]]))[0]  # about forward x
        W[:3, 3] = tr.p[0] - W[:3, :3] @ tr.p[0]
        upright.append(tr.transformed(world=W))
    extra = TakeSet(tuple(upright), ("swipe_up",) * 5, tuple(f"swipe_up/own/trial_{k + 1}" for k in range(5)))
    report = check_takes(hpm_takes + extra)
    direction = [f for f in report.findings if "differ mainly in direction" in f.message]
    assert {f.gesture for f in direction} & {"swipe_up", "go_left"}, report.format()


def test_hpm_seven_need_no_vertical(hpm_report: CheckReport) -> None:
    assert not [f for f in hpm_report.findings if "direction" in f.message]


def test_takes_that_are_the_way_back_are_flagged(hpm_takes: TakeSet, hpm_report: CheckReport) -> None:
    """A zigzag recorded with its ways back kept (``record --keep-all``): its takes fall into two
    groups, and check names the ways back; the HPM seven's takes form one group each."""
    from framefree.library import TakeRecorder
    from framefree.replica import person
    from framefree.replica.people_streams import take_session

    session = take_session("zigzag", person(3), n_takes=4, seed=3)
    rec = TakeRecorder(keep_all=True)
    for t, p, q in zip(session.traj.t, session.traj.p, session.traj.q, strict=True):
        rec.push(t, p, q)
    takes = [tk for _, tk in rec.finish()]
    assert len(takes) == 7
    names = tuple(f"zigzag/own/trial_{k + 1}" for k in range(len(takes)))
    report = check_takes(hpm_takes + TakeSet(tuple(takes), ("zigzag",) * len(takes), names))
    found = [f.message for f in report.findings if f.gesture == "zigzag" and "two groups" in f.message]
    assert len(found) == 1
    ways_back = ", ".join(names[k] for k in (1, 3, 5))
    assert f"{ways_back} unlike" in found[0] and "--remove zigzag/own/trial_2" in found[0]
    assert not [f for f in hpm_report.findings if "two groups" in f.message]
