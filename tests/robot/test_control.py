"""Velocity mapping and joint impedance control: tracking, limits, singularities."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.robot.control import HOME_Q, Controller, ControlParams, dls_velocity
from framefree.robot.kinematics import Q_MAX, Q_MIN, QD_MAX, TAU_MAX, PandaKinematics
from framefree.robot.planner import DOWN, Command

KIN = PandaKinematics()
DT = 0.002
R_DOWN = np.array(DOWN)
#: a singular configuration (found numerically: q6 = 0 with this elbow angle loses one rank)
Q_SINGULAR = np.array([0.0, 0.5, 0.0, -0.467002424, 0.0, 0.0, 0.0])


def twist(v, w=(0, 0, 0)):
    return np.concatenate([w, v]).astype(float)


def test_singular_configuration_is_singular():
    s = np.linalg.svd(KIN.jacobian(Q_SINGULAR), compute_uv=False)
    assert s[-1] < 1e-8


def test_dls_is_the_pseudo_inverse_away_from_singularities():
    J = KIN.jacobian(HOME_Q)
    x = np.array([0.1, -0.2, 0.05, 0.03, 0.01, -0.02])
    np.testing.assert_allclose(dls_velocity(J, x, 0.05, 0.05), np.linalg.pinv(J) @ x, atol=1e-12)
    sec = np.arange(7.0)
    dq = dls_velocity(J, x, 0.05, 0.05, sec)
    np.testing.assert_allclose(J @ dq, x, atol=1e-10)  # the secondary task does not disturb


def test_reference_tracks_a_commanded_twist():
    """Kinematic level: the integrated reference moves the TCP by v·t (tolerance 0.1 mm)."""
    c = Controller()
    c.reset(HOME_Q)
    p0 = KIN.tcp_pose(HOME_Q)[:3, 3]
    v = np.array([0.05, 0.1, -0.05])
    for _ in range(500):
        c.update_reference(twist(v), DT, R_DOWN)
    T = KIN.tcp_pose(c.q_ref)
    np.testing.assert_allclose(T[:3, 3] - p0, v * 1.0, atol=1e-4)
    np.testing.assert_allclose(T[:3, :3], R_DOWN, atol=1e-3)


def test_joint_position_and_velocity_limits_hold_when_pushed_out_of_reach():
    params = ControlParams()
    c = Controller(params)
    c.reset(HOME_Q)
    lo, hi = Q_MIN + params.limit_margin, Q_MAX - params.limit_margin
    worst_speed = 0.0
    for v in ([0.3, 0, 0], [0, 0, 0.3], [0, -0.3, 0], [-0.3, 0, -0.3]):
        for _ in range(2500):  # 5 s at 0.3 m/s: far beyond the reach in every direction
            q = c.update_reference(twist(v), DT, R_DOWN)
            assert np.all(q >= lo - 1e-12) and np.all(q <= hi + 1e-12)
            worst_speed = max(worst_speed, np.max(np.abs(c.dq_ref) / QD_MAX))
            assert np.all(np.isfinite(q))
    assert worst_speed <= params.qd_scale + 1e-12


def test_reference_is_stable_at_a_singular_configuration():
    params = ControlParams()
    c = Controller(params)
    c.reset(Q_SINGULAR)
    for w in ([0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0]):
        for _ in range(200):
            c.update_reference(twist([0.05, 0.05, 0.0], w), DT)
            assert np.all(np.isfinite(c.dq_ref))
            assert np.all(np.abs(c.dq_ref) <= params.qd_scale * QD_MAX + 1e-12)


def _sim(q0=None):
    pytest.importorskip("mujoco")
    from framefree.robot.sim import PandaSim

    return PandaSim(q0=q0)


def _command(v, R=R_DOWN, w=(0, 0, 0)):
    return Command(twist(v, w), R, 0.07, 0.0, "move", "test")


def test_impedance_controller_tracks_a_twist_in_simulation():
    """Velocity within 2 mm/s of the command after the ramp; lag < 3 mm (< 0.5 mm steady)."""
    sim = _sim()
    v = np.array([0.0, 0.1, 0.0])
    p = [sim.ee_pose()[:3, 3]]
    taus = []
    for k in range(750):  # 1.5 s; the command ramps up over the first 0.2 s
        vk = v * min(1.0, k * DT / 0.2)
        sim.step(_command(vk))
        p.append(sim.ee_pose()[:3, 3])
        taus.append(sim.data.ctrl[:7].copy())
    p = np.array(p)
    vel = np.diff(p, axis=0) / DT
    steady = vel[250:]
    assert np.abs(steady - v).max() < 2e-3
    expected_y = np.cumsum([v[1] * min(1.0, k * DT / 0.2) for k in range(750)]) * DT
    lag = np.abs(p[1:, 1] - p[0, 1] - expected_y)
    assert lag.max() < 3e-3
    assert lag[500:].max() < 5e-4
    assert np.abs(p[:, [0, 2]] - p[0, [0, 2]]).max() < 1e-3
    assert np.all(np.abs(taus) <= TAU_MAX + 1e-9)
    np.testing.assert_allclose(sim.ee_pose()[:3, :3], R_DOWN, atol=5e-3)


def test_simulated_arm_stays_stable_at_a_singular_configuration():
    sim = _sim(Q_SINGULAR)
    for w in ([0, 0, 0.5], [0.5, 0, 0]):
        for _ in range(400):
            sim.step(_command([0.05, 0.0, 0.0], R=None, w=w))
    for _ in range(500):  # then hold still
        sim.step(_command([0.0, 0.0, 0.0], R=None))
    assert np.all(np.isfinite(sim.q))
    assert np.abs(sim.dq).max() < 1e-2  # came to rest, no oscillation
    assert np.all(sim.q >= Q_MIN - 1e-3) and np.all(sim.q <= Q_MAX + 1e-3)
    assert np.abs(sim.controller.q_ref - sim.q).max() < 0.02
