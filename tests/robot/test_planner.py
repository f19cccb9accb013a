"""Planner FSM: each event's command, stop precedence, bounded accelerations, repeats, unknowns."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.online.events import Event
from framefree.robot.planner import Planner, PlannerParams

DT = 0.002


def pose(p):
    T = np.eye(4)
    T[:3, 3] = p
    return T


class FollowingArm:
    """A perfect arm: the TCP moves exactly with the commanded velocity (unless blocked)."""

    def __init__(self, planner: Planner, p0=(0.5, 0.0, 0.2)):
        self.planner = planner
        self.p = np.array(p0, dtype=float)
        self.p_ref = self.p.copy()
        self.commands = []
        self.block_z: float | None = None

    def run(self, seconds: float):
        for _ in range(round(seconds / DT)):
            c = self.planner.step(DT, pose(self.p))
            self.commands.append(c)
            self.p_ref = self.p_ref + c.velocity * DT
            self.p = self.p_ref.copy()
            if self.block_z is not None:
                self.p[2] = max(self.p[2], self.block_z)
        return self

    @property
    def velocities(self):
        return np.array([c.velocity for c in self.commands])


def ev(label, t=0.0):
    return Event(label, t, 0.1, 0)


@pytest.mark.parametrize(
    ("label", "axis"),
    [("go_left", (0, 1, 0)), ("go_right", (0, -1, 0)), ("go_up", (0, 0, 1)), ("go_down", (0, 0, -1))],
)
def test_directional_events_move_along_base_axes_for_their_travel(label, axis):
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner)
    p0 = arm.p.copy()
    assert planner.handle(ev(label)).reason == "started"
    arm.run(1.5)
    v = arm.commands[-1].velocity
    np.testing.assert_allclose(v, params.speed * np.array(axis), atol=1e-12)  # cruise
    assert np.all(arm.commands[-1].twist[:3] == 0)
    arm.run(3.0)
    assert planner.state == "idle"
    np.testing.assert_allclose(arm.p - p0, params.travel[label] * np.array(axis), atol=2e-4)
    assert np.all(arm.commands[-1].velocity == 0)


def test_go_home_converges_to_home_position():
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner, p0=(0.3, 0.1, 0.45))
    planner.handle(ev("go_home"))
    arm.run(8.0)
    assert planner.state == "idle"
    assert np.linalg.norm(arm.p - params.home_position) < params.home_tolerance
    assert np.abs(arm.velocities).max() <= params.home_speed + 1e-12
    np.testing.assert_array_equal(arm.commands[-1].orientation, np.array(params.home_orientation))


def test_gripper_events_ramp_the_opening_reference():
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner)
    assert planner.handle(ev("close_gripper")).accepted
    arm.run(0.5)
    w = np.array([c.gripper_width for c in arm.commands])
    assert np.all(np.abs(np.diff(w)) <= params.gripper_speed * DT + 1e-12)
    arm.run(2.0)
    assert arm.commands[-1].gripper_width == params.gripper_closed_width
    planner.handle(ev("open_gripper"))
    arm.run(2.0)
    assert arm.commands[-1].gripper_width == params.gripper_open_width


def test_stop_decelerates_with_bounded_deceleration_and_takes_precedence():
    params = PlannerParams(stop_deceleration=0.4)
    planner = Planner(params)
    arm = FollowingArm(planner)
    planner.handle(ev("go_left"))
    arm.run(1.0)
    n0 = len(arm.commands)
    # a stop and a gesture with the same time stamp: stop wins, the gesture is ignored
    decisions = planner.handle_many([ev("go_up", 5.0), ev("stop", 5.0)])
    assert [d.reason for d in decisions] == ["stopping", "ignored while stopping"]
    assert planner.handle(ev("go_right", 5.0)).reason == "ignored while stopping"
    arm.run(0.5)
    v = arm.velocities[n0 - 1 :]
    dv = np.linalg.norm(np.diff(v, axis=0), axis=1)
    assert dv.max() <= params.stop_deceleration * DT * (1 + 1e-9)
    t_stop = params.speed / params.stop_deceleration
    stopped = np.flatnonzero(np.linalg.norm(v, axis=1) == 0)[0]
    assert stopped * DT <= t_stop + 2 * DT
    assert planner.state == "idle"
    assert planner.handle(ev("stop", 6.0)).reason == "at rest"
    assert planner.handle(ev("go_right", 6.5)).reason == "started"  # at rest again: gestures work


def test_a_gesture_from_before_a_stop_never_moves_the_arm_whenever_it_arrives():
    """A gesture classified late reaches the planner after the stop that followed it: ignored,
    also once the arm is at rest again, while a later gesture still acts."""
    planner = Planner()
    arm = FollowingArm(planner)
    planner.handle(ev("go_left", 1.0))
    arm.run(0.5)
    assert planner.handle(ev("stop", 3.0)).reason == "stopping"
    assert planner.handle(ev("go_up", 2.5)).reason == "before a stop"
    arm.run(2.0)
    assert planner.state == "idle" and not np.any(planner.velocity)
    late = planner.handle(ev("go_down", 2.9))  # at rest now: still from before the stop
    assert (late.accepted, late.reason) == (False, "before a stop")
    arm.run(1.0)
    assert not np.any(arm.velocities[-round(1.0 / DT):])
    idle = Planner()
    assert idle.handle(ev("stop", 4.0)).reason == "at rest"  # also a stop to an arm at rest
    assert idle.handle(ev("go_up", 3.0)).reason == "before a stop"
    assert planner.handle(ev("go_down", 3.1)).reason == "started"


def test_stop_keeps_the_gripper_reference():
    planner = Planner()
    arm = FollowingArm(planner)
    planner.handle(ev("close_gripper"))
    arm.run(0.4)
    w = arm.commands[-1].gripper_width
    planner.handle(ev("stop"))
    arm.run(2.0)
    assert arm.commands[-1].gripper_width < w  # still closing


def test_every_velocity_change_is_bounded():
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner)
    rng = np.random.default_rng(3)
    labels = ["go_left", "go_right", "go_up", "go_down", "go_home", "open_gripper", "stop"]
    for _ in range(25):
        planner.handle(ev(labels[rng.integers(len(labels))]))
        arm.run(float(rng.uniform(0.05, 0.8)))
    dv = np.linalg.norm(np.diff(arm.velocities, axis=0), axis=1) / DT
    assert dv.max() <= max(params.acceleration, params.stop_deceleration) * (1 + 1e-9)
    assert np.linalg.norm(arm.velocities, axis=1).max() <= max(params.speed, params.home_speed) + 1e-12


def test_repeated_direction_does_not_extend_the_motion():
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner)
    p0 = arm.p.copy()
    planner.handle(ev("go_left"))
    arm.run(1.0)
    assert planner.handle(ev("go_left")).reason == "repeated"
    arm.run(4.0)
    assert abs(arm.p[1] - p0[1] - params.travel["go_left"]) < 2e-4
    # once it has ended, the same gesture starts a new motion
    assert planner.handle(ev("go_left")).reason == "started"


def test_repeat_window_ignores_a_re_performed_gesture_after_its_motion_ended():
    params = PlannerParams(repeat_window=8.0)
    planner = Planner(params)
    arm = FollowingArm(planner)
    p0 = arm.p.copy()
    planner.handle(ev("go_left"))
    arm.run(4.0)  # the motion has ended
    assert planner.state != "move"
    assert planner.handle(ev("go_left")).reason == "repeated"
    arm.run(2.0)
    assert abs(arm.p[1] - p0[1] - params.travel["go_left"]) < 2e-4
    # another accepted command in between: the same gesture is a new command again
    planner.handle(ev("go_up"))
    arm.run(3.0)
    assert planner.handle(ev("go_left")).reason == "started"
    # and past the window it is a new command too
    arm.run(9.0)
    assert planner.handle(ev("go_left")).reason == "started"


def test_repeated_gripper_home_and_unknown_events():
    planner = Planner()
    arm = FollowingArm(planner)
    assert planner.handle(ev("open_gripper")).reason == "repeated"  # starts open
    planner.handle(ev("go_home"))
    assert planner.handle(ev("go_home")).reason == "repeated"
    state = planner.state
    d = planner.handle(ev("wave_hello"))
    assert (d.accepted, d.reason) == (False, "unknown label")
    assert planner.state == state
    arm.run(0.1)
    assert len(planner.decisions) == 4


def test_next_event_ends_the_motion():
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner)
    planner.handle(ev("go_left"))
    arm.run(1.0)
    planner.handle(ev("go_up"))  # blends into the new direction
    arm.run(1.5)
    np.testing.assert_allclose(arm.commands[-1].velocity, [0, 0, params.speed], atol=1e-12)
    planner.handle(ev("close_gripper"))  # a gripper event ends the motion
    arm.run(1.0)
    assert planner.state == "idle" and np.all(arm.commands[-1].velocity == 0)


def test_workspace_box_is_never_left():
    params = PlannerParams(workspace_min=(0.25, -0.45, 0.15))
    planner = Planner(params)
    arm = FollowingArm(planner)
    planner.handle(ev("go_down"))
    arm.run(5.0)
    assert arm.p[2] >= 0.15 - 1e-4
    assert planner.state == "idle"


def test_contact_ends_a_motion_and_relaxes_the_reference():
    params = PlannerParams()
    planner = Planner(params)
    arm = FollowingArm(planner)
    arm.block_z = 0.12  # the TCP cannot go below 12 cm (a block on the table)
    planner.handle(ev("go_down"))
    arm.run(4.0)
    assert planner.state == "idle"
    assert arm.p[2] == pytest.approx(0.12)
    assert np.all(arm.commands[-1].velocity == 0)
    # the reference was backed off to within a quarter of the contact threshold
    assert 0.0 < 0.12 - arm.p_ref[2] <= 0.25 * params.contact_deviation + 1e-4
    assert planner.contact is False


def test_params_are_validated():
    with pytest.raises(ValueError, match="unit vector"):
        PlannerParams(directions={"go_left": (0, 2, 0)}, travel={"go_left": 0.1})
    with pytest.raises(ValueError, match="speed"):
        PlannerParams(speed=0)
