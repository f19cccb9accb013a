"""Poses in and events out, one module per transport or file format: live pose sources (CSV
replay, ZeroMQ on loopback, OpenVR, Lab Streaming Layer, ROS 2 bags), event outputs (JSON lines,
OSC, LSL markers), recording formats (Machete, the multi-tracker CSV, the gesture library file)
and coordinate conventions. Single-tracker pose files are read by
:meth:`framefree.core.trajectory.Trajectory.from_csv`.
"""
