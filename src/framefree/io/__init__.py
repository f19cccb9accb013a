"""Pose sources and event outputs over lab transports (LSL, ROS 2 bags, OSC, JSON lines)."""
