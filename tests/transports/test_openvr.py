"""The OpenVR source, one device or several, against a stand-in for the ``openvr`` package.

SteamVR and a headset are not on a test machine; the stand-in answers the four calls the
source makes (device classes, poses, init, shutdown) as pyopenvr does, so what is tested is
framefree's side: which devices are chosen, the pose conversion, NaN for a device that lost
tracking, and the one-line errors."""

from __future__ import annotations

import itertools
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from framefree.core import se3
from framefree.errors import FramefreeError
from framefree.io.openvr_source import OpenVRSource
from framefree.io.sources import open_source

HMD, CONTROLLER, TRACKER = 1, 2, 3
CLASSES = [HMD, CONTROLLER, CONTROLLER, TRACKER, 0, 0, 0, 0]
R = se3.rotation_from_vector(np.array([0.2, -0.4, 0.9]))


def _matrix(k: int, device: int) -> list[list[float]]:
    """Device-to-world 3 × 4 matrix of device ``device`` at poll ``k``: R, and a position that
    moves 1 cm per poll."""
    p = np.array([0.1 * device, 1.0 + 0.01 * k, -0.5])
    return np.hstack([R, p[:, None]]).tolist()


class _System:
    def __init__(self, lost: int | None = None) -> None:
        self.polls = itertools.count()
        self.lost = lost  # a device whose tracking is lost

    def getTrackedDeviceClass(self, i: int) -> int:
        return CLASSES[i]

    def getDeviceToAbsoluteTrackingPose(self, universe, seconds, count):
        k = next(self.polls)
        return [SimpleNamespace(bPoseIsValid=i != self.lost, mDeviceToAbsoluteTracking=_matrix(k, i))
                for i in range(count)]


@pytest.fixture
def openvr(monkeypatch):
    """Install the stand-in as ``openvr``; returns it (its ``system`` and ``shut`` flag)."""
    module = SimpleNamespace(
        VRApplication_Other=3, k_unMaxTrackedDeviceCount=len(CLASSES), TrackingUniverseStanding=1,
        TrackedDeviceClass_Controller=CONTROLLER, TrackedDeviceClass_GenericTracker=TRACKER,
        system=_System(), shut=[])
    module.init = lambda kind: module.system
    module.shutdown = lambda: module.shut.append(True)
    monkeypatch.setitem(sys.modules, "openvr", module)
    return module


def _first(source, n: int = 3) -> list:
    return list(itertools.islice(iter(source), n))


def test_one_device_is_the_generic_tracker_with_its_pose(openvr):
    source = OpenVRSource(rate=1000.0)
    assert source.device == 3 and source.n_trackers == 1
    samples = _first(source)
    _, p, q = samples[-1]
    assert p.shape == (3,) and q.shape == (4,)
    np.testing.assert_allclose(p, [0.3, 1.02, -0.5])
    np.testing.assert_allclose(se3.matrix_from_quaternion(q), R, atol=1e-12)
    assert [s[0] for s in samples] == sorted(s[0] for s in samples)


def test_several_devices_are_every_controller_and_tracker(openvr):
    source = open_source("openvr", several=True)
    assert source.n_trackers == 3
    _, p, q = _first(source, 1)[0]
    assert p.shape == (3, 3) and q.shape == (3, 4)
    np.testing.assert_allclose(p[:, 0], [0.1, 0.2, 0.3])  # devices 1, 2, 3 in order


def test_named_devices_and_a_lost_one(openvr):
    openvr.system.lost = 2
    source = open_source("openvr#2,1", several=True)
    _, p, q = _first(source, 1)[0]
    assert np.isnan(p[0]).all() and np.isnan(q[0]).all()  # device 2 lost tracking
    np.testing.assert_allclose(p[1], [0.1, 1.0, -0.5])


def test_one_device_skips_the_samples_it_lost(openvr):
    openvr.system.lost = 3
    source = OpenVRSource(rate=1000.0, device=1)
    assert np.isfinite(_first(source, 1)[0][1]).all()
    source = OpenVRSource(rate=1000.0, devices=[3, 1])
    assert np.isnan(_first(source, 1)[0][1][0]).all()


def test_the_source_shuts_openvr_down_when_left(openvr):
    source = OpenVRSource(rate=1000.0)
    it = iter(source)
    next(it)
    it.close()
    assert openvr.shut == [True]


@pytest.mark.parametrize(("spec", "several", "message"), [
    ("openvr#x", False, "expected openvr or openvr#DEVICE"),
    ("openvr#0", False, "device 0 is no tracker or controller"),
    ("openvr#1,9", True, "device 9 is no tracker or controller"),
])
def test_wrong_devices_say_so_in_one_line(openvr, spec, several, message):
    with pytest.raises(FramefreeError, match=message):
        open_source(spec, several=several)


def test_several_need_two_devices(openvr, monkeypatch):
    monkeypatch.setattr(sys.modules[__name__], "CLASSES", [HMD, CONTROLLER, 0, 0, 0, 0, 0, 0])
    with pytest.raises(FramefreeError, match="reports 1 tracker or controller"):
        OpenVRSource(several=True)


def test_without_openvr_the_message_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "openvr", None)  # import fails
    with pytest.raises(FramefreeError, match="pip install openvr"):
        OpenVRSource()
