"""The published numbers: Table I of Verduyn, Vochten & De Schutter (arXiv 2503.11352).

Recognition ratios in percent on the HPM test set, copied as printed
(docs/algorithms/table1-protocol.md). Keys of each row: the seven printed columns (``original_2``,
``slower``, ``faster``, ``first_half``, the pooled ``body_frame`` and ``world_frame`` columns,
``combination``) plus ``mean`` and ``std``.

A few printed values are not multiples of 1/21 or 1/63 (RRV arclength Δ{w} 85.4, RRV angle
combination 80.9, RRV screw Δ{w} 69.9); they are kept as printed and are not exact targets.
"""

from __future__ import annotations

__all__ = ["PAPER_COLUMNS", "PAPER_TABLE1", "paper_row"]

#: printed columns of Table I, in order
PAPER_COLUMNS: tuple[str, ...] = (
    "original_2",
    "slower",
    "faster",
    "first_half",
    "body_frame",
    "world_frame",
    "combination",
)

_ROWS: dict[str, tuple[float, ...]] = {
    # key: (original 2, slower, faster, half, Δ{b}, Δ{w}, comb., mean, std)
    "dhb:arclength": (85.7, 85.7, 100, 57.1, 84.1, 85.7, 47.6, 80.5, 14.8),
    "dhb:angle": (66.7, 66.7, 95.2, 42.9, 60.3, 63.5, 57.1, 63.6, 13.0),
    "dhb:screw": (85.7, 71.4, 100, 61.9, 88.9, 84.1, 71.4, 82.7, 10.7),
    "efs:arclength": (85.7, 71.4, 95.2, 42.9, 74.6, 85.7, 47.6, 74.9, 16.5),
    "efs:angle": (71.4, 76.2, 95.2, 66.7, 66.7, 65.1, 71.4, 70.6, 9.2),
    "efs:screw": (100, 90.5, 100, 66.7, 95.2, 98.4, 38.1, 88.7, 19.3),
    "isa:angle": (71.4, 61.9, 85.7, 57.1, 71.4, 74.6, 61.9, 70.5, 7.9),
    "isa:screw": (85.7, 81.0, 100, 95.2, 85.7, 85.7, 81.0, 87.0, 5.7),
    "bilts:angle": (76.2, 52.4, 90.5, 66.7, 74.6, 74.6, 90.5, 74.9, 10.7),
    "bilts:screw": (95.2, 85.7, 100, 100, 98.4, 98.4, 100, 97.4, 4.5),
    "bilts+:screw": (100, 100, 100, 100, 100, 100, 100, 100, 0.0),
    "rrv:arclength": (81.0, 90.5, 95.2, 61.9, 82.3, 85.4, 42.9, 79.5, 14.9),
    "rrv:angle": (66.7, 61.9, 61.9, 57.1, 69.8, 66.7, 80.9, 67.1, 8.4),
    "rrv:screw": (66.7, 47.6, 71.4, 33.3, 61.9, 69.9, 33.3, 58.9, 15.4),
    "dsrf:arclength": (100, 100, 100, 57.1, 100, 100, 28.6, 89.6, 24.0),
    "dsrf:angle": (100, 90.5, 100, 71.4, 100, 100, 47.6, 91.8, 17.1),
    "dsrf:screw": (100, 100, 100, 38.1, 96.8, 100, 38.1, 87.9, 24.8),
}

#: Table I as ``{"<method>:<progress>": {column: percent, ..., "mean": ..., "std": ...}}``
PAPER_TABLE1: dict[str, dict[str, float]] = {
    key: {
        **{col: float(v) for col, v in zip(PAPER_COLUMNS, vals[:7], strict=True)},
        "mean": float(vals[7]),
        "std": float(vals[8]),
    }
    for key, vals in _ROWS.items()
}


def paper_row(key: str) -> dict[str, float] | None:
    """The paper's numbers for row ``"<method>:<progress>"``, or None if Table I has no such row."""
    return PAPER_TABLE1.get(key)
