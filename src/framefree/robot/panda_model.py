"""MJCF model of a Franka Panda with its hand, a table and blocks, written from published parameters.

Nothing is downloaded: the kinematic chain is built from :data:`~framefree.robot.kinematics.DH_TABLE`
(the same numbers the controller uses), the inertials from Gaz et al. (2019), the geometry from
simple capsules and boxes. Only the hand, the fingers, the table and the blocks collide (the arm's
links are drawn but do not collide; the scripted tasks keep them well above the table).

The scene's frame is the robot base frame: x forward, y to the robot's left, z up; the table top
is the plane z = 0 and the robot stands on it at the origin.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np

from .kinematics import (
    DH_TABLE,
    FINGER_BASE,
    FINGER_COM_HEIGHT,
    FINGER_MASS,
    FLANGE_LENGTH,
    HAND_CENTER_OF_MASS,
    HAND_MASS,
    HAND_YAW,
    LINK_CENTERS_OF_MASS,
    LINK_INERTIAS,
    LINK_MASSES,
    Q_MAX,
    Q_MIN,
    TAU_MAX,
    TCP_OFFSET,
)

__all__ = ["Block", "SceneSpec", "scene_xml"]

#: Reflected rotor inertia added to every arm joint [kg m²] (keeps the stiff impedance loop stable).
ARMATURE = 0.1
#: Viscous friction of every arm joint [N m s/rad].
JOINT_DAMPING = 0.1
#: Finger position servo: stiffness [N/m] and force limit [N] per finger.
FINGER_KP = 800.0
FINGER_FORCE = 40.0
#: Finger travel [m] (each finger; the opening width is twice this).
FINGER_RANGE = 0.04
#: Finger pad: half sizes (x, thickness, height) [m]; its centre is at the TCP height.
PAD_HALF = (0.010, 0.004, 0.0125)


@dataclass(frozen=True)
class Block:
    """A cube (or box) resting on the table.

    Attributes
    ----------
    name : str
        Body name (must be unique in the scene).
    position : tuple of float
        Initial centre (x, y, z) in the base frame [m].
    half_size : tuple of float
        Half extents (x, y, z) [m].
    mass : float
        Mass [kg].
    rgba : tuple of float
        Colour.
    """

    name: str
    position: tuple[float, float, float]
    half_size: tuple[float, float, float] = (0.02, 0.02, 0.02)
    mass: float = 0.05
    rgba: tuple[float, float, float, float] = (0.8, 0.2, 0.2, 1.0)


@dataclass(frozen=True)
class SceneSpec:
    """What the simulated world contains besides the robot.

    Attributes
    ----------
    blocks : tuple of Block
        Blocks on the table (free bodies).
    timestep : float
        Physics time step [s].
    friction : float
        Sliding friction coefficient of pads, blocks and table.
    """

    blocks: tuple[Block, ...] = field(
        default_factory=lambda: (
            Block("block_a", (0.5, 0.15, 0.06), rgba=(0.85, 0.2, 0.2, 1.0)),
            Block("block_b", (0.5, 0.15, 0.02), rgba=(0.2, 0.6, 0.25, 1.0)),
            Block("block_c", (0.5, -0.2, 0.02), rgba=(0.2, 0.35, 0.85, 1.0)),
        )
    )
    timestep: float = 0.002
    friction: float = 1.0


def _f(values) -> str:
    return " ".join(f"{float(v):.9g}" for v in np.ravel(values))


def _rotx_quat(alpha: float) -> tuple[float, float, float, float]:
    return (math.cos(alpha / 2), math.sin(alpha / 2), 0.0, 0.0)


def _next_origin(i: int) -> np.ndarray:
    """Origin of frame i+2 in frame i+1 (0-based link index i), zero for the last link."""
    if i + 1 >= 7:
        return np.array([0.0, 0.0, FLANGE_LENGTH])
    a, d, alpha = DH_TABLE[i + 1]
    return np.array([a, -d * math.sin(alpha), d * math.cos(alpha)])


def _link_geoms(i: int, indent: str) -> list[str]:
    """Visual geometry of link i+1: a joint housing along z and capsules to the next joint."""
    radius = 0.06 if i < 4 else 0.045
    lines = [
        f'{indent}<geom class="link" type="cylinder" size="{radius:.3g} {radius:.3g}"'
        f' rgba="0.93 0.93 0.93 1"/>'
    ]
    target = _next_origin(i)
    # route the capsule first along x (the DH offset a), then along the rest
    corners = [np.zeros(3)]
    if abs(target[0]) > 1e-9 and np.linalg.norm(target[1:]) > 1e-9:
        corners.append(np.array([target[0], 0.0, 0.0]))
    corners.append(target)
    for p0, p1 in itertools.pairwise(corners):
        if np.linalg.norm(p1 - p0) > 1e-9:
            lines.append(
                f'{indent}<geom class="link" type="capsule" size="{0.8 * radius:.3g}"'
                f' fromto="{_f(p0)} {_f(p1)}" rgba="0.9 0.9 0.9 1"/>'
            )
    return lines


def _inertial(i: int) -> str:
    return (
        f'<inertial mass="{LINK_MASSES[i]:.9g}" pos="{_f(LINK_CENTERS_OF_MASS[i])}"'
        f' fullinertia="{_f(LINK_INERTIAS[i])}"/>'
    )


def _finger(name: str, quat: str, indent: str) -> list[str]:
    px, py, pz = PAD_HALF
    pad_z = TCP_OFFSET - FINGER_BASE
    return [
        f'{indent}<body name="{name}" pos="0 0 {FINGER_BASE}" quat="{quat}">',
        f'{indent}  <inertial mass="{FINGER_MASS}" pos="0 0 {FINGER_COM_HEIGHT}"'
        ' diaginertia="2.4e-6 2.4e-6 7.5e-7"/>',
        f'{indent}  <joint name="{name}_joint" type="slide" axis="0 1 0" range="0 {FINGER_RANGE}"'
        ' armature="0.01" damping="5"/>',
        f'{indent}  <geom name="{name}_body" class="grip" type="box"'
        f' size="0.011 0.006 {(pad_z - pz) / 2:.6g}" pos="0 0.009 {(pad_z - pz) / 2:.6g}"'
        ' rgba="0.25 0.25 0.25 1"/>',
        f'{indent}  <geom name="{name}_pad" class="grip" type="box" size="{px} {py} {pz}"'
        f' pos="0 {py} {pad_z:.6g}" rgba="0.15 0.15 0.15 1"/>',
        f"{indent}</body>",
    ]


def scene_xml(spec: SceneSpec | None = None) -> str:
    """MJCF text of the Panda (7 torque-controlled joints, 2 position-servoed fingers) and scene.

    Parameters
    ----------
    spec : SceneSpec, optional
        Blocks and physics options (default: :class:`SceneSpec`).

    Returns
    -------
    str
        An MJCF document: bodies ``link1`` … ``link7``, ``hand``, ``left_finger``,
        ``right_finger``, one free body per block; sites ``tcp`` and ``flange``; actuators
        ``torque1`` … ``torque7`` [N m] and ``finger_left``, ``finger_right`` (target opening of
        each finger [m], 0 = closed).
    """
    spec = SceneSpec() if spec is None else spec
    lines = _scene_header(spec)
    indent = "      "
    for i in range(7):
        a, d, alpha = DH_TABLE[i]
        pos = np.array([a, -d * math.sin(alpha), d * math.cos(alpha)])
        lines.append(
            f'{indent}<body name="link{i + 1}" pos="{_f(pos)}" quat="{_f(_rotx_quat(alpha))}">'
        )
        inner = indent + "  "
        lines.append(inner + _inertial(i))
        lines.append(
            f'{inner}<joint name="joint{i + 1}" axis="0 0 1" range="{Q_MIN[i]} {Q_MAX[i]}"/>'
        )
        lines.extend(_link_geoms(i, inner))
        indent = inner
    lines += _hand(indent)
    for _ in range(7):
        indent = indent[:-2]
        lines.append(f"{indent}</body>")
    lines.append("    </body>")
    lines += _blocks(spec)
    lines.append("  </worldbody>")
    lines.append('  <contact><exclude body1="link7" body2="hand"/></contact>')
    lines += _actuators()
    lines.append("</mujoco>")
    return "\n".join(lines) + "\n"


def _scene_header(spec: SceneSpec) -> list[str]:
    """MJCF up to the robot's base body: options, defaults, assets, lights, floor, table, link0."""
    mu = spec.friction
    return [
        '<mujoco model="framefree_panda">',
        '  <compiler angle="radian" autolimits="true"/>',
        f'  <option timestep="{spec.timestep}" integrator="implicitfast" cone="elliptic"'
        ' impratio="10"/>',
        '  <visual><global offwidth="1280" offheight="960"/><quality shadowsize="4096"/></visual>',
        "  <default>",
        f'    <joint armature="{ARMATURE}" damping="{JOINT_DAMPING}"/>',
        '    <default class="link"><geom contype="0" conaffinity="0" group="1"/></default>',
        f'    <default class="grip"><geom condim="4" friction="{mu} 0.005 0.0001"'
        ' solref="0.004 1" group="1"/></default>',
        "  </default>",
        "  <asset>",
        '    <texture name="sky" type="skybox" builtin="gradient" rgb1="0.75 0.85 0.95"'
        ' rgb2="0.3 0.4 0.5" width="256" height="256"/>',
        '    <texture name="grid" type="2d" builtin="checker" rgb1="0.55 0.55 0.58"'
        ' rgb2="0.45 0.45 0.48" width="256" height="256"/>',
        '    <material name="floor" texture="grid" texrepeat="8 8" reflectance="0.1"/>',
        '    <texture name="wood" type="2d" builtin="flat" rgb1="0.72 0.58 0.42" width="16"'
        ' height="16"/>',
        '    <material name="table" texture="wood"/>',
        "  </asset>",
        "  <worldbody>",
        '    <light pos="0.6 -0.6 2.0" dir="-0.2 0.3 -1" diffuse="0.8 0.8 0.8" castshadow="true"/>',
        '    <light pos="-0.5 0.8 1.5" dir="0.3 -0.4 -1" diffuse="0.35 0.35 0.35"'
        ' castshadow="false"/>',
        '    <geom name="floor" type="plane" size="3 3 0.1" pos="0 0 -0.75" material="floor"/>',
        f'    <geom name="table" type="box" size="0.6 0.8 0.375" pos="0.45 0 -0.375"'
        f' material="table" friction="{mu} 0.005 0.0001" condim="4"/>',
        '    <body name="link0">',
        '      <geom class="link" type="cylinder" size="0.09 0.05" pos="0 0 0.05"'
        ' rgba="0.9 0.9 0.9 1"/>',
        '      <geom class="link" type="capsule" size="0.06" fromto="0 0 0.05 0 0 0.333"'
        ' rgba="0.9 0.9 0.9 1"/>',
    ]


def _hand(indent: str) -> list[str]:
    """Flange, hand and fingers (children of link7), at the indentation of link7's contents."""
    hand_quat = (math.cos(HAND_YAW / 2), 0.0, 0.0, math.sin(HAND_YAW / 2))
    lines = [
        f'{indent}<site name="flange" pos="0 0 {FLANGE_LENGTH}" size="0.005"/>',
        f'{indent}<body name="hand" pos="0 0 {FLANGE_LENGTH}" quat="{_f(hand_quat)}">',
        f'{indent}  <inertial mass="{HAND_MASS}" pos="{_f(HAND_CENTER_OF_MASS)}"'
        ' diaginertia="0.001 0.0025 0.0017"/>',
        f'{indent}  <geom name="hand_body" class="grip" type="box" size="0.02 0.1 0.025"'
        ' pos="0 0 0.033" rgba="0.95 0.95 0.95 1"/>',
        f'{indent}  <site name="tcp" pos="0 0 {TCP_OFFSET}" size="0.004" rgba="1 0.5 0 0.6"/>',
    ]
    lines += _finger("left_finger", "1 0 0 0", indent + "  ")
    lines += _finger("right_finger", "0 0 0 1", indent + "  ")
    lines.append(f"{indent}</body>")
    return lines


def _blocks(spec: SceneSpec) -> list[str]:
    """One free body per block."""
    mu = spec.friction
    lines = []
    for b in spec.blocks:
        lines += [
            f'    <body name="{b.name}" pos="{_f(b.position)}">',
            "      <freejoint/>",
            f'      <geom name="{b.name}" type="box" size="{_f(b.half_size)}" mass="{b.mass}"'
            f' rgba="{_f(b.rgba)}" condim="4" friction="{mu} 0.005 0.0001" solref="0.004 1"/>',
            "    </body>",
        ]
    return lines


def _actuators() -> list[str]:
    """Joint torque motors and the two finger position servos."""
    lines = ["  <actuator>"]
    for i in range(7):
        lines.append(
            f'    <motor name="torque{i + 1}" joint="joint{i + 1}"'
            f' ctrlrange="{-TAU_MAX[i]} {TAU_MAX[i]}"/>'
        )
    for side in ("left", "right"):
        lines.append(
            f'    <position name="finger_{side}" joint="{side}_finger_joint" kp="{FINGER_KP}"'
            f' ctrlrange="0 {FINGER_RANGE}" forcerange="{-FINGER_FORCE} {FINGER_FORCE}"/>'
        )
    lines.append("  </actuator>")
    return lines
