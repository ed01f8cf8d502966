"""The design grid of a B-spline or NURBS surface in one numba loop over the cells.

What ``design_poly.py`` does for a polynomial surface, for a tensor-product spline: per cell
the bilinear seed from the coarse inverse table, Newton's method on (x(u, v), y(u, v)) =
(x, y) with each step clipped to [-0.05, 1.05]^2 (the surface evaluated at the parameter
clipped to [0, 1]^2, as :class:`~..geometry.bspline.BSplineSurface` does), the same on-part
rule and the unit normal ``sign * (S_u x S_v) / |S_u x S_v|``. The point and its first
derivatives come from the homogeneous poles (w P, w) (weights 1 for a B-spline) by the
basis functions of ``geometry/spline_kernel.py`` (``basis1``) and the quotient rule
S_u = (A_u - w_u S) / w (Piegl & Tiller, Eq. 4.20): no temporary array per cell.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..geometry.spline_kernel import _span, basis1
from .design_poly import _clip, bilinear, store_cell

__all__ = ["spline_cells"]


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _point(h, tu, tv, p, q, lo_u, sp_u, lo_v, sp_v, u, v, nu0, nu1, nv0, nv1, low, left,
           right, acc, out):
    """out[0:3] = S, out[3:6] = S_u, out[6:9] = S_v at (u, v) of the unit square; bu, bv
    nu0, nu1, nv0, nv1: scratch for the basis functions and their derivatives."""
    x = lo_u + min(max(u, 0.0), 1.0) * sp_u
    y = lo_v + min(max(v, 0.0), 1.0) * sp_v
    su = _span(tu, p, h.shape[0], x)
    sv = _span(tv, q, h.shape[1], y)
    basis1(tu, p, su, x, nu0, nu1, low, left, right)
    basis1(tv, q, sv, y, nv0, nv1, low, left, right)
    acc[:] = 0.0  # A (4), A_u (4), A_v (4)
    for ia in range(p + 1):
        for c in range(4):  # along v first: sum_b N_b P_ab and sum_b N'_b P_ab
            s0 = 0.0
            s1 = 0.0
            for ib in range(q + 1):
                w = h[su - p + ia, sv - q + ib, c]
                s0 += nv0[ib] * w
                s1 += nv1[ib] * w
            acc[c] += nu0[ia] * s0
            acc[4 + c] += nu1[ia] * s0
            acc[8 + c] += nu0[ia] * s1
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
    m = max(p, q) + 1
    low, left, right = np.empty(m), np.empty(m), np.empty(m)
    nu0, nu1, nv0, nv1 = np.empty(p + 1), np.empty(p + 1), np.empty(q + 1), np.empty(q + 1)
    pt, acc = np.empty(9), np.empty(12)
    bad = 0
    for c in range(cx.shape[0]):
        iy, ix = c // nx, c % nx
        x, y, u, v = cx[c], cy[c], seed_u[c], seed_v[c]
        res2 = np.inf
        for k in range(iters + 1):
            _point(h, tu, tv, p, q, lo_u, sp_u, lo_v, sp_v, u, v, nu0, nu1, nv0, nv1, low,
                   left, right, acc, pt)
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
