"""Compiled passes of the pass-plane tables (``planes.PassGeometry``): the planes' extents,
the bilinear seed of plane points and the zone-band membership of ``sections._stretches``.

Each does, point by point, exactly the floating-point operations of its numpy reference
(``PassGeometry.pass_extent_numpy``, ``PassGeometry.seed_numpy`` and
``sections._band_inside_numpy``), in the same order, so
their numbers agree bit for bit (tested); they only skip the temporaries: the band test of
a zoned evaluation built a (planes x feed samples) array per sub-plane offset, each point
seeded from the tables with ten of them.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["extent", "seed_uv", "band_inside", "zone_cells"]


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _d_cell(g, d):
    """``PassGeometry._index`` of one offset: (j0, fj)."""
    ng = len(g)
    if d != d:  # NaN sorts last (np.searchsorted)
        j = ng
    else:  # np.searchsorted(g, d, side="right"): the count of nodes <= d
        a, b = 0, ng
        while a < b:
            mid = (a + b) // 2
            if g[mid] <= d:
                a = mid + 1
            else:
                b = mid
        j = a
    j0 = min(max(j - 1, 0), ng - 2)
    fj = (d - g[j0]) / (g[j0 + 1] - g[j0])
    if fj < 0.0:
        fj = 0.0
    elif fj > 1.0:
        fj = 1.0
    return j0, fj


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _tau_cell(tau, nt):
    """The tau cell of ``PassGeometry.seed_numpy`` of one point: (t0, ft)."""
    if tau < 0.0:
        tau = 0.0
    elif tau > 1.0:
        tau = 1.0
    tf = tau * (nt - 1)
    if tf != tf:
        t0 = 0  # numpy's NaN -> int64 is the smallest int64, clipped to 0
    else:
        t0 = min(max(np.int64(np.floor(tf)), 0), nt - 2)
    return t0, tf - t0


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _bilinear(U, V, j0, fj, t0, ft):
    """``PassGeometry.seed_numpy`` of one point of table cell (j0, t0): (u, v)."""
    w00, w01 = (1 - fj) * (1 - ft), (1 - fj) * ft
    w10, w11 = fj * (1 - ft), fj * ft
    u = (U[j0, t0] * w00 + U[j0, t0 + 1] * w01 + U[j0 + 1, t0] * w10
         + U[j0 + 1, t0 + 1] * w11)
    v = (V[j0, t0] * w00 + V[j0, t0 + 1] * w01 + V[j0 + 1, t0] * w10
         + V[j0 + 1, t0 + 1] * w11)
    return u, v


@njit(cache=True, nogil=True, error_model="numpy")
def extent(g, s_lo, s_hi, d):
    """(s_lo, s_hi) of planes d (q,): linear in the offset table."""
    q = len(d)
    lo, hi = np.empty(q), np.empty(q)
    for i in range(q):
        j0, fj = _d_cell(g, d[i])
        lo[i] = s_lo[j0] * (1 - fj) + s_lo[j0 + 1] * fj
        hi[i] = s_hi[j0] * (1 - fj) + s_hi[j0 + 1] * fj
    return lo, hi


@njit(cache=True, nogil=True, error_model="numpy")
def seed_uv(g, U, V, d, tau):
    """(u, v) of plane points (d, tau), each (q,): the table's bilinear seed."""
    q, nt = len(d), U.shape[1]
    u, v = np.empty(q), np.empty(q)
    for i in range(q):
        j0, fj = _d_cell(g, d[i])
        t0, ft = _tau_cell(tau[i], nt)
        u[i], v[i] = _bilinear(U, V, j0, fj, t0, ft)
    return u, v


@njit(cache=True, nogil=True, error_model="numpy")
def band_inside(g, U, V, labels, z, s, d2, lo2, span, maybe):
    """(P, nt) whether the band of each plane holds zone z at each feed sample: s (P, nt)
    the samples' feed coordinates; per sub-plane offset o and plane i the offset d2[o, i],
    its extent's start lo2[o, i] and span[o, i]; a sample is inside when on some sub-plane
    it lies within the extent (1e-9) and its seed's mesh cell carries label z. ``maybe``
    (table cells): False where no seed of the cell can fall in a cell of zone z
    (:func:`zone_cells`), those samples are not seeded."""
    P, nt = s.shape
    n, m = labels.shape
    ntab = U.shape[1]
    inside = np.zeros((P, nt), np.bool_)
    for o in range(d2.shape[0]):
        for i in range(P):
            j0, fj = _d_cell(g, d2[o, i])
            lo, sp = lo2[o, i], span[o, i]
            for t in range(nt):
                if inside[i, t]:
                    continue  # already inside: another sub-plane cannot change it
                t2 = (s[i, t] - lo) / sp
                if not ((t2 >= -1e-9) & (t2 <= 1 + 1e-9)):
                    continue
                t0, ft = _tau_cell(t2, ntab)
                if not maybe[j0, t0] and fj == fj:
                    continue
                u, v = _bilinear(U, V, j0, fj, t0, ft)
                a = min(max(np.int64(u * n) if u == u else 0, 0), n - 1)
                b = min(max(np.int64(v * m) if v == v else 0, 0), m - 1)
                if labels[a, b] == z:
                    inside[i, t] = True
    return inside


def zone_cells(U, V, labels, z, margin: float = 1e-9) -> np.ndarray:
    """(n_d - 1, n_tau - 1) bool: whether a seed in each table cell can fall in a mesh cell
    labelled z. A seed is a convex combination of its cell's four corners (weights in
    [0, 1]), so its u lies within the corners' range (``margin`` covers the round-off of
    the weights' sum) and its mesh row within that range's rows; likewise v. False: the
    box of mesh cells holds no cell of zone z (a summed-area count)."""
    n, m = labels.shape
    corners = [(U[:-1, :-1], U[:-1, 1:], U[1:, :-1], U[1:, 1:]),
               (V[:-1, :-1], V[:-1, 1:], V[1:, :-1], V[1:, 1:])]
    box = []
    for c, size in zip(corners, (n, m)):
        lo = np.minimum(np.minimum(c[0], c[1]), np.minimum(c[2], c[3])) - margin
        hi = np.maximum(np.maximum(c[0], c[1]), np.maximum(c[2], c[3])) + margin
        box.append((np.clip(np.trunc(lo * size), 0, size - 1).astype(np.int64),
                    np.clip(np.trunc(hi * size), 0, size - 1).astype(np.int64)))
    (a0, a1), (b0, b1) = box
    sat = np.zeros((n + 1, m + 1), np.int64)
    sat[1:, 1:] = np.cumsum(np.cumsum(labels == z, axis=0), axis=1)
    count = sat[a1 + 1, b1 + 1] - sat[a0, b1 + 1] - sat[a1 + 1, b0] + sat[a0, b0]
    return count > 0
