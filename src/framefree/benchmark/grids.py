"""The method/progress rows of Table I and their training grids (ALGORITHMS.md §7.2, §7.5).

A :class:`MethodSpec` names one row of the paper's Table I (a descriptor and a progress type) and
knows its 2-D training grid over ``(x, L)``: ``x`` is the descriptor-specific parameter (λ for DHB,
eFS and ISA; the window scale ``ds_scale`` for BILTS and BILTS+; nothing for RRV and DSRF), ``L``
[m] the scale length. The grids are exactly those of the reference, and
:meth:`MethodSpec.grid` lists the points in the order in which the tie rule of §7.3 scans them:
smallest ``x`` first, then smallest ``L``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

__all__ = [
    "L_VALUES",
    "TABLE1_ROWS",
    "X_VALUES",
    "MethodSpec",
    "parse_methods",
    "row_key",
]

#: scale lengths L [m] of every 2-D grid (``linspace(0.1, 0.9, 5)``)
L_VALUES: tuple[float, ...] = (0.1, 0.3, 0.5, 0.7, 0.9)

#: x values per (descriptor, progress); ``"*"`` matches any progress type
X_VALUES: dict[tuple[str, str], tuple[float, ...]] = {
    ("dhb", "*"): (0.01, 0.1, 1.0, 10.0, 100.0),
    ("efs", "*"): (0.001, 0.01, 0.1, 1.0, 10.0),
    ("isa", "*"): (0.0001, 0.001, 0.01, 0.1, 1.0),
    ("bilts", "angle"): tuple(math.radians(d) for d in (1.0, 10.0, 20.0, 30.0, 40.0)),
    ("bilts", "screw"): (0.03, 0.06, 0.09, 0.12, 0.15),
    ("bilts+", "angle"): tuple(math.radians(d) for d in (1.0, 10.0, 20.0, 30.0, 40.0)),
    ("bilts+", "screw"): (0.03, 0.06, 0.09, 0.12, 0.15),
}

#: the descriptor constructor argument that ``x`` sets (None: no x parameter)
X_PARAM: dict[str, str | None] = {
    "dhb": "lam",
    "efs": "lam",
    "isa": "lam",
    "bilts": "ds_scale",
    "bilts+": "ds_scale",
    "rrv": None,
    "dsrf": None,
}

#: global descriptors: positions normalized by the arclength of the time trajectory (§4.7); L
#: is trained only with screw-path progress
GLOBAL_METHODS: frozenset[str] = frozenset({"rrv", "dsrf"})

#: display names as printed in Table I
DISPLAY_NAMES: dict[str, str] = {
    "dhb": "DHB",
    "efs": "eFS",
    "isa": "ISA",
    "bilts": "BILTS",
    "bilts+": "BILTS+",
    "rrv": "RRV",
    "dsrf": "DSRF",
}

#: progress names as printed in Table I
PROGRESS_NAMES: dict[str, str] = {"arclength": "arclength", "angle": "angle", "screw": "screw path"}

#: placeholder L passed to descriptors whose progress and descriptor do not use L (RRV, DSRF with
#: arclength or angle progress: the reference's "x = L = 1" dummies)
DUMMY_L = 1.0


def row_key(method: str, progress: str) -> str:
    """Short identifier of a row, ``"<method>:<progress>"`` (e.g. ``"bilts+:screw"``)."""
    return f"{method}:{progress}"


@dataclass(frozen=True)
class MethodSpec:
    """One row of Table I: a registered descriptor name and a progress type.

    Parameters
    ----------
    method : str
        Registered descriptor name (``"dhb"``, ``"efs"``, ``"isa"``, ``"bilts"``, ``"bilts+"``,
        ``"rrv"``, ``"dsrf"``, or any other registered name).
    progress : {"arclength", "angle", "screw"}
        Progress type used to reparameterize the trajectories.
    """

    method: str
    progress: str

    @property
    def key(self) -> str:
        """``"<method>:<progress>"``."""
        return row_key(self.method, self.progress)

    @property
    def label(self) -> str:
        """Human-readable row label, e.g. ``"BILTS+ screw path"``."""
        name = DISPLAY_NAMES.get(self.method, self.method)
        return f"{name} {PROGRESS_NAMES.get(self.progress, self.progress)}"

    @property
    def x_param(self) -> str | None:
        """Descriptor argument set by ``x`` (``"lam"``, ``"ds_scale"`` or None)."""
        return X_PARAM.get(self.method)

    @property
    def trains_L(self) -> bool:
        """Whether L is a trained parameter (False for RRV/DSRF without screw progress)."""
        return not (self.method in GLOBAL_METHODS and self.progress != "screw")

    @property
    def x_values(self) -> tuple[float, ...]:
        """Grid values of ``x`` (one dummy ``None`` when the method has no x parameter)."""
        if self.x_param is None:
            return (None,)  # type: ignore[return-value]
        for key in ((self.method, self.progress), (self.method, "*")):
            if key in X_VALUES:
                return X_VALUES[key]
        raise ValueError(f"no grid for {self.key}")

    @property
    def L_values(self) -> tuple[float, ...]:
        """Grid values of L [m] (a single dummy when L is not trained)."""
        return L_VALUES if self.trains_L else (DUMMY_L,)

    @property
    def reparameterization_uses_L(self) -> bool:
        """Whether the progress (hence the reparameterized poses) depends on L (screw path)."""
        return self.progress == "screw"

    def params(self, x: float | None, L: float) -> dict[str, Any]:
        """Descriptor constructor arguments of grid point ``(x, L)``."""
        out: dict[str, Any] = {"progress": self.progress, "L": float(L)}
        if self.x_param is not None:
            out[self.x_param] = float(x)  # type: ignore[arg-type]
        return out

    def grid(self) -> list[tuple[float | None, float]]:
        """All grid points ``(x, L)`` in tie-rule scan order: smallest x first, then smallest L."""
        return [(x, L) for x in self.x_values for L in self.L_values]

    def trained(self, x: float | None, L: float) -> dict[str, float]:
        """The trained parameters worth reporting (no dummies)."""
        out: dict[str, float] = {}
        if self.x_param is not None and x is not None:
            out[self.x_param] = float(x)
        if self.trains_L:
            out["L"] = float(L)
        return out


#: the 17 method/progress rows of Table I, in the paper's order
TABLE1_ROWS: tuple[MethodSpec, ...] = (
    MethodSpec("dhb", "arclength"),
    MethodSpec("dhb", "angle"),
    MethodSpec("dhb", "screw"),
    MethodSpec("efs", "arclength"),
    MethodSpec("efs", "angle"),
    MethodSpec("efs", "screw"),
    MethodSpec("isa", "angle"),
    MethodSpec("isa", "screw"),
    MethodSpec("bilts", "angle"),
    MethodSpec("bilts", "screw"),
    MethodSpec("bilts+", "screw"),
    MethodSpec("rrv", "arclength"),
    MethodSpec("rrv", "angle"),
    MethodSpec("rrv", "screw"),
    MethodSpec("dsrf", "arclength"),
    MethodSpec("dsrf", "angle"),
    MethodSpec("dsrf", "screw"),
)

_PROGRESS_ALIASES = {
    "arclength": "arclength",
    "arc": "arclength",
    "angle": "angle",
    "screw": "screw",
    "screw path": "screw",
    "screw_path": "screw",
    "screwpath": "screw",
}


def parse_methods(
    text: str | Sequence[str] | None, available: Sequence[str] | None = None
) -> list[MethodSpec]:
    """Parse a method selection such as ``"all"`` or ``"bilts+:screw,dhb:arclength,rrv"``.

    Parameters
    ----------
    text : str or sequence of str or None
        ``"all"`` / None (the 17 rows of Table I), or comma-separated items ``method:progress``;
        an item without ``:progress`` selects every Table I row of that method.
    available : sequence of str, optional
        Registered descriptor names; rows of other descriptors raise (or, for ``"all"``, are
        dropped). Default: no check.

    Returns
    -------
    list of MethodSpec
        In the order given (``"all"``: Table I order), without duplicates.

    Raises
    ------
    ValueError
        For an unknown progress type, or a descriptor that is not registered.
    """
    avail = None if available is None else {a.lower() for a in available}
    if text is None or (isinstance(text, str) and text.strip().lower() in ("", "all")):
        rows = list(TABLE1_ROWS)
        return rows if avail is None else [r for r in rows if r.method in avail]
    items = text.split(",") if isinstance(text, str) else list(text)
    out: list[MethodSpec] = []
    for raw in items:
        item = raw.strip().lower()
        if not item:
            continue
        method, _, prog = item.partition(":")
        method = method.strip()
        if avail is not None and method not in avail:
            raise ValueError(
                f"unknown descriptor {method!r} in --methods; available: {', '.join(sorted(avail))}"
            )
        if prog:
            try:
                progress = _PROGRESS_ALIASES[prog.strip()]
            except KeyError:
                raise ValueError(
                    f"unknown progress type {prog!r} in {raw.strip()!r}; "
                    "use arclength, angle or screw"
                ) from None
            specs = [MethodSpec(method, progress)]
        else:
            specs = [r for r in TABLE1_ROWS if r.method == method] or [
                MethodSpec(method, p) for p in ("arclength", "angle", "screw")
            ]
        for s in specs:
            if s not in out:
                out.append(s)
    if not out:
        raise ValueError("no methods selected")
    return out
