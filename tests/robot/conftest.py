"""MuJoCo picks its GL backend at import: choose the offscreen one before any test imports it."""

import os

if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
    os.environ["MUJOCO_GL"] = "egl"
