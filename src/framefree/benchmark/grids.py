"""The rows of Table I, the recommended row, and their training grids.

A :class:`MethodSpec` names one row: a registered descriptor, a progress type and, for rows beyond
the paper, fixed options (pre-smoothing of the 50 Hz poses, descriptor arguments such as
``open_end``). Everything else — the trained parameter and its values, whether L is trained, the
display name — is declared by the descriptor class itself (:mod:`framefree.descriptors.base`), so
a new descriptor needs no entry here. The 2-D training grid is ``(x, L)``: ``x`` is the
descriptor's trained parameter (λ for DHB, eFS and ISA; the window scale ``ds_scale`` for BILTS and
BILTS+; nothing for RRV and DSRF), ``L`` [m] the scale length. :meth:`MethodSpec.grid` lists the
points in the order in which the tie rule scans them: smallest ``x`` first, then smallest ``L``
(``docs/algorithms/table1-protocol.md``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ..descriptors.base import L_GRID, Descriptor, descriptor_class

__all__ = [
    "L_VALUES",
    "RECOMMENDED",
    "RECOMMENDED_AXIS_PRIOR",
    "RECOMMENDED_PRESMOOTH",
    "TABLE1_ROWS",
    "MethodSpec",
    "parse_methods",
    "row_key",
]

#: scale lengths L [m] of every 2-D grid (``linspace(0.1, 0.9, 5)``)
L_VALUES: tuple[float, ...] = L_GRID

#: progress names as printed in Table I
PROGRESS_NAMES: dict[str, str] = {"arclength": "arclength", "angle": "angle", "screw": "screw path"}

#: placeholder L passed to descriptors whose progress and descriptor do not use L (RRV, DSRF with
#: arclength or angle progress: the reference's "x = L = 1" dummies)
DUMMY_L = 1.0

#: Gaussian window [samples] of the recommended row's pre-smoothing of the 50 Hz poses. A fixed
#: design constant, not searched: the value the issue reported for BILTS+ on an independent
#: held-out data set (``docs/algorithms/recommended.md``)
RECOMMENDED_PRESMOOTH = 5

#: weight κ of the recommended row's axis prior (``docs/algorithms/bilts.md#axis-prior``): the
#: origin's place along a nearly fixed screw axis is pulled towards the body origin with the weight
#: of the rotation rate itself. A fixed design constant, not searched.
RECOMMENDED_AXIS_PRIOR = 1.0


def row_key(method: str, progress: str) -> str:
    """Short identifier of a row, ``"<method>:<progress>"`` (e.g. ``"bilts+:screw"``)."""
    return f"{method}:{progress}"


@dataclass(frozen=True)
class MethodSpec:
    """One benchmark row: a registered descriptor and a progress type, plus fixed options.

    Parameters
    ----------
    method : str
        Registered descriptor name (``"dhb"``, ``"efs"``, ``"isa"``, ``"bilts"``, ``"bilts+"``,
        ``"rrv"``, ``"dsrf"``, or any other registered name).
    progress : {"arclength", "angle", "screw"}
        Progress type used to reparameterize the trajectories.
    presmooth : int, optional
        Gaussian window [samples] applied to the 50 Hz poses before progress is computed (None:
        the reference's raw poses, or the run's ``--presmooth``).
    options : tuple of (str, value) pairs
        Fixed descriptor arguments added to every grid point (e.g. ``(("open_end", True),)``).
    name : str, optional
        Row identifier replacing ``"<method>:<progress>"`` (e.g. ``"recommended"``).
    title : str, optional
        Row label replacing the descriptor's display name.
    """

    method: str
    progress: str
    presmooth: int | None = None
    options: tuple[tuple[str, Any], ...] = ()
    name: str | None = None
    title: str | None = None

    @property
    def descriptor(self) -> type[Descriptor]:
        """The registered descriptor class."""
        return descriptor_class(self.method)

    @property
    def key(self) -> str:
        """``name`` or ``"<method>:<progress>"``."""
        return self.name or row_key(self.method, self.progress)

    @property
    def method_name(self) -> str:
        """What the JSON and CSV call the row's method: ``name`` or the descriptor name."""
        return self.name or self.method

    @property
    def display_name(self) -> str:
        """``title`` or the descriptor's display name (e.g. ``"BILTS+"``)."""
        return self.title or self.descriptor.label()

    @property
    def progress_name(self) -> str:
        """Progress type as printed in Table I (e.g. ``"screw path"``)."""
        return PROGRESS_NAMES.get(self.progress, self.progress)

    @property
    def label(self) -> str:
        """Human-readable row label, e.g. ``"BILTS+ screw path"``."""
        return f"{self.display_name} {self.progress_name}"

    @property
    def x_param(self) -> str | None:
        """Descriptor argument set by ``x`` (``"lam"``, ``"ds_scale"`` or None)."""
        return self.descriptor.trained_parameter

    @property
    def trains_L(self) -> bool:
        """Whether L is a trained parameter (False for RRV/DSRF without screw progress)."""
        return self.descriptor.trains_scale_length(self.progress)

    @property
    def x_values(self) -> tuple[float, ...]:
        """Grid values of ``x`` (one dummy ``None`` when the method has no x parameter)."""
        if self.x_param is None:
            return (None,)  # type: ignore[return-value]
        values = self.descriptor.parameter_grid(self.progress)
        if not values:
            raise ValueError(f"no grid for {self.key}")
        return values

    @property
    def L_values(self) -> tuple[float, ...]:
        """Grid values of L [m] (a single dummy when L is not trained)."""
        return self.descriptor.scale_length_grid(self.progress) or (DUMMY_L,)

    @property
    def reparameterization_uses_L(self) -> bool:
        """Whether the progress (hence the reparameterized poses) depends on L (screw path)."""
        return self.progress == "screw"

    def params(self, x: float | None, L: float) -> dict[str, Any]:
        """Descriptor constructor arguments of grid point ``(x, L)``."""
        out: dict[str, Any] = {"progress": self.progress, "L": float(L)}
        if self.x_param is not None:
            out[self.x_param] = float(x)  # type: ignore[arg-type]
        if self.presmooth is not None and "presmooth" in self.descriptor.param_names:
            out["presmooth"] = int(self.presmooth)
        out.update(self.options)
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

#: the recommended offline method: BILTS+ with screw-path progress on pre-smoothed 50 Hz poses,
#: open-end alignment and the axis prior; ds_scale and L trained by the same grid search as the
#: paper's rows
RECOMMENDED = MethodSpec(
    "bilts+",
    "screw",
    presmooth=RECOMMENDED_PRESMOOTH,
    options=(("open_end", True), ("axis_prior", RECOMMENDED_AXIS_PRIOR)),
    name="recommended",
    title="framefree (recommended)",
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
        ``"all"`` / None (the 17 rows of Table I and the recommended row), ``"paper"`` (the 17
        rows), or comma-separated items ``method:progress``; an item without ``:progress``
        selects every Table I row of that method; ``recommended`` selects :data:`RECOMMENDED`.
    available : sequence of str, optional
        Registered descriptor names; rows of other descriptors raise (or, for ``"all"``, are
        dropped). Default: no check.

    Returns
    -------
    list of MethodSpec
        In the order given (``"all"``: Table I order, then the recommended row), without
        duplicates.

    Raises
    ------
    ValueError
        For an unknown progress type, or a descriptor that is not registered.
    """
    avail = None if available is None else {a.lower() for a in available}
    if text is None or (isinstance(text, str) and text.strip().lower() in ("", "all", "paper")):
        rows = list(TABLE1_ROWS)
        if not (isinstance(text, str) and text.strip().lower() == "paper"):
            rows.append(RECOMMENDED)
        return rows if avail is None else [r for r in rows if r.method in avail]
    items = text.split(",") if isinstance(text, str) else list(text)
    out: list[MethodSpec] = []
    for raw in items:
        item = raw.strip().lower()
        if not item:
            continue
        if item == RECOMMENDED.name:
            if RECOMMENDED not in out:
                out.append(RECOMMENDED)
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
