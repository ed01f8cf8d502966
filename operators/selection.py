"""Parent selection: indices into the population, drawn with an explicit generator."""

from __future__ import annotations

import numpy as np


def roulette(fitness: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """Fitness-proportionate (roulette-wheel) selection of ``n`` indices, with replacement.

    ``fitness: (N,)`` non-negative, larger is better; all zero means uniform choice.
    """
    fitness = np.asarray(fitness, dtype=float)
    cum = np.cumsum(fitness)
    if not cum[-1] > 0:
        return rng.integers(0, fitness.size, n)
    idx = np.searchsorted(cum, rng.random(n) * cum[-1], side="right")
    return np.minimum(idx, fitness.size - 1)


def tournament(fitness: np.ndarray, n: int, rng: np.random.Generator, size: int = 2) -> np.ndarray:
    """``n`` winners of tournaments of ``size`` contestants drawn with replacement (larger wins)."""
    fitness = np.asarray(fitness, dtype=float)
    contestants = rng.integers(0, fitness.size, (n, size))
    winners = np.argmax(fitness[contestants], axis=1)
    return contestants[np.arange(n), winners]
