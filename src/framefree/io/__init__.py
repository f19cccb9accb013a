"""Poses in and events out: live pose sources (CSV replay, ZeroMQ on loopback, OpenVR), one
module per transport or file format. Pose files themselves are read by
:meth:`framefree.core.trajectory.Trajectory.from_csv`.
"""
