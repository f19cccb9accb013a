"""Recognition metrics of the protocol (docs/algorithms/table1-protocol.md).

* recognition ratio (RR) per context = correct / number of test trials of that context, in percent;
* the pooled Δ{b} and Δ{w} columns of Table I = RR over all trials of the body-frame (world-frame)
  contexts together;
* mean ± σ = mean and **sample** standard deviation (N − 1) over the individual test contexts,
  computed from the per-context RRs **rounded to one decimal** (this reproduces the printed values).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

import numpy as np

from ..datasets.layout import MODEL_CONTEXT, REPLICA_CONTEXTS

__all__ = [
    "CONTEXT_ORDER",
    "GROUP_PATTERNS",
    "confusion_matrix",
    "context_groups",
    "mean_std",
    "order_contexts",
    "pooled_ratio",
    "ratios_by_context",
]

#: Table I's order of the HPM test contexts; others follow in sorted order
CONTEXT_ORDER: tuple[str, ...] = tuple(c for c in REPLICA_CONTEXTS if c != MODEL_CONTEXT)

#: pooled columns of Table I: column name -> context-name pattern
GROUP_PATTERNS: dict[str, re.Pattern[str]] = {
    "body_frame": re.compile(r"^body_frame(_\w+)?$"),
    "world_frame": re.compile(r"^world_frame(_\w+)?$"),
}


def order_contexts(contexts: Sequence[str]) -> list[str]:
    """Contexts in Table I order (known HPM names first, then the rest sorted)."""
    known = [c for c in CONTEXT_ORDER if c in contexts]
    rest = sorted(c for c in set(contexts) if c not in CONTEXT_ORDER)
    return known + rest


def context_groups(contexts: Sequence[str]) -> dict[str, list[str]]:
    """Pooled columns among ``contexts``: ``{"body_frame": [...], "world_frame": [...]}``."""
    out: dict[str, list[str]] = {}
    for group, pat in GROUP_PATTERNS.items():
        members = [c for c in order_contexts(contexts) if pat.match(c)]
        if members:
            out[group] = members
    return out


def _percent(correct: int, total: int) -> float:
    return float("nan") if total == 0 else 100.0 * correct / total


def ratios_by_context(
    true: Sequence[object], predicted: Sequence[object], contexts: Sequence[str]
) -> dict[str, float]:
    """Recognition ratio [%] per context.

    Parameters
    ----------
    true, predicted : sequence, shape (n,)
        True and recognized labels of each query (a prediction of None counts as wrong).
    contexts : sequence of str, shape (n,)
        Context of each query.

    Returns
    -------
    dict
        ``{context: RR in percent}`` in :func:`order_contexts` order.
    """
    t = np.asarray(true, dtype=object)
    p = np.asarray(predicted, dtype=object)
    c = np.asarray(contexts, dtype=object)
    if not (t.shape == p.shape == c.shape):
        raise ValueError(f"shapes differ: true {t.shape}, predicted {p.shape}, contexts {c.shape}")
    ok = t == p
    return {
        ctx: _percent(int(ok[c == ctx].sum()), int((c == ctx).sum()))
        for ctx in order_contexts(list(set(c)))
    }


def pooled_ratio(
    true: Sequence[object],
    predicted: Sequence[object],
    contexts: Sequence[str],
    members: Sequence[str],
) -> float:
    """Recognition ratio [%] over all queries whose context is one of ``members``."""
    t = np.asarray(true, dtype=object)
    p = np.asarray(predicted, dtype=object)
    sel = np.isin(np.asarray(contexts, dtype=object), list(members))
    return _percent(int((t[sel] == p[sel]).sum()), int(sel.sum()))


def mean_std(per_context: Sequence[float] | Mapping[str, float]) -> tuple[float, float]:
    """Mean and sample standard deviation over contexts of RRs rounded to one decimal
    (docs/algorithms/table1-protocol.md).

    Parameters
    ----------
    per_context : sequence of float or mapping
        Recognition ratios [%] of the individual test contexts (not the pooled columns).

    Returns
    -------
    mean, std : float
        In percent; ``std`` uses N − 1 normalization (0 for a single context).
    """
    vals = list(per_context.values()) if isinstance(per_context, Mapping) else list(per_context)
    r = np.round(np.asarray(vals, dtype=np.float64), 1)
    r = r[np.isfinite(r)]
    if r.size == 0:
        return float("nan"), float("nan")
    std = float(np.std(r, ddof=1)) if r.size > 1 else 0.0
    return float(np.mean(r)), std


def confusion_matrix(
    true: Sequence[object], predicted: Sequence[object], labels: Sequence[object]
) -> np.ndarray:
    """Counts (n_labels, n_labels + 1): rows = true class, columns = recognized class.

    The last column counts queries that got no class (their descriptor could not be computed).
    """
    index = {lab: i for i, lab in enumerate(labels)}
    n = len(labels)
    out = np.zeros((n, n + 1), dtype=np.int64)
    for t, p in zip(true, predicted, strict=True):
        out[index[t], index.get(p, n)] += 1
    return out
