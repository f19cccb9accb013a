"""Panda kinematics and gravity against finite differences and MuJoCo."""

from __future__ import annotations

import numpy as np
import pytest

from framefree.robot.control import HOME_Q
from framefree.robot.kinematics import Q_MAX, Q_MIN, Q_READY, PandaKinematics, rotation_error
from framefree.robot.planner import PlannerParams

KIN = PandaKinematics()
RNG = np.random.default_rng(7)
CONFIGS = [RNG.uniform(Q_MIN, Q_MAX) for _ in range(6)] + [Q_READY, HOME_Q]


def test_ready_pose_matches_franka_documentation():
    T = KIN.tcp_pose(Q_READY)
    # flange of the ready pose is at about (0.307, 0, 0.590) m; the TCP 0.1034 m below it
    np.testing.assert_allclose(T[:3, 3], [0.30689, 0.0, 0.590 - 0.1034], atol=5e-4)
    np.testing.assert_allclose(T[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=1e-9)


def test_home_configuration_reaches_the_planner_home_pose():
    params = PlannerParams()
    T = KIN.tcp_pose(HOME_Q)
    np.testing.assert_allclose(T[:3, 3], params.home_position, atol=1e-4)
    np.testing.assert_allclose(T[:3, :3], np.array(params.home_orientation), atol=1e-4)


@pytest.mark.parametrize("q", CONFIGS)
def test_jacobian_matches_finite_differences(q):
    J = KIN.jacobian(q)
    h = 1e-6
    T0 = KIN.tcp_pose(q)
    for j in range(7):
        dq = np.zeros(7)
        dq[j] = h
        T1 = KIN.tcp_pose(q + dq)
        np.testing.assert_allclose((T1[:3, 3] - T0[:3, 3]) / h, J[3:, j], atol=1e-5)
        np.testing.assert_allclose(rotation_error(T1[:3, :3], T0[:3, :3]) / h, J[:3, j], atol=1e-5)


def test_jacobian_fk_and_gravity_match_mujoco():
    mujoco = pytest.importorskip("mujoco")
    from framefree.robot.panda_model import scene_xml

    model = mujoco.MjModel.from_xml_string(scene_xml())
    data = mujoco.MjData(model)
    site = model.site("tcp").id
    jacp = np.zeros((3, model.nv))
    jacr = np.zeros((3, model.nv))
    for q in CONFIGS:
        data.qpos[:7] = q
        data.qvel[:] = 0
        mujoco.mj_forward(model, data)
        mujoco.mj_jacSite(model, data, jacp, jacr, site)
        J = KIN.jacobian(q)
        np.testing.assert_allclose(J[:3], jacr[:, :7], atol=1e-10)
        np.testing.assert_allclose(J[3:], jacp[:, :7], atol=1e-10)
        T = KIN.tcp_pose(q)
        np.testing.assert_allclose(T[:3, 3], data.site_xpos[site], atol=1e-10)
        np.testing.assert_allclose(T[:3, :3].ravel(), data.site_xmat[site], atol=1e-8)
        # at rest MuJoCo's bias force is exactly the gravity torque (inertials from one table)
        np.testing.assert_allclose(KIN.gravity_torque(q), data.qfrc_bias[:7], atol=1e-8)
