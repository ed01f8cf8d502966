"""Crossover of binary chromosomes: pairs of parents ``(m, L)`` give pairs of children.

A crossover is drawn as one segment ``[lo, hi)`` per pair (the loci the two children swap;
an empty segment, ``lo = L``, for a pair that does not cross), then applied: by
:func:`swap_segments` here, or by the compiled breeding pass of :mod:`.breeding`, which
gives the same children.
"""

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


def swap_segments(A: np.ndarray, B: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pair ``i`` of ``(A, B)`` swaps its loci ``[lo[i], hi[i])``."""
    pos = np.arange(A.shape[1])
    return _swap(A, B, (pos >= lo[:, None]) & (pos < hi[:, None]))


def single_point_segments(m: int, L: int, rate: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Single-point crossover (Fountas, "single-point crossover") drawn for ``m`` pairs of
    ``L`` loci: each pair crosses with probability ``rate`` at a cut ``c`` in ``[1, L-1]``
    and its children swap their tails ``[c, L)``."""
    cut = rng.integers(1, L, m) if L > 1 else np.full(m, L)
    cross = rng.random(m) < rate
    return np.where(cross, cut, L), np.full(m, L)


def two_point_segments(m: int, L: int, rate: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Two-point crossover drawn for ``m`` pairs: the segment ``[c1, c2)``, ``0 < c1 < c2 <= L``."""
    if L < 3:
        return single_point_segments(m, L, rate, rng)
    c = np.sort(np.stack([rng.integers(1, L, m), rng.integers(1, L, m)], axis=1), axis=1)
    hi = np.where(c[:, 0] == c[:, 1], L, c[:, 1])
    cross = rng.random(m) < rate
    return np.where(cross, c[:, 0], L), hi


def single_point(
    A: np.ndarray, B: np.ndarray, rate: float, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Single-point crossover of the pairs ``(A[i], B[i])`` (:func:`single_point_segments`);
    pairs that do not cross are copied unchanged."""
    return swap_segments(A, B, *single_point_segments(A.shape[0], A.shape[1], rate, rng))


def two_point(
    A: np.ndarray, B: np.ndarray, rate: float, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Two-point crossover of the pairs ``(A[i], B[i])`` (:func:`two_point_segments`)."""
    return swap_segments(A, B, *two_point_segments(A.shape[0], A.shape[1], rate, rng))
