"""A gesture library's settings: what it stores, and how an older library is migrated.

A library file of format 4 (:mod:`framefree.io.library_file`) stores the user's settings
(``config``: :meth:`RecognizerConfig.to_dict <framefree.online.config.RecognizerConfig.to_dict>`)
and what enrolment learned from the takes (``learned``: :meth:`LearnedSettings.to_dict
<framefree.online.learned.LearnedSettings.to_dict>`, values and provenance).

A library of format 3 stored one flat configuration of 69 fields with the learned values in it.
:func:`settings_from_meta` sorts it into the two: every value is kept, so the migrated library
recognizes exactly as before. What cannot be sorted (a setting this framefree does not know)
fails with one line saying how to enroll the library again.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..io.library_file import FORMAT_VERSION, LibraryError, rebuild_hint
from .config import RecognizerConfig
from .learned import LEARNED_NAMES, LearnedSettings, Provenance, takes_digest

__all__ = ["settings_from_meta"]

#: Settings a format-3 library may lack, with the value it was enrolled with: one saved before
#: ``align`` existed aligned on singular values, one saved before ``gesture_pauses`` existed
#: kept the pause limits common to all gestures.
_V3_DEFAULTS = {"align": "singular", "gesture_pauses": False, "valley_starts": False}
#: Constants a format-4 library may lack, with the value it was enrolled and calibrated with:
#: one saved before ``valley_starts`` existed (v28 and before) started candidates only after a
#: rest or a dip.
_V4_CONSTANTS = {"valley_starts": False}


def settings_from_meta(path: str | Path, meta: dict[str, Any],
                       rows: Sequence[np.ndarray] = ()) -> tuple[RecognizerConfig, LearnedSettings]:
    """The user settings and learned values of a library file's JSON member.

    Parameters
    ----------
    path : path
        The library file (for messages).
    meta : dict
        Its JSON member, format 4 or 3 (:data:`~framefree.io.library_file.READABLE_FORMATS`).
    rows : sequence of (N_k, 8) arrays, optional
        The takes' rows (a migrated library's provenance names them by their SHA-256).

    Raises
    ------
    LibraryError
        One line, saying how to enroll the library again, when its settings do not fit this
        framefree.
    """
    try:
        if meta.get("format_version") == FORMAT_VERSION:
            config = dict(meta["config"])
            if isinstance(config.get("constants"), dict):
                config["constants"] = {**_V4_CONSTANTS, **config["constants"]}
            return (RecognizerConfig.from_dict(config),
                    LearnedSettings.from_dict(meta["learned"]))
        return _migrate_v3(meta, rows)
    except (KeyError, TypeError, ValueError) as exc:
        raise LibraryError(f"{path}: settings do not fit framefree {__version__} ({exc}); "
                           f"{rebuild_hint(Path(path), meta)}") from None


def _migrate_v3(meta: dict[str, Any], rows: Sequence[np.ndarray]
                ) -> tuple[RecognizerConfig, LearnedSettings]:
    """Sort a format-3 library's flat configuration into user settings and learned values."""
    flat = {**_V3_DEFAULTS, **meta["config"]}
    asked = meta.get("settings") or {}
    user = {k: v for k, v in flat.items() if k not in LEARNED_NAMES}
    for name in ("gesture_thresholds", "stop_threshold"):  # user settings: as asked
        user[name] = asked.get(name)
    values = {k: v for k, v in flat.items() if k in LEARNED_NAMES and v is not None}
    values["gesture_thresholds"] = meta["gesture_thresholds"]
    values["stop_threshold"] = meta["stop_threshold"]
    version = meta.get("framefree_version", "?")
    rule = f"learned by framefree {version} (library format 3)"
    provenance = Provenance({k: rule for k in values}, len(meta.get("names") or ()),
                            takes_digest(rows) if len(rows) else "", version,
                            f"migrated from library format 3 by framefree {__version__}")
    return RecognizerConfig.from_dict(user), LearnedSettings(**values, provenance=provenance)
