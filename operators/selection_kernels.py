"""The compiled form of :func:`evoplan.operators.selection.roulette`'s wheel (numba)."""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def wheel_indices(cum, u):
    """``min(searchsorted(cum, u * cum[-1], side="right"), N - 1)`` for ``cum: (N,)``
    non-decreasing and ``u: (n,)`` in ``[0, 1)``: the same indices, found through a guide
    table (Chen & Asau's method) instead of a binary search per draw.

    Bucket ``k`` of the ``N`` buckets starts at the first index whose ``cum`` exceeds
    ``k / N`` of the total; a draw starts at its bucket's index and steps to the first ``cum``
    above it. The steps go both ways, so the answer is the count of ``cum`` at or below the
    draw whatever rounding the bucket carries: a few steps a draw, in order, against the
    ``log2 N`` unpredictable branches of a binary search."""
    N = cum.size
    total = cum[N - 1]
    guide = np.empty(N, dtype=np.int64)
    i = 0
    for k in range(N):
        threshold = total * (k / N)
        while i < N and cum[i] <= threshold:
            i += 1
        guide[k] = i
    out = np.empty(u.size, dtype=np.int64)
    for j in range(u.size):
        q = u[j] * total
        x = u[j] * N
        k = max(int(x), 0) if x < N else N - 1  # (a NaN draw: the last bucket, as numpy sorts NaN)
        i = guide[k]
        while i > 0 and cum[i - 1] > q:
            i -= 1
        while i < N and cum[i] <= q:
            i += 1
        out[j] = min(i, N - 1)
    return out
