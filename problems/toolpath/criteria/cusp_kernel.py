"""Compiled pass of ``scallop_3axis.cusp_heights``: the first h level whose width spans the
gap, point by point.

The numpy reference (``scallop_3axis.cusp_heights_numpy``) builds the (points x h levels)
widths, their secant correction and the spanning mask, then interpolates between the
first spanning level and the one below; here each point's levels are computed in order and
the search stops at the first that spans, with the same floating-point operations in the
same order, so the numbers agree bit for bit (tested). Where the section is not concave
(kappa <= 0) the search starts at the first level whose plain width reaches the gap,
found by bisection: no level below it can span.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["cusp_search"]


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _width(table, i, j, a, b, kappa, h, k):
    """The secant-corrected width of level k (``WidthTable.widths`` then
    ``profile.secant_width``)."""
    W = ((1 - a) * (1 - b) * table[i, j, k] + a * (1 - b) * table[i + 1, j, k]
         + (1 - a) * b * table[i, j + 1, k] + a * b * table[i + 1, j + 1, k])
    shrink = 1.0 - kappa * W * W / (8.0 * h[k])
    if shrink > 0:
        return W / np.sqrt(max(shrink, 1e-300))
    return np.inf


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _first_level(table, i, j, a, b, w, nh):
    """The first level whose plain width (no secant correction) reaches w, by bisection
    (nh when none does). The widths rise with the level: the table does
    (``np.maximum.accumulate``) and every rounded step of the bilinear sum is monotone in
    it, with the same weights at every level. Where kappa <= 0 the secant factor is
    1 / sqrt(>= 1), so no level below this one spans the gap: the search may start here
    and find the level the full search finds."""
    lo, hi = 0, nh
    while lo < hi:
        mid = (lo + hi) // 2
        W = ((1 - a) * (1 - b) * table[i, j, mid] + a * (1 - b) * table[i + 1, j, mid]
             + (1 - a) * b * table[i, j + 1, mid] + a * b * table[i + 1, j + 1, mid])
        if W >= w:
            hi = mid
        else:
            lo = mid + 1
    return lo


@njit(cache=True, nogil=True, error_model="numpy")
def cusp_search(table, h, i, j, a, b, kappa, w, ordered=False):
    """Cusp heights of q gaps w (q,): the table's cell (i, j) and fractions (a, b) of each,
    the section curvature kappa (q,); inf where no level spans. ``ordered``: the table holds
    no NaN (its widths then rise with the level, so the bisection of :func:`_first_level`
    may start the search)."""
    q, nh = len(w), len(h)
    out = np.empty(q)
    for p in range(q):
        k = -1
        wk = 0.0
        first = 0
        if ordered and kappa[p] <= 0.0 and a[p] == a[p] and b[p] == b[p]:
            first = _first_level(table, i[p], j[p], a[p], b[p], w[p], nh)
        for lev in range(first, nh):
            wk = _width(table, i[p], j[p], a[p], b[p], kappa[p], h, lev)
            if wk >= w[p]:
                k = lev
                break
        if k < 0:
            out[p] = np.inf
            continue
        if k == 0:
            out[p] = 0.0
            continue
        w0 = _width(table, i[p], j[p], a[p], b[p], kappa[p], h, k - 1)
        w1, x = wk, w[p]
        frac = (x * x - w0 * w0) / (w1 * w1 - w0 * w0)
        if frac < 0.0:
            frac = 0.0
        elif frac > 1.0:
            frac = 1.0
        if not np.isfinite(frac):
            frac = 1.0
        out[p] = h[k - 1] + frac * (h[k] - h[k - 1])
    return out
