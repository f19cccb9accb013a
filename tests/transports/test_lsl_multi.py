"""An LSL stream of two trackers (8 channels each, with the valid flag) read whole: one pose of
every tracker per sample, a lost tracker's position NaN. Run in a child process, so that liblsl
loads with framefree's configuration; nothing may leave loopback (``loopback_only``)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

_TWO_TRACKERS = """
import threading, time, uuid
import numpy as np
from framefree.io.lsl import LslSource, import_pylsl
pylsl = import_pylsl()
name = f"ff-two-{uuid.uuid4().hex[:8]}"

def send():
    info = pylsl.StreamInfo(name, "MoCap", 16, 90.0, pylsl.cf_double64, name)
    outlet = pylsl.StreamOutlet(info)
    outlet.wait_for_consumers(30.0)
    for k in range(30):
        right = [0.1 * k, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        left = [0.0, 0.4, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0 if k == 7 else 1.0]  # lost at k = 7
        outlet.push_sample(right + left, 50.0 + k / 90.0)
        time.sleep(0.002)
    time.sleep(0.3)
    del outlet

sender = threading.Thread(target=send)
sender.start()
source = LslSource(name, tracker=None, timeout=10.0)
poses = list(source)
sender.join()
t, p, q = poses[7]
print(source.n_trackers, len(poses), p.shape, q.shape, np.isnan(p[1]).all(), p[0, 0], q[1].tolist())
"""


def test_every_tracker_of_an_lsl_stream_at_once(loopback_only):
    pytest.importorskip("pylsl", reason="pip install 'framefree[lsl]'")
    env = {k: v for k, v in os.environ.items() if k != "LSLAPICFG"}
    proc = subprocess.run([sys.executable, "-c", _TWO_TRACKERS], capture_output=True, text=True,
                          env=env, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["2", "30", "(2,", "3)", "(2,", "4)", "True", "0.7000000000000001",
                                   "[0.0,", "0.0,", "0.0,", "1.0]"]
