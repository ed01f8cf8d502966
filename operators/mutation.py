"""Mutation of binary chromosomes ``G: (n, L) bool``; a new array is returned."""

from __future__ import annotations

import numpy as np


def single_point(G: np.ndarray, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Single-point mutation (Fountas): with probability ``rate`` an individual flips one random bit."""
    n, L = G.shape
    out = G.copy()
    hit = np.flatnonzero(rng.random(n) < rate)
    loci = rng.integers(0, L, n)[hit]
    out[hit, loci] ^= True
    return out


def per_bit(G: np.ndarray, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Bit-flip mutation: every bit flips independently with probability ``rate``."""
    return G ^ (rng.random(G.shape) < rate)
