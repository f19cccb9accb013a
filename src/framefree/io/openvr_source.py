"""Poses of HTC Vive trackers and controllers through OpenVR/SteamVR (optional ``openvr``).

One device (a generic tracker, else a controller), or several at once for a recognizer of
several trackers: every controller and generic tracker SteamVR reports, in device order, or the
devices named (``openvr#3,4``). A device that loses tracking gives NaN for that sample, which the
recognizer's gate drops or bridges as it does any dropout (docs/streams.md).
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

from ..core.se3 import quaternion_from_matrix
from ..errors import FramefreeError

__all__ = ["OpenVRSource"]

_MISSING = ("the OpenVR adapter needs the 'openvr' package (pip install openvr) and a running "
            "SteamVR with the tracker paired; use --source zmq://127.0.0.1:PORT or a CSV file "
            "otherwise")


class OpenVRSource:
    """Poses of one or several tracked devices through OpenVR, polled at a fixed rate.

    Parameters
    ----------
    rate : float
        Polling rate [Hz].
    device : int, optional
        Tracked-device index of the one device; default: the first generic tracker, else the
        first controller.
    devices : sequence of int, optional
        Several devices: their indices, in the order of the recognizer's trackers. Yields
        positions (n, 3) [m] and quaternions (n, 4) per sample.
    several : bool
        Several devices, found: every generic tracker and controller SteamVR reports, in device
        order (at least two).

    Raises
    ------
    FramefreeError
        When the ``openvr`` package or a running SteamVR is not available, or the devices are not
        there.
    """

    def __init__(self, rate: float = 50.0, device: int | None = None,
                 devices: Sequence[int] | None = None, several: bool = False) -> None:
        try:
            import openvr  # type: ignore[import-not-found]
        except ImportError:
            raise FramefreeError(_MISSING) from None
        self._openvr = openvr
        try:
            self._vr = openvr.init(openvr.VRApplication_Other)
        except Exception as exc:  # openvr raises its own error types
            raise FramefreeError(f"SteamVR is not running or no headset/tracker is present ({exc})") from None
        self.rate = float(rate)
        self.several = bool(several or devices is not None)
        if devices is not None:
            self.devices = [int(d) for d in devices]
            self._check(self.devices)
        elif self.several:
            self.devices = self._find_all()
        elif device is not None:
            self.devices = [int(device)]
            self._check(self.devices)
        else:
            self.devices = [self._find_device()]
        self.device = self.devices[0]

    @classmethod
    def from_spec(cls, spec: str, several: bool = False) -> OpenVRSource:
        """``openvr`` (one device, or every one with ``several``) or ``openvr#I,J,...`` (these
        device indices)."""
        _, _, named = spec.partition("#")
        if not named:
            return cls(several=several)
        try:
            devices = [int(x) for x in named.split(",")]
        except ValueError:
            raise FramefreeError(f"{spec}: expected openvr or openvr#DEVICE,DEVICE,... (device "
                                 "indices)") from None
        if len(devices) == 1 and not several:
            return cls(device=devices[0])
        return cls(devices=devices)

    @property
    def n_trackers(self) -> int:
        """Devices per sample."""
        return len(self.devices)

    def _classes(self) -> list[Any]:
        ovr = self._openvr
        return [self._vr.getTrackedDeviceClass(i) for i in range(ovr.k_unMaxTrackedDeviceCount)]

    def _wanted(self) -> tuple[Any, Any]:
        return (self._openvr.TrackedDeviceClass_GenericTracker,
                self._openvr.TrackedDeviceClass_Controller)

    def _find_device(self) -> int:
        classes = self._classes()
        for wanted in self._wanted():
            if wanted in classes:
                return classes.index(wanted)
        raise FramefreeError("SteamVR reports no tracker or controller")

    def _find_all(self) -> list[int]:
        found = [i for i, c in enumerate(self._classes()) if c in self._wanted()]
        if len(found) < 2:
            raise FramefreeError(f"SteamVR reports {len(found)} tracker or controller, and the "
                                 "models have several: pair them, or name them (openvr#I,J)")
        return found

    def _check(self, devices: Sequence[int]) -> None:
        classes = self._classes()
        for d in devices:
            if not 0 <= d < len(classes) or classes[d] not in self._wanted():
                raise FramefreeError(f"openvr: device {d} is no tracker or controller")

    def _pose(self, pose: Any) -> tuple[np.ndarray, np.ndarray]:
        """Position (3,) [m] and quaternion (4,) of one device's pose; NaN when not tracked."""
        if not pose.bPoseIsValid:
            return np.full(3, np.nan), np.full(4, np.nan)
        m = np.array([[pose.mDeviceToAbsoluteTracking[r][c] for c in range(4)] for r in range(3)])
        return m[:, 3].copy(), quaternion_from_matrix(m[:, :3], continuous=False)

    def __iter__(self) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
        ovr = self._openvr
        t0 = time.perf_counter()
        period = 1.0 / self.rate
        try:
            while True:
                poses = self._vr.getDeviceToAbsoluteTrackingPose(
                    ovr.TrackingUniverseStanding, 0, ovr.k_unMaxTrackedDeviceCount)
                t = time.perf_counter() - t0
                sample = [self._pose(poses[d]) for d in self.devices]
                if self.several:
                    yield t, np.stack([p for p, _ in sample]), np.stack([q for _, q in sample])
                elif np.isfinite(sample[0][0]).all():
                    yield t, sample[0][0], sample[0][1]
                time.sleep(max(0.0, period - math.fmod(time.perf_counter() - t0, period)))
        finally:
            ovr.shutdown()
