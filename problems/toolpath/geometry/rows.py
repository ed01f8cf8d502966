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

__all__ = ["interp_rows", "ranges"]


def ranges(counts):
    """For counts (k,): (owner (sum,), position within owner (sum,)): the rows of k blocks
    laid end to end, block i holding counts[i] rows."""
    owner = np.repeat(np.arange(len(counts)), counts)
    starts = np.cumsum(counts) - counts
    return owner, np.arange(owner.size) - starts[owner]


def interp_rows(xp, fp, x, rows=None):
    """For each query i: np.interp(x[i], xp[r], fp[r]) with r = rows[i] (default i).

    xp: (k, m) tables, each ascending (m >= 2); fp: (k, m) values, or (m,) shared by every
    table; x: (q,) queries; rows: (q,) table of each query. Clamped at the table's ends.
    """
    xp, fp, x = np.asarray(xp, float), np.asarray(fp, float), np.asarray(x, float)
    m = xp.shape[1]
    r = np.arange(len(x)) if rows is None else np.asarray(rows)
    lo, hi = np.zeros(len(x), np.int64), np.full(len(x), m - 1, np.int64)
    while np.any(hi - lo > 1):
        mid = (lo + hi) // 2
        below = xp[r, mid] <= x
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    a, b = xp[r, lo], xp[r, hi]
    gap = b - a
    w = np.clip((x - a) / np.where(gap > 0, gap, 1.0), 0.0, 1.0)
    w = np.where(gap > 0, w, (x >= b).astype(float))
    f_lo, f_hi = (fp[lo], fp[hi]) if fp.ndim == 1 else (fp[r, lo], fp[r, hi])
    return f_lo + w * (f_hi - f_lo)
