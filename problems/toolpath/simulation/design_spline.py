"""The design grid of a B-spline or NURBS surface in one numba loop over the cells.

What ``design_poly.py`` does for a polynomial surface, for a tensor-product spline: per cell
the bilinear seed from the coarse inverse table, Newton's method on (x(u, v), y(u, v)) =
(x, y) with each step clipped to [-0.05, 1.05]^2 (the surface evaluated at the parameter
clipped to [0, 1]^2, as :class:`~..geometry.bspline.BSplineSurface` does), the same on-part
rule and the unit normal ``sign * (S_u x S_v) / |S_u x S_v|``. The point and its first
derivatives come from the homogeneous poles (w P, w) (weights 1 for a B-spline) by the
basis functions of ``geometry/spline_kernel.py`` and the quotient rule
S_u = (A_u - w_u S) / w (Piegl & Tiller, Eq. 4.20): no temporary array per cell.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..geometry.spline_kernel import _ders, _span
from .design_poly import _clip, bilinear, store_cell

__all__ = ["spline_cells"]


@njit(cache=True, nogil=True, error_model="numpy")
def _point(h, tu, tv, p, q, lo_u, sp_u, lo_v, sp_v, u, v, ndu_u, ndu_v, a_u, a_v, lu, ru,
           lv, rv, bu, bv, acc, out):
    """out[0:3] = S, out[3:6] = S_u, out[6:9] = S_v at (u, v) of the unit square."""
    x = lo_u + min(max(u, 0.0), 1.0) * sp_u
    y = lo_v + min(max(v, 0.0), 1.0) * sp_v
    su = _span(tu, p, h.shape[0], x)
    sv = _span(tv, q, h.shape[1], y)
    _ders(tu, p, su, x, 1, ndu_u, a_u, lu, ru, bu)
    _ders(tv, q, sv, y, 1, ndu_v, a_v, lv, rv, bv)
    acc[:] = 0.0  # A (4), A_u (4), A_v (4)
    for ia in range(p + 1):
        for ib in range(q + 1):
            n0 = bu[0, ia] * bv[0, ib]
            nu_ = bu[1, ia] * bv[0, ib]
            nv_ = bu[0, ia] * bv[1, ib]
            for c in range(4):
                w = h[su - p + ia, sv - q + ib, c]
                acc[c] += n0 * w
                acc[4 + c] += nu_ * w
                acc[8 + c] += nv_ * w
    inv = 1.0 / acc[3]
    for c in range(3):
        s = acc[c] * inv
        out[c] = s
        out[3 + c] = (acc[4 + c] - acc[7] * s) * inv * sp_u
        out[6 + c] = (acc[8 + c] - acc[11] * s) * inv * sp_v


@njit(cache=True, nogil=True, error_model="numpy")
def spline_cells(h, tu, tv, p, q, lo_u, sp_u, lo_v, sp_v, sign, xs, ys, tx, ty, tab_u, tab_v,
                 iters, tol, z, normal, inside, uu, vv):
    """Fill the (ny, nx) outputs for the cell centres (xs[ix], ys[iy]) of the spline with
    homogeneous poles ``h`` (nu, nv, 4), knots ``tu``, ``tv``, degrees p, q, knot range
    [lo, lo + sp] per direction; as ``design_poly.poly_cells`` (same rules, same return:
    the count of cells on the part whose normal is not upward)."""
    tol2 = tol * tol
    nx = xs.shape[0]
    cx = np.empty(ys.shape[0] * nx)
    cy = np.empty(ys.shape[0] * nx)
    for c in range(cx.shape[0]):
        cx[c], cy[c] = xs[c % nx], ys[c // nx]
    seed_u, seed_v = bilinear(tx, ty, tab_u, cx, cy), bilinear(tx, ty, tab_v, cx, cy)
    ndu_u, ndu_v = np.empty((p + 1, p + 1)), np.empty((q + 1, q + 1))
    a_u, a_v = np.empty((2, p + 1)), np.empty((2, q + 1))
    lu, ru, lv, rv = np.empty(p + 1), np.empty(p + 1), np.empty(q + 1), np.empty(q + 1)
    bu, bv = np.empty((2, p + 1)), np.empty((2, q + 1))
    pt, acc = np.empty(9), np.empty(12)
    bad = 0
    for c in range(cx.shape[0]):
        iy, ix = c // nx, c % nx
        x, y, u, v = cx[c], cy[c], seed_u[c], seed_v[c]
        res2 = np.inf
        for k in range(iters + 1):
            _point(h, tu, tv, p, q, lo_u, sp_u, lo_v, sp_v, u, v, ndu_u, ndu_v, a_u, a_v,
                   lu, ru, lv, rv, bu, bv, acc, pt)
            rx, ry = pt[0] - x, pt[1] - y
            res2 = rx * rx + ry * ry
            if k == iters or not res2 > tol2:
                break
            det = pt[3] * pt[7] - pt[6] * pt[4]
            if not abs(det) > 1e-300:
                det = 1e-300
            u = _clip(u - (pt[7] * rx - pt[6] * ry) / det)
            v = _clip(v - (pt[3] * ry - pt[4] * rx) / det)
        bad += store_cell(z, normal, inside, uu, vv, iy, ix, u, v, res2, sign, pt[2],
                          pt[3], pt[4], pt[5], pt[6], pt[7], pt[8])
    return bad
