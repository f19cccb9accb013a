"""A simulated Franka FR3 served over the real libfranka protocol, on loopback (franky-sim).

``franky-sim`` (``pip install 'framefree[franka]'``) runs the published FR3 model with its
gripper in MuJoCo and answers on UDP/TCP exactly as an arm's FCI does, so the client side —
franky, libfranka and :class:`~framefree.robot.backends.FrankaBackend` — is the one that drives a
real arm. The server binds the first free address among ``hosts`` (all loopback): a second
simulator finds 127.0.0.1 busy and takes 127.0.0.2, so always connect to :attr:`host`.

>>> with ProtocolSimulator() as sim:                         # doctest: +SKIP
...     backend = FrankaBackend(sim.host)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import FramefreeError
from .kinematics import Q_READY

__all__ = ["LOOPBACK_HOSTS", "ProtocolSimulator"]

#: Addresses the simulator may bind, in order (loopback only: nothing outside the machine).
LOOPBACK_HOSTS = tuple(f"127.0.0.{k}" for k in range(1, 17))

_MISSING = ("the Franka simulator needs franky-sim: pip install 'framefree[franka]' "
            "(or make env, which installs it)")


class ProtocolSimulator:
    """Start and stop a franky-sim FR3 in this process (a server thread at 1 kHz, real time).

    Parameters
    ----------
    q0 : array_like, shape (7,), optional
        Initial joint angles [rad] (default: Franka's ready pose, as the MuJoCo demo).
    gripper_width : float
        Initial finger opening [m].
    hosts : sequence of str
        Candidate loopback addresses, tried in order.

    Attributes
    ----------
    host : str
        The address the arm answers on (set by :meth:`start`).
    """

    def __init__(self, q0: Sequence[float] | np.ndarray | None = None,
                 gripper_width: float = 0.07, hosts: Sequence[str] = LOOPBACK_HOSTS) -> None:
        self.q0 = [float(v) for v in (Q_READY if q0 is None else q0)]  # franky-sim wants floats
        if len(self.q0) != 7:
            raise ValueError(f"q0 needs 7 joint angles, got {len(self.q0)}")
        self.gripper_width = float(gripper_width)
        if any(not h.startswith("127.") for h in hosts):
            raise ValueError("the simulator binds loopback addresses (127.*) only")
        self.hosts = tuple(hosts)
        self.host: str | None = None
        self._sim: Any = None
        self._server: Any = None

    def start(self) -> str:
        """Build the scene, bind, run the server thread; return the host to connect to."""
        from . import sim as _gl  # noqa: F401  (MuJoCo's GL backend is chosen at its first import)

        try:
            from franky_sim import SimulationServer
            from franky_sim.mujoco_simulator import MujocoSimulator
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self._sim = MujocoSimulator()
        self._sim.init()
        robot = self._sim.add_robot(initial_q=self.q0, initial_hand_width=self.gripper_width)
        self._server = SimulationServer(self._sim, self.hosts)
        try:
            self._server.init()
        except OSError as exc:
            self.stop()
            raise FramefreeError(f"Franka simulator: no free loopback address ({exc})") from None
        self._server.run_async()
        self.host = str(robot.hostname)
        return self.host

    def stop(self) -> None:
        """Stop the server thread and release the addresses (safe to call twice)."""
        server, sim = self._server, self._sim
        self._server = self._sim = None
        if server is not None:
            server.cleanup()
            # close the client connections too: a client left on an open connection that nobody
            # answers blocks for ever in libfranka's stop (franky calls it when its Robot is
            # destroyed), instead of seeing the connection lost
            for robot_server in server.robot_servers:
                robot_server.reset_state()
                if robot_server.gripper_server is not None:
                    robot_server.gripper_server.reset_state()
        if sim is not None and sim.is_initialized and not sim.is_cleaned_up:
            sim.cleanup()

    @property
    def running(self) -> bool:
        """Whether the server thread runs."""
        return self._server is not None and bool(self._server.running)

    def __enter__(self) -> ProtocolSimulator:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
