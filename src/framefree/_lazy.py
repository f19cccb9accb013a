"""Public names imported on first use (:pep:`562`), for the package ``__init__`` modules.

``framefree`` and ``framefree.online`` expose many names whose modules pull in numba kernels,
matplotlib or pose sources. Importing them only when a name is first looked up keeps
``import framefree`` and ``framefree live`` fast.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


def lazy_attributes(
    package: str, namespace: dict[str, Any], table: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """Module-level ``__getattr__`` and ``__dir__`` for a package with lazily imported names.

    Parameters
    ----------
    package : str
        The package's ``__name__`` (relative module names in ``table`` resolve against it).
    namespace : dict
        The package's ``globals()``; a name, once imported, is stored there so that later lookups
        cost nothing.
    table : mapping of str to str
        Public name -> (relative) module that defines it.

    Returns
    -------
    getattr_, dir_ : callable
        To be assigned to the package's ``__getattr__`` and ``__dir__``.
    """

    def getattr_(name: str) -> Any:
        if name in table:
            value = getattr(importlib.import_module(table[name], package), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def dir_() -> list[str]:
        return sorted(set(namespace) | set(table))

    return getattr_, dir_
