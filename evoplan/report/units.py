"""Units of what a report shows: the toolpath genes (``problems/toolpath/genes.py``'s table)
and the criteria (the criteria table's ``unit``), so every decision and criterion is labelled."""

from __future__ import annotations

from ..units import GENE_UNITS  # noqa: F401 - one table for the figures and the report


def criterion_unit(name: str) -> str:
    """The unit of a toolpath criterion (``F_`` prefix and objective normalized: no unit)."""
    from ..problems.toolpath.criteria.table import CRITERIA

    if name.startswith("F_") or name in ("weighted_sum", "objective"):
        return "normalized"
    try:
        return CRITERIA[name].unit
    except (KeyError, ValueError):
        return ""


def is_number(value) -> bool:
    """Only a number carries a unit: a name (a cutter's ``type``), a flag or a text has none."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def labelled(name: str, unit: str) -> str:
    return f"{name} ({unit})" if unit else name
