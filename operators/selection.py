"""Parent selection: indices into the population, drawn with an explicit generator."""

from __future__ import annotations

import numpy as np

from ..compiled import use_compiled


def roulette(fitness: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """Fitness-proportionate (roulette-wheel) selection of ``n`` indices, with replacement.

    ``fitness: (N,)`` non-negative, larger is better; all zero means uniform choice. The
    compiled wheel (:mod:`.selection_kernels`, once it pays: :func:`evoplan.compiled.use_compiled`)
    gives the same indices as the binary search.
    """
    fitness = np.asarray(fitness, dtype=float)
    cum = np.cumsum(fitness)
    if not cum[-1] > 0:
        return rng.integers(0, fitness.size, n)
    u = rng.random(n)
    if use_compiled():
        from .selection_kernels import wheel_indices  # numba: imported only when it pays

        return wheel_indices(cum, u)
    idx = np.searchsorted(cum, u * cum[-1], side="right")
    return np.minimum(idx, fitness.size - 1)


def tournament(fitness: np.ndarray, n: int, rng: np.random.Generator, size: int = 2) -> np.ndarray:
    """``n`` winners of tournaments of ``size`` contestants drawn with replacement (larger wins)."""
    fitness = np.asarray(fitness, dtype=float)
    contestants = rng.integers(0, fitness.size, (n, size))
    winners = np.argmax(fitness[contestants], axis=1)
    return contestants[np.arange(n), winners]
