"""Elitism: the fittest individuals carried over unchanged (Fountas, "Viral infection")."""

from __future__ import annotations

import numpy as np


def elite_indices(f: np.ndarray, count: int) -> np.ndarray:
    """Indices of the ``count`` lowest objective values (minimization), best first, stable on ties."""
    f = np.where(np.isnan(f), np.inf, np.asarray(f, dtype=float))
    if count <= 0:
        return np.empty(0, dtype=np.intp)
    return np.argsort(f, kind="stable")[:count]
