"""Fitness scaling of Fountas Eq. 10, with the objective normalization it needs.

Eq. 10, ``Fitted_i = FitSum * exp(-ObjVal_i**2)``, is meaningful only for objective values of
order one: ``exp(-f**2)`` is 0 for every ``f`` beyond about 6 and cannot rank them. evoplan
therefore normalizes the population's objective values to ``[0, 1]`` first, then multiplies by
a ``pressure`` factor ``c`` before Eq. 10:

- ``"rank"`` (default): ``v_i = rank_i / (n - 1)``, ranks ascending as the paper ranks
  objective values. Scale-free: the selection pressure does not change as the population
  converges or with the units of the objective.
- ``"minmax"``: ``v_i = (f_i - min f) / (max f - min f)``; keeps the spacing of the values.

``fitness = FitSum * exp(-(c * v)**2)``; with ``c = 1`` the best is ``e`` times as likely to be
drawn by roulette as the worst, with ``c = 2`` ``e**4`` times. ``FitSum`` (the sum of the
objective values) is a common factor: it changes no selection probability, and is kept only so
that the numbers are those of Eq. 10. Failed evaluations (``inf``/``nan``) rank last.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np


def normalize(f: np.ndarray, method: str = "rank") -> np.ndarray:
    """Objective values ``f: (n,)`` (minimized) to ``[0, 1]``, 0 for the best; non-finite -> 1."""
    f = np.asarray(f, dtype=float)
    n = f.size
    finite = np.isfinite(f)
    all_finite = bool(finite.all())
    if n <= 1 or not finite.any():
        return np.where(finite, 0.0, 1.0)
    if method == "rank":
        ranks = np.empty(n)
        ranks[np.argsort(f if all_finite else np.where(finite, f, np.inf), kind="stable")] = np.arange(n)
        return ranks / (n - 1)
    if method == "minmax":
        lo, hi = (f.min(), f.max()) if all_finite else (f[finite].min(), f[finite].max())
        v = (f - lo) / (hi - lo) if hi > lo else np.zeros(n)
        return v if all_finite else np.where(finite, v, 1.0)
    raise ValueError(f"unknown normalization {method!r} (rank, minmax)")


def exponential_fitness(
    f: np.ndarray, method: str = "rank", pressure: float = 1.0, order: np.ndarray | None = None
) -> np.ndarray:
    """Fountas Eq. 10 on normalized objective values: ``(n,) -> (n,)`` positive, larger is fitter.

    ``order``: ``np.argsort(f, kind="stable")`` when the caller has it and every value is
    finite. With ``order`` and ranks, the factor ``exp(-v**2)`` of each rank comes from
    :func:`rank_factors` (the same numbers, computed once per population size), and nothing
    is sorted again."""
    f = np.asarray(f, dtype=float)
    if order is not None and method == "rank" and f.size > 1:
        fitsum = float(np.abs(f).sum())
        out = np.empty(f.size)
        out[order] = (fitsum if fitsum > 0 else 1.0) * rank_factors(f.size, float(pressure))
        return out
    v = normalize(f, method) * pressure
    fitsum = float(np.abs(f).sum() if order is not None else np.abs(f[np.isfinite(f)]).sum())
    return (fitsum if fitsum > 0 else 1.0) * np.exp(-(v * v))


@lru_cache(maxsize=16)
def rank_factors(n: int, pressure: float) -> np.ndarray:
    """Eq. 10's ``exp(-v**2)`` for the ranks ``0 .. n - 1``, ``v = rank / (n - 1) * pressure``
    as :func:`normalize` and :func:`exponential_fitness` compute it (read-only, memoized)."""
    v = np.arange(n, dtype=np.float64) / (n - 1) * pressure
    out = np.exp(-(v * v))
    out.setflags(write=False)
    return out
