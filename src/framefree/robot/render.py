"""Offscreen rendering of simulated sessions (PNG strips, animated GIF) and matplotlib figures.

MuJoCo needs an offscreen OpenGL: ``MUJOCO_GL=egl`` (GPU/EGL driver; the default chosen by
:mod:`framefree.robot.sim` when there is no display) or ``MUJOCO_GL=osmesa`` (software; Debian
package ``libosmesa6``). The backend is fixed when :mod:`mujoco` is first imported, so set the
variable before that. :func:`rendering_available` tells whether it works and why not.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .panda_model import SceneSpec, scene_xml
from .sim import import_mujoco

__all__ = [
    "plot_session",
    "render_frames",
    "rendering_available",
    "save_gif",
    "save_strip",
]

_CHECKED: tuple[bool, str] | None = None


def rendering_available() -> tuple[bool, str]:
    """Whether MuJoCo can render offscreen in this process.

    Returns
    -------
    ok : bool
    message : str
        The backend in use, or why rendering does not work and what to do about it.
    """
    global _CHECKED
    if _CHECKED is not None:
        return _CHECKED
    backend = os.environ.get("MUJOCO_GL", "(default)")
    try:
        mj = import_mujoco()
        m = mj.MjModel.from_xml_string(
            '<mujoco><worldbody><geom type="sphere" size="0.1"/></worldbody></mujoco>'
        )
        r = mj.Renderer(m, 8, 8)
        d = mj.MjData(m)
        r.update_scene(d)
        r.render()
        r.close()
        _CHECKED = (True, f"offscreen rendering with MUJOCO_GL={backend}")
    except Exception as exc:  # any GL failure means: no rendering here
        _CHECKED = (
            False,
            f"offscreen rendering unavailable with MUJOCO_GL={backend} ({type(exc).__name__}: "
            f"{str(exc).strip().splitlines()[-1] if str(exc).strip() else exc!r}); set "
            "MUJOCO_GL=egl (needs an EGL driver) or MUJOCO_GL=osmesa (apt-get install "
            "libosmesa6) before starting Python",
        )
    return _CHECKED


def render_frames(
    log,
    times: np.ndarray | None = None,
    n_frames: int = 8,
    scene: SceneSpec | None = None,
    width: int = 480,
    height: int = 360,
    lookat: tuple[float, float, float] = (0.35, 0.0, 0.3),
    distance: float = 2.0,
    azimuth: float = 150.0,
    elevation: float = -20.0,
) -> list[np.ndarray]:
    """Render the logged configurations of a session.

    Parameters
    ----------
    log : SessionLog
        The session (its ``qpos`` rows are rendered).
    times : ndarray, shape (k,), optional
        Simulated times to render [s] (nearest logged sample); default ``n_frames`` evenly
        spaced over the session.
    n_frames : int, optional
        Number of frames when ``times`` is not given.
    scene : SceneSpec, optional
        The scene the session ran in (must match the log's blocks).
    width, height : int, optional
        Image size [px].
    lookat, distance, azimuth, elevation : optional
        Free camera: target point [m], distance [m], azimuth and elevation [deg].

    Returns
    -------
    list of ndarray, shape (height, width, 3), uint8

    Raises
    ------
    RuntimeError
        When offscreen rendering does not work (the message says what to do).
    """
    ok, message = rendering_available()
    if not ok:
        raise RuntimeError(message)
    mj = import_mujoco()
    model = mj.MjModel.from_xml_string(scene_xml(scene))
    data = mj.MjData(model)
    if times is None:
        times = np.linspace(log.t[0], log.t[-1], n_frames)
    idx = np.clip(np.searchsorted(log.t, np.asarray(times, dtype=float)), 0, len(log.t) - 1)
    cam = mj.MjvCamera()
    cam.lookat[:] = lookat
    cam.distance = distance
    cam.azimuth = azimuth
    cam.elevation = elevation
    renderer = mj.Renderer(model, height, width)
    frames = []
    try:
        for i in idx:
            data.qpos[:] = log.qpos[i]
            mj.mj_forward(model, data)
            renderer.update_scene(data, camera=cam)
            frames.append(renderer.render().copy())
    finally:
        renderer.close()
    return frames


def save_strip(frames: list[np.ndarray], path: str | Path, columns: int = 4) -> Path:
    """Tile frames into one PNG image (row-major grid).

    Parameters
    ----------
    frames : list of ndarray, shape (h, w, 3), uint8
        Images of equal size.
    path : str or Path
        Output PNG file.
    columns : int, optional
        Number of images per row.

    Returns
    -------
    Path
    """
    from PIL import Image

    h, w, _ = frames[0].shape
    rows = -(-len(frames) // columns)
    cols = min(columns, len(frames))
    canvas = np.full((rows * h, cols * w, 3), 255, dtype=np.uint8)
    for k, f in enumerate(frames):
        r, c = divmod(k, columns)
        canvas[r * h : (r + 1) * h, c * w : (c + 1) * w] = f
    path = Path(path)
    Image.fromarray(canvas).save(path)
    return path


def save_gif(frames: list[np.ndarray], path: str | Path, fps: float = 10.0) -> Path:
    """Write frames as an animated GIF (Pillow, no video encoder needed).

    Parameters
    ----------
    frames : list of ndarray, shape (h, w, 3), uint8
    path : str or Path
    fps : float, optional
        Frames per second of the animation.

    Returns
    -------
    Path
    """
    from PIL import Image

    images = [Image.fromarray(f) for f in frames]
    path = Path(path)
    images[0].save(
        path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0
    )
    return path


def _block_colours(names: list[str]) -> dict[str, tuple[str, tuple[float, ...]]]:
    """Each block's colour in the scene (a word and an RGBA) for the default scene's blocks."""
    from .panda_model import SceneSpec

    rgba = {b.name: b.rgba for b in SceneSpec().blocks}
    out = {}
    for name in names:
        c = rgba.get(name, (0.5, 0.5, 0.5, 1.0))
        word = ("red", "green", "blue")[int(max(range(3), key=lambda i: c[i]))]
        out[name] = (word, c)
    return out


def plot_session(log, path: str | Path, title: str = "") -> Path:
    """Figure of a session: TCP and block paths, TCP position with the gripper and the commands,
    block heights, joint angles.

    Parameters
    ----------
    log : SessionLog
    path : str or Path
        Output image file (PNG, PDF, …).
    title : str, optional

    Returns
    -------
    Path
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    colours = _block_colours(list(log.block_names))
    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5))
    _session_paths(ax[0, 0], log, colours)
    _session_tcp(ax[0, 1], log)
    a = ax[1, 0]
    for k, name in enumerate(log.block_names):
        word, rgba = colours[name]
        a.plot(log.t, log.blocks[:, k, 2], color=rgba, label=f"{name} ({word})")
    a.set_xlabel("t [s]")
    a.set_ylabel("block centre height z [m]")
    a.set_title("Block heights")
    a.legend(fontsize=8)
    a = ax[1, 1]
    a.plot(log.t, log.q)
    a.set_xlabel("t [s]")
    a.set_ylabel("joint angle [rad]")
    a.set_title("Joint angles")
    a.legend([f"q{i + 1}" for i in range(7)], fontsize=7, ncol=4)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _session_paths(a, log, colours) -> None:
    """Side view of the TCP path and the blocks' paths (start ○, end □), blocks in their colour."""
    a.plot(log.ee[:, 1], log.ee[:, 2], "k-", lw=1.2, label="TCP")
    for k, name in enumerate(log.block_names):
        word, rgba = colours[name]
        b = log.blocks[:, k]
        a.plot(b[:, 1], b[:, 2], "--", lw=1.0, color=rgba, label=f"{name} ({word})")
        a.plot(b[0, 1], b[0, 2], "o", ms=4, color=rgba)
        a.plot(b[-1, 1], b[-1, 2], "s", ms=5, color=rgba)
    a.plot([], [], "o", color="0.4", ms=4, label="block at start")
    a.plot([], [], "s", color="0.4", ms=5, label="block at end")
    a.set_xlabel("y [m] (+ = robot's left)")
    a.set_ylabel("z [m]")
    a.set_title("TCP and block paths (base frame, side view)")
    a.set_aspect("equal", adjustable="datalim")
    a.legend(fontsize=7)


def _session_tcp(a, log) -> None:
    """TCP position and gripper opening over time; the commands as labelled ticks on top."""
    for k, axis in enumerate("xyz"):
        a.plot(log.t, log.ee[:, k], label=f"TCP {axis}")
    a2 = a.twinx()
    a2.plot(log.t, log.gripper, "k:", lw=1.0, label="gripper opening")
    a2.set_ylabel("gripper opening [m]")
    a.set_xlabel("t [s]")
    a.set_ylabel("TCP position [m]")
    lines = a.get_lines() + a2.get_lines()
    a.legend(lines, [ln.get_label() for ln in lines], loc="lower right", fontsize=7)
    for d in log.decisions:
        a.axvline(d.time, color="0.85", lw=0.6, zorder=0)
    top = a.secondary_xaxis("top")
    top.set_xticks([d.time for d in log.decisions], [d.event.label.replace("_", " ") for d in log.decisions],
                   rotation=90, fontsize=6)
    top.tick_params(length=2, pad=1)
