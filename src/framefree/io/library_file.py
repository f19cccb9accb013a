"""The gesture library file: the takes of a vocabulary, the recognizer settings and the calibrated
thresholds, as bytes on disk. This module knows the layout and its versions only; what a library
*is* (:class:`~framefree.library.GestureLibrary`) and how a recognizer is restored from one
(:meth:`~framefree.online.Recognizer.restore`) live above it.

File format (``FORMAT_VERSION`` 4; version 3 stored the learned values inside one flat
configuration and is migrated on loading (:mod:`framefree.online.library_settings`); version 1
predates the recognizer's ``axis_prior`` setting, which changes the models' descriptors, and
version 2 its corner limits, which change which negatives the thresholds were calibrated on, so
neither can be read): a ``.npz`` (zip) archive readable with ``numpy.load(path,
allow_pickle=False)`` plus one JSON member; nothing in it executes code when loaded.

=================  ====================================================================================
``library.json``   ``format_version``, ``framefree_version``, ``created`` (UTC), ``built_from``,
                   ``names``, ``labels``, ``config`` (the user's settings,
                   ``RecognizerConfig.to_dict``), ``learned`` (every value learned from the takes
                   and its provenance, ``LearnedSettings.to_dict``), ``calibration`` (summary),
                   ``fingerprint`` (SHA-256 of takes, labels, settings and format)
``samples.npy``    float64 (S, 8): every take's rows ``t, x, y, z, qw, qx, qy, qz`` one after another
``offsets.npy``    int64 (M + 1,): take ``k`` is ``samples[offsets[k]:offsets[k + 1]]``
=================  ====================================================================================
"""

from __future__ import annotations

import io
import json
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..core.trajectory import Trajectory
from ..errors import FramefreeError

__all__ = [
    "FORMAT_VERSION",
    "JSON_MEMBER",
    "READABLE_FORMATS",
    "LibraryError",
    "library_takes",
    "read_library_file",
    "rebuild_hint",
    "write_library_file",
]

#: Version of the library file layout and of the meaning of its settings.
FORMAT_VERSION = 4
#: Older versions that are still read (and migrated by :mod:`framefree.online.library_settings`).
READABLE_FORMATS = (3, FORMAT_VERSION)
#: Name of the JSON member (stable across format versions, so any version can be recognized).
JSON_MEMBER = "library.json"


class LibraryError(FramefreeError):
    """A gesture library cannot be built, read or used (the message says why and what to do)."""


def rebuild_hint(path: Path, meta: dict[str, Any]) -> str:
    """What to do about a library that cannot be read: enroll it again from the folders it was
    built from (the command)."""
    src = " ".join(meta.get("built_from") or []) or "LIBRARY_FOLDER"
    return f"enroll it again: framefree enroll {src} -o {path}"


def write_library_file(path: str | Path, meta: dict[str, Any], rows: Sequence[np.ndarray]) -> Path:
    """Write a library file atomically (a ``.part`` file renamed at the end).

    Parameters
    ----------
    path : path
        The file to write; parent folders are created.
    meta : dict
        The JSON member (see the module docstring).
    rows : sequence of (n_k, 8) arrays
        Every take's rows ``t, x, y, z, qw, qx, qy, qz``.

    Returns
    -------
    Path
    """
    path = Path(path)
    arrays = list(rows)
    samples = np.concatenate(arrays) if arrays else np.zeros((0, 8))
    offsets = np.concatenate([[0], np.cumsum([a.shape[0] for a in arrays])]).astype(np.int64)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".part")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr(JSON_MEMBER, json.dumps(meta, indent=1, default=float))
        for name, arr in (("samples", samples), ("offsets", offsets)):
            buf = io.BytesIO()
            np.lib.format.write_array(buf, np.ascontiguousarray(arr), allow_pickle=False)
            zf.writestr(f"{name}.npy", buf.getvalue())
    tmp.replace(path)
    return path


def read_library_file(path: str | Path) -> tuple[dict[str, Any], list[np.ndarray]]:
    """Read a library file: its JSON member and every take's rows.

    Returns
    -------
    meta : dict
        The JSON member.
    rows : list of (n_k, 8) arrays
        The takes' rows, in the order of ``meta["names"]``.

    Raises
    ------
    LibraryError
        When the file is not a library or was written in another format version (the message
        says how to rebuild it).
    """
    path = Path(path)
    try:
        with zipfile.ZipFile(path) as zf:
            meta = json.loads(zf.read(JSON_MEMBER))
            fmt = meta.get("format_version")
            if fmt not in READABLE_FORMATS:
                raise LibraryError(
                    f"{path}: gesture library format {fmt} (framefree {meta.get('framefree_version')}), "
                    f"this framefree {__version__} reads formats "
                    f"{', '.join(map(str, READABLE_FORMATS))}; {rebuild_hint(path, meta)}")
            arrays = {n: np.lib.format.read_array(io.BytesIO(zf.read(f"{n}.npy")), allow_pickle=False)
                      for n in ("samples", "offsets")}
    except (OSError, KeyError, zipfile.BadZipFile, json.JSONDecodeError, ValueError) as exc:
        if isinstance(exc, LibraryError):
            raise
        raise LibraryError(f"{path}: not a framefree gesture library ({type(exc).__name__}: {exc})") from None
    samples, offsets = arrays["samples"], arrays["offsets"]
    rows = [samples[offsets[k]:offsets[k + 1]] for k in range(len(meta["names"]))]
    return meta, rows


def library_takes(path: str | Path, rows: Sequence[np.ndarray], names: Sequence[str]) -> list[Trajectory]:
    """The takes of a library file as trajectories, each named ``<file>:<take name>``."""
    return [Trajectory.from_array(r, source=f"{path}:{n}") for r, n in zip(rows, names, strict=True)]
