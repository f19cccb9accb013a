"""Live ROS 2 topics: the spec syntax, and one clear line where rclpy cannot be imported (it
comes with a ROS 2 installation, not from PyPI)."""

from __future__ import annotations

import importlib.util

import pytest
from click.testing import CliRunner

from framefree.cli import cli
from framefree.errors import FramefreeError
from framefree.io.outputs import check_spec
from framefree.io.ros2 import ROS2_MISSING, parse_topic

NO_RCLPY = importlib.util.find_spec("rclpy") is None


def test_topic_specs():
    assert parse_topic("ros2:///tracker/pose") == ("/tracker/pose", "pose")
    assert parse_topic("ros2:///odom#odometry") == ("/odom", "odometry")
    for bad in ("ros2://tracker/pose", "ros2:///", "ros2:///x#twist", "lsl://x"):
        with pytest.raises(FramefreeError):
            parse_topic(bad)
    check_spec("ros2:///gestures")
    with pytest.raises(FramefreeError, match="ros2:///TOPIC"):
        check_spec("ros2://gestures")


@pytest.mark.skipif(not NO_RCLPY, reason="rclpy is installed: the message below is not shown")
def test_without_rclpy_one_line_says_what_to_install(tmp_path):
    res = CliRunner().invoke(cli, ["record", "--source", "ros2:///tracker/pose", "--gesture", "wave",
                                   "--library", str(tmp_path / "lib")])
    assert res.exit_code == 2
    assert ROS2_MISSING in res.output and res.output.strip().count("\n") == 0
    assert not (tmp_path / "lib").exists()
    from framefree.io.outputs import open_emitter

    with pytest.raises(FramefreeError, match="rclpy"):
        open_emitter("ros2:///gestures")
