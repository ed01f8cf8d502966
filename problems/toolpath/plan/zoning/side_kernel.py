"""Compiled form of ``profile.SideTable.width``: the bisection on the side-width table,
point by point in one pass.

``SideTable.width_numpy`` runs 30 bisection rounds over the whole array, each a trilinear
``scipy.ndimage.map_coordinates`` lookup (plus a second and third lookup for the points
between the two innermost beta nodes) and four temporaries: most of an iso-scallop plan's
width computation. Here every point does its own rounds with the same formulas: the same
node coordinates, the trilinear weights of ``map_coordinates(order=1, mode="nearest")``
(coordinates clamped to the table; the corners summed in scipy's order, last axis
fastest), the same narrower-of-two rule and the same bisection test. Widths agree with the
reference to round-off (the interpolation's sums may associate differently: a bisection
step can then go the other way only at an exact tie, 4 h_c / 2^30 apart), tested.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["side_widths"]


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _coord(c, n):
    """(i0, i1, weight of i1) of one linear coordinate, clamped like mode="nearest"."""
    if c <= 0.0:
        return 0, 0, 0.0
    if c >= n - 1:
        return n - 1, n - 1, 0.0
    i0 = int(math.floor(c))
    return i0, i0 + 1, c - i0


@njit(cache=True, nogil=True, error_model="numpy")
def _lookup(table, k, i, j):
    n_h, n_t, n_b = table.shape
    a0, a1, wa = _coord(k, n_h)
    b0, b1, wb = _coord(i, n_t)
    c0, c1, wc = _coord(j, n_b)
    out = 0.0
    for ia in range(2):
        xa = a0 if ia == 0 else a1
        fa = 1.0 - wa if ia == 0 else wa
        for ib in range(2):
            xb = b0 if ib == 0 else b1
            fb = 1.0 - wb if ib == 0 else wb
            for ic in range(2):
                xc = c0 if ic == 0 else c1
                fc = 1.0 - wc if ic == 0 else wc
                out += table[xa, xb, xc] * fa * fb * fc
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def _at(table, h_top, n_b2, beta_0, hh, t_z, beta):
    n_h, n_t = table.shape[0], table.shape[1]
    k = math.sqrt(min(max(hh / h_top, 0.0), 1.0)) * (n_h - 1)
    i = math.sqrt(min(abs(t_z), 1.0)) * (n_t - 1)

    def col(b):
        s = (1.0 if b > 0 else (-1.0 if b < 0 else 0.0)) * math.sqrt(
            min(abs(b) / (0.5 * math.pi), 1.0))
        return (s + 1.0) * 0.5 * (n_b2 - 1)

    if abs(beta) < beta_0:
        return min(_lookup(table, k, i, col(beta_0)), _lookup(table, k, i, col(-beta_0)))
    return _lookup(table, k, i, col(beta))


@njit(cache=True, nogil=True, error_model="numpy")
def side_widths(table, h, h_top, beta_0, t_z, beta, kappa, iterations):
    """``SideTable.width`` of (t_z, beta, kappa) (flat arrays of one length)."""
    n = t_z.shape[0]
    n_b2 = table.shape[2]
    out = np.empty(n)
    for p in range(n):
        lo, hi = 0.0, h_top
        tz, bt, kp = t_z[p], beta[p], kappa[p]
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            x = _at(table, h_top, n_b2, beta_0, mid, tz, bt)
            if mid - 0.5 * kp * x * x < h:
                lo = mid
            else:
                hi = mid
        x = _at(table, h_top, n_b2, beta_0, 0.5 * (lo + hi), tz, bt)
        out[p] = x / max(1.0 - kp * h, 1e-3)
    return out
