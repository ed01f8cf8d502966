"""Crossover of binary chromosomes: pairs of parents ``(m, L)`` give pairs of children."""

from __future__ import annotations

import numpy as np


def _swap(A: np.ndarray, B: np.ndarray, mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The children: ``A`` with ``B``'s bits where ``mask``, and ``B`` with ``A``'s. Booleans
    swap through the bits that differ, ``D = (A ^ B) & mask``: the same children, bit for bit,
    several times faster than ``np.where`` on booleans."""
    if A.dtype == bool and B.dtype == bool:
        D = (A ^ B) & mask
        return A ^ D, B ^ D
    return np.where(mask, B, A), np.where(mask, A, B)


def single_point(
    A: np.ndarray, B: np.ndarray, rate: float, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Single-point crossover (Fountas, "single-point crossover").

    Each pair crosses with probability ``rate`` at a cut ``c`` in ``[1, L-1]``: the children
    swap their tails ``[c, L)``. Pairs that do not cross are copied unchanged.
    """
    m, L = A.shape
    cut = rng.integers(1, L, m) if L > 1 else np.full(m, L)
    cross = rng.random(m) < rate
    mask = (np.arange(L) >= cut[:, None]) & cross[:, None]
    return _swap(A, B, mask)


def two_point(
    A: np.ndarray, B: np.ndarray, rate: float, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Two-point crossover: the children swap the segment ``[c1, c2)`` with ``0 < c1 < c2 <= L``."""
    m, L = A.shape
    if L < 3:
        return single_point(A, B, rate, rng)
    c = np.sort(np.stack([rng.integers(1, L, m), rng.integers(1, L, m)], axis=1), axis=1)
    c[:, 1] = np.where(c[:, 0] == c[:, 1], L, c[:, 1])
    cross = rng.random(m) < rate
    pos = np.arange(L)
    mask = (pos >= c[:, :1]) & (pos < c[:, 1:]) & cross[:, None]
    return _swap(A, B, mask)
