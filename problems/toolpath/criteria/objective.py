"""Fountas Eq. 9: weighted sum of normalized criteria, with FIXED normalization bounds.

ObjFcn_ws = w_1 Crt_1 + ... + w_n Crt_n,  sum w_i = 1, 0 <= w_i <= 1   (Eq. 9)

Each criterion is normalized as (value - lo) / (hi - lo) with the paper's "minimum and
maximum values of the single criteria". Here the bounds are computed ONCE, when the problem
is built, from a fixed design over the parameter box (:func:`normalization_design`): every
tool at the 16 corners and the centre of the four continuous ranges, plus a seeded uniform
sample; they never drift with the population. Values outside the design's range fall
outside [0, 1] (not clipped, so the ordering is kept). Bounds can also be given explicitly.

Default weights (Fountas' two criteria, equal importance): machining_error 0.5,
cc_count 0.5. Every criterion is minimized.
"""

from __future__ import annotations

import itertools

import numpy as np

from ..checks import interval, number
from .table import canonical, check_name, names

__all__ = ["DEFAULT_WEIGHTS", "OBJECTIVE_CRITERIA", "parse_weights", "parse_objectives",
           "parse_bounds", "normalization_design", "bounds_from_sample", "normalize",
           "weighted_sum"]

DEFAULT_WEIGHTS = {"machining_error": 0.5, "cc_count": 0.5}

#: criteria that may be weighted: the table's weightable ones (``criteria/table.py``)
OBJECTIVE_CRITERIA = names(weightable=True)


def _criterion(name, key: str, seen) -> str:
    """A weightable criterion's name (alias resolved) for the entry ``key``; refuses one
    given twice (an alias and its name)."""
    crit = check_name(name, key, weightable=True)
    if crit in seen:
        raise ValueError(f"{key}: {crit} is given twice")
    return crit


def parse_weights(weights=None, key: str = "weights") -> dict[str, float]:
    """Validate weights {criterion: w}: weightable names of the criteria table (old names
    such as ``total_length`` accepted), each in [0, 1], sum 1 within 1e-9."""
    if weights is None:
        return dict(DEFAULT_WEIGHTS)
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


def parse_objectives(objectives, key: str = "objectives") -> list[str]:
    """A list of weightable criteria (aliases resolved, no repeats) for a multi-objective F."""
    if isinstance(objectives, (str, dict)) or not objectives:
        raise ValueError(f"{key}: expected a list of criteria, got {objectives!r}")
    out: list[str] = []
    for i, name in enumerate(objectives):
        out.append(_criterion(name, f"{key}[{i}]", out))
    return out


def parse_bounds(bounds, names, key: str = "normalization") -> dict[str, tuple[float, float]]:
    """Explicit bounds {criterion: [lo, hi]} with lo < hi for criteria among ``names`` (the
    weighted ones; aliases resolved); names not given are left out."""
    if bounds is None:
        return {}
    if not isinstance(bounds, dict):
        raise ValueError(f"{key}: expected a mapping criterion -> [lo, hi], got {bounds!r}")
    out = {}
    for name, b in bounds.items():
        crit = canonical(name) if isinstance(name, str) else name
        if crit not in names:
            raise ValueError(f"{key}.{name}: not a weighted criterion ({', '.join(names)})")
        out[crit] = interval(b, f"{key}.{name}")
    return out


def normalization_design(n_tools: int, lo, hi, n_random: int = 64, seed: int = 0) -> np.ndarray:
    """Fixed design X (m, 5): each tool index x (corners + centre of the 4 continuous
    ranges), plus ``n_random`` seeded uniform points over the whole box."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    corners = np.array(list(itertools.product(*[(lo[i], hi[i]) for i in range(1, 5)])))
    cont = np.vstack([corners, (lo[1:] + hi[1:]) / 2])
    grid = np.vstack([np.column_stack([np.full(len(cont), t), cont]) for t in range(n_tools)])
    rng = np.random.default_rng(seed)
    rand = lo + rng.random((n_random, 5)) * (hi - lo)
    rand[:, 0] = rng.integers(0, n_tools, n_random)
    return np.vstack([grid, rand])


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
