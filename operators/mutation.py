"""Mutation of binary chromosomes ``G: (n, L) bool``; a new array is returned.

A mutation is drawn as its flips (one locus per individual, -1 for none, or a mask of the
bits that flip), then applied by :func:`flip` here or by the compiled breeding pass of
:mod:`.breeding`, which gives the same bits.
"""

from __future__ import annotations

import numpy as np


def single_point_loci(n: int, L: int, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Single-point mutation (Fountas) drawn for ``n`` individuals: with probability ``rate``
    an individual flips one random locus; ``(n,) int``, -1 where none flips."""
    hit = rng.random(n) < rate
    return np.where(hit, rng.integers(0, L, n), -1)


def per_bit_mask(n: int, L: int, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Bit-flip mutation drawn for ``(n, L)`` bits: each flips independently with probability ``rate``."""
    return rng.random((n, L)) < rate


def flip(G: np.ndarray, flips: np.ndarray) -> np.ndarray:
    """``G`` with ``flips`` applied: a mask ``(n, L)`` of bits, or one locus per row (-1: none)."""
    if flips.ndim == 2:
        return G ^ flips
    out = G.copy()
    hit = np.flatnonzero(flips >= 0)
    out[hit, flips[hit]] ^= True
    return out


def single_point(G: np.ndarray, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Single-point mutation of ``G`` (:func:`single_point_loci`)."""
    return flip(G, single_point_loci(G.shape[0], G.shape[1], rate, rng))


def per_bit(G: np.ndarray, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Bit-flip mutation of ``G`` (:func:`per_bit_mask`)."""
    return flip(G, per_bit_mask(G.shape[0], G.shape[1], rate, rng))
