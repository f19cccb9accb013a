"""Robot motion planner: a finite-state machine from recognized events to end-effector commands.

Pure logic (no simulator, no robot model): :meth:`Planner.handle` takes a recognition
:class:`~framefree.online.events.Event`, :meth:`Planner.step` advances the plan by one control
period given the measured tool-centre-point (TCP) pose and returns a :class:`Command` — a 6-D TCP
twist, a desired TCP orientation and a gripper opening reference (docs/robot.md, *Planner
states*).

Mapping (default :class:`PlannerParams`; the gesture names are arbitrary labels for frame-free
hand-palm motions, the directions are those of the **robot base frame**: x forward, y to the
robot's left, z up):

============== ===================================================================
label          motion plan
============== ===================================================================
go_left        translate along +y at ``speed`` for ``travel["go_left"]`` metres
go_right       translate along −y
go_up          translate along +z
go_down        translate along −z (ends early on contact, see ``contact_deviation``)
go_home        straight line to ``home_position`` at ``home_speed`` (the controller
               turns the orientation to ``home_orientation`` and pulls the redundant
               joint back to the home configuration, so the arm ends in it)
open_gripper   finger opening reference → ``gripper_open_width`` at ``gripper_speed``
close_gripper  finger opening reference → ``gripper_closed_width`` (the fingers stop
               on the object and squeeze it with the servo's force limit)
stop           decelerate to standstill at ``stop_deceleration`` (takes precedence)
============== ===================================================================

States: ``idle`` (at rest or settling), ``move`` (directional motion), ``home`` and ``stop``.
Every velocity change is rate limited: ``‖Δv‖ ≤ acceleration·dt`` (``stop_deceleration·dt``
while stopping or after a contact), and motions follow a trapezoidal profile that ends at rest
exactly after their travel distance.

Rules for events that do not simply start a motion:

* **stop takes precedence**: it aborts any motion; gestures that arrive while the arm is
  decelerating are ignored (reported as such) until it is at rest; among events with the same
  time stamp a stop is handled first (:meth:`Planner.handle_many`); a gesture stamped
  before a stop already handled is ignored whenever it arrives (``"before a stop"``: a gesture
  classified late never moves the arm after the stop that followed it). Stop does not touch the
  gripper: a held object stays held.
* **the next event ends a motion**: a different direction starts at once (the velocity blends
  with bounded acceleration); a gripper event or go_home ends a directional motion too.
* **repeated events** are idempotent: the same direction while that motion is still under way
  does not restart or extend it (a repeated gesture that the user made because they thought the
  first was missed must not double the distance); go_home while homing, open while open(ing),
  close while closed/closing, stop while at rest — all no-ops, reported as ``repeated``.
* **unknown labels** are ignored and reported (the recognizer may know more gestures than the
  robot); the plan is unchanged.
* **workspace**: the commanded velocity is limited per axis so that the TCP brakes (with
  ``acceleration``) to rest at the box ``[workspace_min, workspace_max]``.
* **contact**: during a directional motion the planner integrates the commanded TCP position; when
  the measured TCP lags it by more than ``contact_deviation`` along the motion direction (the arm is
  blocked: a block met the table or another block, the fingers met the table) the motion ends
  and the arm decelerates at ``stop_deceleration``. This is what makes a fixed go_down distance
  usable for stacking (see :mod:`framefree.robot.scenario`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..online.events import Event

__all__ = ["Command", "Decision", "Planner", "PlannerParams"]


def _frozen(d: dict) -> Mapping:
    return MappingProxyType(dict(d))


#: Gripper pointing straight down, fingers closing along the base y axis.
DOWN = ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0))


@dataclass(frozen=True)
class PlannerParams:
    """Speeds, limits and the event mapping of the planner (SI units, robot base frame).

    Attributes
    ----------
    directions : Mapping[str, tuple of float]
        Label → unit direction of a translational motion.
    travel : Mapping[str, float]
        Label → travel distance of that motion [m] (the motion ends at rest after it).
    speed : float
        Cruise speed of directional motions [m/s].
    acceleration : float
        Bound on the commanded TCP acceleration [m/s²] for starting, blending and ending motions.
    stop_deceleration : float
        Bound on the deceleration after a stop signal or a contact [m/s²].
    home_label, open_label, close_label : str
        Labels of the go-home and gripper gestures.
    home_position : tuple of float
        TCP position of the home configuration [m].
    home_orientation : tuple of tuple of float
        TCP orientation held during every motion (3 × 3 rotation matrix, rows).
    home_speed : float
        Cruise speed of the homing motion [m/s].
    home_gain : float
        Proportional gain [1/s] that makes homing converge on the measured TCP.
    home_tolerance : float
        Homing ends when the TCP is this close to ``home_position`` [m] and at rest.
    gripper_open_width, gripper_closed_width : float
        Finger opening references [m] for open/close.
    gripper_speed : float
        Rate of the finger opening reference [m/s].
    workspace_min, workspace_max : tuple of float
        Box the TCP must stay in [m].
    contact_deviation : float
        Lag of the measured TCP behind the commanded position, along the motion, that ends a
        directional motion [m]; 0 disables contact detection.
    repeat_window : float
        A directional or go-home command equal to the last accepted one, arriving within this
        many seconds of it, is a repeat and ignored even if that motion has already ended [s].
        People re-perform a gesture when the robot seems not to react (the paper's user did so
        twice); when the recognizer caught the first attempt, the second must not move the
        robot again. 0 (default) disables the rule: then only a repeat during the motion is
        ignored.
    """

    directions: Mapping[str, tuple[float, float, float]] = field(
        default_factory=lambda: _frozen(
            {
                "go_left": (0.0, 1.0, 0.0),
                "go_right": (0.0, -1.0, 0.0),
                "go_up": (0.0, 0.0, 1.0),
                "go_down": (0.0, 0.0, -1.0),
            }
        )
    )
    travel: Mapping[str, float] = field(
        default_factory=lambda: _frozen(
            {"go_left": 0.15, "go_right": 0.15, "go_up": 0.10, "go_down": 0.14}
        )
    )
    speed: float = 0.06
    acceleration: float = 0.25
    stop_deceleration: float = 0.5
    home_label: str = "go_home"
    open_label: str = "open_gripper"
    close_label: str = "close_gripper"
    home_position: tuple[float, float, float] = (0.5, 0.0, 0.2)
    home_orientation: tuple[tuple[float, float, float], ...] = DOWN
    home_speed: float = 0.1
    home_gain: float = 2.0
    home_tolerance: float = 2e-3
    gripper_open_width: float = 0.07
    gripper_closed_width: float = 0.0
    gripper_speed: float = 0.05
    workspace_min: tuple[float, float, float] = (0.25, -0.45, 0.0)
    workspace_max: tuple[float, float, float] = (0.75, 0.45, 0.65)
    contact_deviation: float = 0.008
    repeat_window: float = 0.0

    def __post_init__(self):
        for name in ("speed", "acceleration", "stop_deceleration", "home_speed", "gripper_speed"):
            if not getattr(self, name) > 0:
                raise ValueError(f"PlannerParams.{name} must be positive")
        for label, d in self.directions.items():
            if abs(np.linalg.norm(d) - 1.0) > 1e-9:
                raise ValueError(f"PlannerParams.directions[{label!r}] is not a unit vector")
            if label not in self.travel or not self.travel[label] > 0:
                raise ValueError(f"PlannerParams.travel[{label!r}] must be a positive distance")


@dataclass(frozen=True)
class Command:
    """What the planner asks of the controller for one control period.

    Attributes
    ----------
    twist : ndarray, shape (6,)
        Commanded TCP twist ``(ω; v)`` in the base frame [rad/s, m/s] (ω is zero: orientation is
        held through ``orientation``).
    orientation : ndarray, shape (3, 3)
        Desired TCP orientation (the controller closes a loop on it).
    gripper_width : float
        Finger opening reference [m] (rate limited).
    gripper_velocity : float
        Rate of ``gripper_width`` [m/s].
    state : str
        Planner state after the step: ``idle``, ``move``, ``home`` or ``stop``.
    label : str
        The event label that set the current plan ('' before any).
    """

    twist: np.ndarray
    orientation: np.ndarray
    gripper_width: float
    gripper_velocity: float
    state: str
    label: str

    @property
    def velocity(self) -> np.ndarray:
        """Linear part of the twist, shape (3,) [m/s]."""
        return self.twist[3:]


@dataclass(frozen=True)
class Decision:
    """How the planner reacted to one event.

    Attributes
    ----------
    event : Event
        The event.
    accepted : bool
        Whether the plan changed.
    reason : str
        ``"started"``, ``"stopping"``, ``"repeated"``, ``"at rest"`` (stop while at rest),
        ``"ignored while stopping"``, ``"before a stop"`` or ``"unknown label"``.
    time : float
        Planner clock when the event was handled [s].
    """

    event: Event
    accepted: bool
    reason: str
    time: float


class Planner:
    """Event-driven motion planner (see the module docstring for the rules).

    Parameters
    ----------
    params : PlannerParams, optional
        Speeds, limits and mapping.
    gripper_width : float, optional
        Initial finger opening reference [m] (default: open).

    Attributes
    ----------
    state : str
        ``idle``, ``move``, ``home`` or ``stop``.
    velocity : ndarray, shape (3,)
        Current commanded TCP velocity [m/s].
    decisions : list of Decision
        Every handled event with the reaction.
    time : float
        Sum of the ``dt`` of all steps [s].
    last_stop : float
        Time stamp of the latest stop signal handled [s] (-inf before the first): a gesture
        stamped before it is ignored (``"before a stop"``), whenever it arrives.
    """

    def __init__(self, params: PlannerParams | None = None, gripper_width: float | None = None):
        self.params = PlannerParams() if params is None else params
        p = self.params
        self._R_home = np.array(p.home_orientation, dtype=float)
        self._home = np.array(p.home_position, dtype=float)
        self._lo = np.array(p.workspace_min, dtype=float)
        self._hi = np.array(p.workspace_max, dtype=float)
        self.state = "idle"
        self.label = ""
        self.velocity = np.zeros(3)
        self.gripper_width = p.gripper_open_width if gripper_width is None else float(gripper_width)
        self.gripper_target = self.gripper_width
        self.decisions: list[Decision] = []
        self.time = 0.0
        self._direction = np.zeros(3)
        self._travel = 0.0
        self._travelled = 0.0
        self._p_cmd: np.ndarray | None = None
        self._hard_brake = False
        self.contact = False
        self.last_stop = -math.inf

    # ------------------------------------------------------------------ events
    def handle(self, event: Event) -> Decision:
        """React to one recognition event (at the current planner time).

        Parameters
        ----------
        event : Event
            A recognized gesture or a stop signal.

        Returns
        -------
        Decision
            Whether the plan changed and why (also appended to :attr:`decisions`).
        """
        p = self.params
        label = event.label
        moving = bool(np.any(self.velocity != 0.0))
        if event.is_stop:
            self.last_stop = max(self.last_stop, float(event.time))
            if self.state == "stop":
                return self._decide(event, False, "repeated")
            if self.state == "idle" and not moving:
                return self._decide(event, False, "at rest")
            self.state = "stop"
            self.label = label
            self._hard_brake = True
            return self._decide(event, True, "stopping")
        if event.time < self.last_stop:
            return self._decide(event, False, "before a stop")
        if self.state == "stop":
            return self._decide(event, False, "ignored while stopping")
        if self._recent_repeat(label):
            return self._decide(event, False, "repeated")
        if label in p.directions:
            if self.state == "move" and self.label == label:
                return self._decide(event, False, "repeated")
            self.state = "move"
            self.label = label
            self._direction = np.array(p.directions[label], dtype=float)
            self._travel = float(p.travel[label])
            self._travelled = 0.0
            self._p_cmd = None
            self._hard_brake = False
            self.contact = False
            return self._decide(event, True, "started")
        if label == p.home_label:
            if self.state == "home":
                return self._decide(event, False, "repeated")
            self.state = "home"
            self.label = label
            self._hard_brake = False
            return self._decide(event, True, "started")
        if label in (p.open_label, p.close_label):
            target = p.gripper_open_width if label == p.open_label else p.gripper_closed_width
            ends_motion = self.state in ("move", "home")
            if target == self.gripper_target and not ends_motion:
                return self._decide(event, False, "repeated")
            self.gripper_target = target
            if ends_motion:
                self.state = "idle"
                self._hard_brake = False
            self.label = label
            return self._decide(event, True, "started")
        return self._decide(event, False, "unknown label")

    def handle_many(self, events: Iterable[Event]) -> list[Decision]:
        """Handle events in time order, a stop before any gesture with the same time stamp.

        Parameters
        ----------
        events : iterable of Event
            Events that arrived during one control period (or any batch).

        Returns
        -------
        list of Decision
        """
        ordered = sorted(events, key=lambda e: (e.time, not e.is_stop))
        return [self.handle(e) for e in ordered]

    def _recent_repeat(self, label: str) -> bool:
        """True for a motion command equal to the last accepted one within ``repeat_window``."""
        p = self.params
        if p.repeat_window <= 0 or not (label in p.directions or label == p.home_label):
            return False
        last = next((d for d in reversed(self.decisions) if d.accepted), None)
        return (
            last is not None
            and last.event.label == label
            and self.time - last.time <= p.repeat_window
        )

    def _decide(self, event: Event, accepted: bool, reason: str) -> Decision:
        d = Decision(event, accepted, reason, self.time)
        self.decisions.append(d)
        return d

    # ------------------------------------------------------------------ control period
    def step(self, dt: float, ee_pose: np.ndarray) -> Command:
        """Advance the plan by one control period.

        Parameters
        ----------
        dt : float
            Control period [s].
        ee_pose : ndarray, shape (4, 4)
            Measured TCP pose in the base frame (only its position is used).

        Returns
        -------
        Command
            Twist, orientation and gripper reference for this period.
        """
        p = self.params
        pos = np.asarray(ee_pose, dtype=float)[:3, 3]
        speed = float(np.linalg.norm(self.velocity))
        v_des = self._desired_velocity(pos, speed)
        a_max = p.acceleration
        if self.state == "stop" or self._hard_brake:
            a_max = p.stop_deceleration
            v_des = np.zeros(3)
        v_des = self._inside_workspace(v_des, pos)
        self._accelerate(v_des, a_max, dt)
        if self.state == "move":
            self._travelled += float(self._direction @ self.velocity) * dt
            if not np.any(self.velocity) and not np.any(v_des):
                self.state = "idle"  # blocked by the workspace box
        if self._p_cmd is not None:
            self._p_cmd = self._p_cmd + self.velocity * dt
        g_step = self._gripper_step(dt)
        self.time += dt
        twist = np.zeros(6)
        twist[3:] = self.velocity
        return Command(
            twist=twist,
            orientation=self._R_home,
            gripper_width=self.gripper_width,
            gripper_velocity=g_step / dt if dt > 0 else 0.0,
            state=self.state,
            label=self.label,
        )

    def _desired_velocity(self, pos: np.ndarray, speed: float) -> np.ndarray:
        """The velocity the current state asks for (it may change the state: arrival, contact)."""
        if self.state == "move":
            return self._move_velocity(pos, speed)
        if self.state == "idle" and self.contact and not self._hard_brake:
            return self._back_off_velocity(pos, speed)
        if self.state == "home":
            return self._home_velocity(pos, speed)
        return np.zeros(3)

    def _move_velocity(self, pos: np.ndarray, speed: float) -> np.ndarray:
        """Towards the move's end with a braking profile; a large lag of the TCP behind the
        reference is a contact: stop hard."""
        p = self.params
        if self._p_cmd is None:
            self._p_cmd = pos.copy()
        lag = float(self._direction @ (self._p_cmd - pos))
        if p.contact_deviation > 0 and lag > p.contact_deviation:
            self.contact = True
            self.state = "idle"
            self._hard_brake = True
            return np.zeros(3)
        remaining = self._travel - self._travelled
        if remaining > 1e-6:
            return self._direction * min(p.speed, math.sqrt(2 * p.acceleration * remaining))
        if speed == 0.0:
            self.state = "idle"
        return np.zeros(3)

    def _back_off_velocity(self, pos: np.ndarray, speed: float) -> np.ndarray:
        """After a contact: back the reference off until the lag (≈ contact force) is small."""
        p = self.params
        lag = float(self._direction @ (self._p_cmd - pos))
        excess = lag - 0.25 * p.contact_deviation
        if excess > 0:
            return -self._direction * min(p.speed, p.home_gain * excess + 1e-3)
        if speed == 0.0:
            self.contact = False
        return np.zeros(3)

    def _home_velocity(self, pos: np.ndarray, speed: float) -> np.ndarray:
        """Towards the home position, slowing down proportionally near it."""
        p = self.params
        e = self._home - pos
        dist = float(np.linalg.norm(e))
        if dist < p.home_tolerance and speed < 1e-3:
            self.state = "idle"
        elif dist > 0:
            return e / dist * min(p.home_speed, math.sqrt(2 * p.acceleration * dist), p.home_gain * dist)
        return np.zeros(3)

    def _inside_workspace(self, v_des: np.ndarray, pos: np.ndarray) -> np.ndarray:
        """The desired velocity limited so that the TCP can brake to rest at the box's faces."""
        a = self.params.acceleration
        room_hi = np.maximum(self._hi - pos, 0.0)
        room_lo = np.maximum(pos - self._lo, 0.0)
        v_des = np.minimum(v_des, np.sqrt(2 * a * room_hi))
        return np.maximum(v_des, -np.sqrt(2 * a * room_lo))

    def _accelerate(self, v_des: np.ndarray, a_max: float, dt: float) -> None:
        """Move the commanded velocity towards ``v_des`` with bounded acceleration; at rest, a stop
        or a hard brake ends."""
        dv = v_des - self.velocity
        n = float(np.linalg.norm(dv))
        if n > a_max * dt:
            dv *= a_max * dt / n
        self.velocity = self.velocity + dv
        if not np.any(np.abs(self.velocity) > 1e-9):
            self.velocity = np.zeros(3)
            if self.state == "stop" or (self.state == "idle" and self._hard_brake):
                self.state = "idle"
                self._hard_brake = False

    def _gripper_step(self, dt: float) -> float:
        """Move the gripper reference towards its target at the gripper speed; returns the step."""
        g_err = self.gripper_target - self.gripper_width
        g_step = math.copysign(min(abs(g_err), self.params.gripper_speed * dt), g_err)
        self.gripper_width += g_step
        return g_step
