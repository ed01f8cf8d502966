"""Linear interpolation in many tables at once, one query per table row.

``np.interp`` takes one table. Laying many tables end to end with offsets makes one call do
them all, but adding an offset that grows with the row index rounds every query by the
batch's size: a plan's numbers then change (by ~1e-14) with the other plans of its
population, and two evaluations of the same plan on different backends differ. Here each
query is located in its own row by a vectorized bisection, then interpolated linearly:
the result depends on that row alone.
"""

from __future__ import annotations

import numpy as np

__all__ = ["interp_rows"]


def interp_rows(xp, fp, x):
    """For each query i: np.interp(x[i], xp[i], fp[i]) (xp rows ascending, clamped at the
    ends). xp, fp: (k, m) with m >= 2; x: (k,)."""
    xp, fp, x = np.asarray(xp, float), np.asarray(fp, float), np.asarray(x, float)
    k, m = xp.shape
    idx = np.arange(k)
    lo, hi = np.zeros(k, np.int64), np.full(k, m - 1, np.int64)
    while np.any(hi - lo > 1):
        mid = (lo + hi) // 2
        below = xp[idx, mid] <= x
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    a, b = xp[idx, lo], xp[idx, hi]
    gap = b - a
    w = np.clip((x - a) / np.where(gap > 0, gap, 1.0), 0.0, 1.0)
    w = np.where(gap > 0, w, (x >= b).astype(float))
    return fp[idx, lo] + w * (fp[idx, hi] - fp[idx, lo])
