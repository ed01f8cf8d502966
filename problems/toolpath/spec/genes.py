"""A run file's ``ranges`` and ``fixed``: the genes' values, checked where they do not depend
on the configuration.

``ranges: {gene: [lo, hi]}`` and ``fixed: {gene: value}`` (the genes are listed in
``genes.py``). What a value may be is a property of the gene alone, checked here: the
step-over is a share of the tool diameter in (0, 100] %, the step a length > 0 mm, lead and
tilt angles in (-90, 90) degrees; a range is two finite numbers lo < hi (a one-point range
``[v, v]`` means ``fixed: {gene: v}``); the tool is a choice over the database, never a range;
a gene is given a range or a fixed value, not both. What depends on the configuration stays
with the gene space the problem builds (``genes.py``): which genes the planner reads, the
zoning method's gene and its range, the tool ids of the database, the strategies to choose
from; those entries are kept as given.
"""

from __future__ import annotations

import math
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from ..checks import interval, number
from ..plan.zoning.methods import REGISTRY
from .errors import HERE

__all__ = ["GeneRanges", "FixedGenes", "PLANNED", "DEFAULT_RANGES", "check_value", "both_given"]

#: the genes whose values the specification checks (the planner's continuous genes)
PLANNED = ("stepover", "lead", "tilt", "step")

#: a free gene's range when ``ranges`` gives none
DEFAULT_RANGES = {"stepover": (20.0, 45.0), "lead": (0.0, 5.0), "tilt": (0.0, 2.0),
                  "step": (5.0, 10.0)}

#: what each of them is (the docs and the schema)
_MEANING = {"stepover": "% of the tool diameter, in (0, 100]",
            "lead": "degrees about the cross-feed axis, in (-90, 90)",
            "tilt": "degrees about the feed, in (-90, 90)",
            "step": "maximum distance between CC points, mm (> 0)"}


def _default(name: str) -> str:
    lo, hi = DEFAULT_RANGES[name]
    return f"{_MEANING[name]}; default [{lo:g}, {hi:g}]"


def check_value(name: str, x: float, key: str) -> float:
    """A value's physical validity (any range end or fixed value of the gene must pass)."""
    if name in ("stepover", "step") and not x > 0:
        raise ValueError(f"{key}: must be > 0, got {x:g}")
    if name == "stepover" and x > 100:
        raise ValueError(f"{key}: a step-over above 100 % of D leaves material uncut, got {x:g}")
    if name in ("lead", "tilt") and not -90 < x < 90:
        raise ValueError(f"{key}: angles must lie in (-90, 90) degrees, got {x:g}")
    return x


def _range_of(name: str):
    def check(value) -> tuple[float, float]:
        try:
            lo, hi = (float(x) for x in value)
        except (TypeError, ValueError):
            lo = hi = None
        if not (lo is not None and lo == hi and math.isfinite(lo)):  # [v, v]: a fixed value
            lo, hi = interval(value, HERE)
        return check_value(name, lo, HERE), check_value(name, hi, HERE)
    check.__doc__ = f"{name}'s range [lo, hi]"
    return check


def _fixed_of(name: str):
    def check(value) -> float:
        return check_value(name, number(value, HERE), HERE)
    check.__doc__ = f"{name}'s fixed value"
    return check


def _ranged(name: str):
    """The type of a checked gene's range: (lo, hi)."""
    return Annotated[tuple[float, float] | None, BeforeValidator(_range_of(name)),
                     Field(description=_default(name))]


def _valued(name: str):
    """The type of a checked gene's fixed value."""
    return Annotated[float | None, BeforeValidator(_fixed_of(name)),
                     Field(description=_MEANING[name])]


def _zone_genes() -> tuple[str, ...]:
    return tuple(m.gene.name for m in REGISTRY.values() if m.gene is not None)


class _Genes(BaseModel):
    """Gene name -> value; the genes of :data:`PLANNED` typed, any other kept as given."""

    model_config = ConfigDict(extra="allow", frozen=True)

    def given(self) -> dict[str, Any]:
        """The genes the run file gives, by name (the checked ones as numbers)."""
        return self.model_dump(exclude_unset=True)


class GeneRanges(_Genes):
    """``ranges``: a free gene's range [lo, hi] (the module doc)."""

    stepover: _ranged("stepover") = None
    lead: _ranged("lead") = None
    tilt: _ranged("tilt") = None
    step: _ranged("step") = None

    @model_validator(mode="before")
    @classmethod
    def _entries(cls, data):
        for name, value in (data.items() if isinstance(data, dict) else ()):
            if name == "tool":
                raise ValueError(f"{HERE}.tool: the tool is a choice over the tool database (list "
                                 f"fewer tools, or fix one with fixed: {{tool: ID}})")
            if (name in PLANNED or name in _zone_genes()) and isinstance(value, (int, float)) \
                    and not isinstance(value, bool):
                raise ValueError(f"{HERE}.{name}: expected [lo, hi], got {value!r} (to fix a "
                                 f"gene, write fixed: {{{name}: {value!r}}})")
        return data


class FixedGenes(_Genes):
    """``fixed``: a gene's value, not a variable (the tool by its id; the module doc)."""

    stepover: _valued("stepover") = None
    lead: _valued("lead") = None
    tilt: _valued("tilt") = None
    step: _valued("step") = None


def both_given(ranges: GeneRanges | None, fixed: FixedGenes | None) -> None:
    """Refuse a gene given both a range and a fixed value (one line naming the range)."""
    if ranges is None or fixed is None:
        return
    fixed_names = fixed.given()
    for name in ranges.given():
        if name in fixed_names:
            raise ValueError(f"ranges.{name}: {name} is fixed (fixed.{name}); give a range or a "
                             f"fixed value, not both")
