"""The maths at the bottom of framefree: SE(3) and quaternions (:mod:`~framefree.core.se3`),
Kabsch alignment, DTW kernels, Kalman and Gaussian smoothing, geometric progress and
reparameterization, the pose CSV format and the :class:`~framefree.core.trajectory.Trajectory`
value type. Nothing here imports anything else of framefree but :mod:`framefree.errors`.
"""
