"""Fountas Eq. 9: weighted sum of normalized criteria, with FIXED normalization bounds.

ObjFcn_ws = w_1 Crt_1 + ... + w_n Crt_n,  sum w_i = 1, 0 <= w_i <= 1   (Eq. 9)

Each criterion is normalized as (value - lo) / (hi - lo) with the paper's "minimum and
maximum values of the single criteria". Here the bounds are computed ONCE, when the problem
is built, from a fixed design over the free genes (``GeneSpace.design`` in ``genes.py``):
every tool at the corners and the centre of the other free ranges, plus a seeded uniform
sample; they never drift with the population. Values outside the design's range fall
outside [0, 1] (not clipped, so the ordering is kept). Bounds can also be given explicitly.

Default weights (Fountas' two criteria, equal importance): machining_error 0.5,
cc_count 0.5. Every criterion is minimized.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import BeforeValidator, TypeAdapter, ValidationError

from ..checks import interval, number
from .table import RENAMED, check_name

__all__ = ["DEFAULT_WEIGHTS", "Weights", "Objectives", "Bounds", "parse_weights",
           "parse_objectives", "parse_bounds", "bounds_from_sample", "normalize", "weighted_sum"]

DEFAULT_WEIGHTS = {"machining_error": 0.5, "cc_count": 0.5}


def _criterion(name, key: str, seen) -> str:
    """A weightable criterion's name for the entry ``key``; refuses one given twice."""
    crit = check_name(name, key, weightable=True)
    if crit in seen:
        raise ValueError(f"{key}: {crit} is given twice")
    return crit


def _weights(weights, key: str) -> dict[str, float]:
    """Weights {criterion: w}: weightable names of the criteria table, each in [0, 1], sum 1
    within 1e-9."""
    if not isinstance(weights, dict) or not weights:
        raise ValueError(f"{key}: expected a non-empty mapping criterion -> weight, got {weights!r}")
    out = {}
    for name, w in weights.items():
        crit = _criterion(name, f"{key}.{name}", out)
        x = number(w, f"{key}.{name}")
        if not 0.0 <= x <= 1.0:
            raise ValueError(f"{key}.{name}: must be in [0, 1], got {w!r}")
        out[crit] = x
    total = sum(out.values())
    if abs(total - 1.0) > 1e-9:
        raise ValueError(f"{key}: must sum to 1 (within 1e-9), got {total:.12g}")
    return out


def _objectives(objectives, key: str) -> list[str]:
    """A list of weightable criteria (no repeats) for a multi-objective F."""
    if not isinstance(objectives, (list, tuple)) or not objectives:
        raise ValueError(f"{key}: expected a list of criteria, got {objectives!r}")
    out: list[str] = []
    for i, name in enumerate(objectives):
        out.append(_criterion(name, f"{key}[{i}]", out))
    return out


def _bounds(bounds, key: str) -> dict[str, tuple[float, float]]:
    """Bounds {criterion: [lo, hi]} with lo < hi (which criteria may have them depends on the
    weights: :func:`parse_bounds`)."""
    if not isinstance(bounds, dict):
        raise ValueError(f"{key}: expected a mapping criterion -> [lo, hi], got {bounds!r}")
    out = {}
    for name, b in bounds.items():
        if isinstance(name, str) and name in RENAMED:
            raise ValueError(f"{key}.{name}: renamed {RENAMED[name]}")
        out[name] = interval(b, f"{key}.{name}")
    return out


def _here(check):
    """``check(value, HERE)``: the key path is filled in where the type sits (spec/errors.py;
    imported when a value is checked, as the spec package imports this module)."""
    def validate(value):
        from ..spec.errors import HERE

        return check(value, HERE)
    validate.__doc__ = check.__doc__
    return validate


#: criterion -> weight (Fountas Eq. 9): weightable criteria of the table, each in [0, 1], sum 1
Weights = Annotated[dict[str, float], BeforeValidator(_here(_weights))]
#: the criteria of a multi-objective F: weightable, none twice
Objectives = Annotated[list[str], BeforeValidator(_here(_objectives))]
#: criterion -> [lo, hi] normalization bounds, lo < hi
Bounds = Annotated[dict[str, tuple[float, float]], BeforeValidator(_here(_bounds))]


def _validate(kind, value, key: str):
    """``value`` validated as the type ``kind``, a one-line ValueError naming ``key``."""
    from ..spec.errors import one_line

    try:
        return TypeAdapter(kind).validate_python(value)
    except ValidationError as e:
        raise ValueError(one_line(e, key)) from None


def parse_weights(weights=None, key: str = "weights") -> dict[str, float]:
    """:data:`Weights` as a function (``None``: the default weights)."""
    return dict(DEFAULT_WEIGHTS) if weights is None else _validate(Weights, weights, key)


def parse_objectives(objectives, key: str = "objectives") -> list[str]:
    """:data:`Objectives` as a function."""
    return _validate(Objectives, objectives, key)


def check_bounded(bounds: dict, names, key: str = "normalization") -> None:
    """Bounds only for criteria among ``names`` (the weighted ones)."""
    for name in bounds:
        if name not in names:
            raise ValueError(f"{key}.{name}: not a weighted criterion ({', '.join(names)})")


def parse_bounds(bounds, names, key: str = "normalization") -> dict[str, tuple[float, float]]:
    """:data:`Bounds` as a function, for criteria among ``names`` only; ``None``: none."""
    if bounds is None:
        return {}
    out = _validate(Bounds, bounds, key)
    check_bounded(out, names, key)
    return out


def bounds_from_sample(criteria: dict, names) -> dict[str, tuple[float, float]]:
    """(min, max) of each named criterion over a sample; a constant one gets (v, v + 1)."""
    out = {}
    for name in names:
        x = np.asarray(criteria[name], float)
        lo, hi = float(np.min(x)), float(np.max(x))
        out[name] = (lo, hi) if hi > lo else (lo, lo + 1.0)
    return out


def normalize(criteria: dict, bounds: dict) -> dict[str, np.ndarray]:
    """(value - lo) / (hi - lo) for every criterion that has bounds."""
    return {k: (np.asarray(criteria[k], float) - lo) / (hi - lo) for k, (lo, hi) in bounds.items()}


def weighted_sum(criteria: dict, weights: dict, bounds: dict) -> np.ndarray:
    """Fountas Eq. 9 over normalized criteria: (n,)."""
    norm = normalize(criteria, {k: bounds[k] for k in weights})
    return sum(w * norm[k] for k, w in weights.items())
