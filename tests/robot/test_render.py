"""Rendering: frames when offscreen GL works, a clear message otherwise; session figure."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

from framefree.online.events import Event
from framefree.robot.render import (
    plot_session,
    render_frames,
    rendering_available,
    save_gif,
    save_strip,
)
from framefree.robot.session import run_events


@pytest.fixture(scope="module")
def log():
    return run_events([Event("go_up", 0.05, 0.1, 0)], duration=0.5, log_rate=20)


def test_session_figure(log, tmp_path):
    path = plot_session(log, tmp_path / "session.png", title="test")
    assert path.stat().st_size > 10_000


def test_render_frames_or_clear_message(log, tmp_path):
    ok, message = rendering_available()
    if not ok:
        assert "MUJOCO_GL" in message
        with pytest.raises(RuntimeError, match="MUJOCO_GL"):
            render_frames(log, n_frames=2)
        pytest.skip(message)
    frames = render_frames(log, n_frames=3, width=96, height=64)
    assert len(frames) == 3 and frames[0].shape == (64, 96, 3) and frames[0].dtype == np.uint8
    assert frames[0].std() > 5  # not a blank image
    assert save_strip(frames, tmp_path / "strip.png", columns=2).stat().st_size > 0
    assert save_gif(frames, tmp_path / "anim.gif").stat().st_size > 0
