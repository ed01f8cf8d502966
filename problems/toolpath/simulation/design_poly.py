"""The design grid of a polynomial surface in one numba loop over the cells.

For S(u, v) = sum_ij A[i, j] u^i v^j (:class:`~..geometry.surface.PolynomialSurface`: Fountas'
part, Eq. 14, and every Bezier net, Choi's included) :func:`poly_cells` computes per cell
what ``design.py``'s numpy path computes per batch, by the same rules:

1. the seed (u, v): the bilinear interpolation of the coarse inverse table (x, y) -> (u, v),
   with scipy's ``RegularGridInterpolator`` conventions (interval ``t[i] <= x < t[i+1]``
   clipped to the end intervals, so a centre beyond the table extrapolates linearly);
2. Newton's method on (x(u, v), y(u, v)) = (x, y), each step clipped to [-0.05, 1.05]^2,
   stopping when the XY residual is below ``tol`` mm or after ``iters`` steps;
3. the cell is on the part when (u, v) lies in [0, 1]^2 (within 1e-9) and the residual is
   below 1e-6 mm; it then gets z, u and v (nan off the part), and every cell gets the unit
   normal ``sign * (S_u x S_v) / |S_u x S_v|`` at its last iterate.

S, S_u and S_v come from Horner schemes instead of the monomial basis times a matrix, and
the residual is compared squared (no hypot): the two paths agree to rounding, about 1e-13 mm
(``tests/problems/simulation/test_design_grid.py``). A cell costs about 45 ns on one core,
and no memory besides its outputs.
"""

from __future__ import annotations

import math
import mmap

import numpy as np
from numba import njit

__all__ = ["bilinear", "empty_plain", "poly_cells", "store_cell", "table_cells"]


def empty_plain(shape, dtype=float) -> np.ndarray:
    """A new array (zeros) on ordinary 4 KiB pages: an anonymous mmap, which numpy does not
    advise to transparent huge pages as it does its own large arrays. Measured on the 2-core
    VM this was written on, the 1.4 GB of outputs of Fountas' part at 0.02 mm cost the
    operating system 2.1-2.7 s of system time on fresh huge pages and 0.4 s on plain pages;
    the sweep over the grid ran equally fast on either."""
    dtype = np.dtype(dtype)
    n = int(np.prod(shape))
    size = max(n * dtype.itemsize, 1)
    private = getattr(mmap, "MAP_PRIVATE", None)  # not shared memory (POSIX; Windows: plain)
    buf = mmap.mmap(-1, size) if private is None else \
        mmap.mmap(-1, size, flags=private | mmap.MAP_ANONYMOUS)
    return np.frombuffer(buf, dtype, count=n).reshape(shape)


@njit(cache=True, nogil=True, error_model="numpy")
def _horner_xy(a, u, v):
    """(x, y, x_u, y_u, x_v, y_v) at (u, v): Horner in v inside Horner in u, each carrying
    its derivative (d = d t + b before b = b t + coefficient)."""
    px = py = ux = uy = vx = vy = 0.0
    for i in range(a.shape[0] - 1, -1, -1):
        bx = by = dx = dy = 0.0
        for j in range(a.shape[1] - 1, -1, -1):
            dx = dx * v + bx
            dy = dy * v + by
            bx = bx * v + a[i, j, 0]
            by = by * v + a[i, j, 1]
        ux = ux * u + px
        uy = uy * u + py
        px = px * u + bx
        py = py * u + by
        vx = vx * u + dx
        vy = vy * u + dy
    return px, py, ux, uy, vx, vy


@njit(cache=True, nogil=True, error_model="numpy")
def _horner_z(a, u, v):
    """(z, z_u, z_v) at (u, v), the same scheme."""
    p = su = sv = 0.0
    for i in range(a.shape[0] - 1, -1, -1):
        b = d = 0.0
        for j in range(a.shape[1] - 1, -1, -1):
            d = d * v + b
            b = b * v + a[i, j, 2]
        su = su * u + p
        p = p * u + b
        sv = sv * u + d
    return p, su, sv


@njit(cache=True, nogil=True, error_model="numpy")
def _clip(w):
    """w clipped to [-0.05, 1.05] as np.clip does it (nan stays nan)."""
    if w < -0.05:
        return -0.05
    if w > 1.05:
        return 1.05
    return w


@njit(cache=True, nogil=True, error_model="numpy")
def table_cells(t, xs):
    """Interval index and normalized distance of each xs in the ascending table t, as
    ``RegularGridInterpolator`` finds them: the largest i with t[i] <= x, clipped to
    [0, len(t) - 2], and (x - t[i]) / (t[i+1] - t[i]) (beyond the ends: extrapolation)."""
    n = t.shape[0]
    idx = np.empty(xs.shape[0], np.int64)
    w = np.empty(xs.shape[0])
    for k in range(xs.shape[0]):
        x = xs[k]
        i = np.searchsorted(t, x, side="right") - 1
        i = min(max(i, 0), n - 2)
        idx[k] = i
        w[k] = (x - t[i]) / (t[i + 1] - t[i])
    return idx, w


@njit(cache=True, nogil=True, error_model="numpy")
def _bilinear(tab, i, j, s, t):
    """Bilinear interpolation in cell (i, j) of a table at normalized distances (s, t), the
    four corners summed in RegularGridInterpolator's order."""
    w = 0.0
    w = w + tab[i, j] * (1 - s) * (1 - t)
    w = w + tab[i, j + 1] * (1 - s) * t
    w = w + tab[i + 1, j] * s * (1 - t)
    w = w + tab[i + 1, j + 1] * s * t
    return w


@njit(cache=True, nogil=True, error_model="numpy")
def bilinear(tx, ty, tab, x, y):
    """tab (len(tx), len(ty)) interpolated at the points (x[k], y[k]): what
    ``RegularGridInterpolator((tx, ty), tab, bounds_error=False, fill_value=None)`` gives
    (linear extrapolation beyond the table); the seed of :func:`poly_cells`."""
    jx, wx = table_cells(tx, x)
    jy, wy = table_cells(ty, y)
    out = np.empty(x.shape[0])
    for k in range(x.shape[0]):
        out[k] = _bilinear(tab, jx[k], jy[k], wx[k], wy[k])
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def poly_cells(a, sign, xs, ys, tx, ty, tu, tv, iters, tol, z, normal, inside, uu, vv):
    """Fill the (ny, nx) outputs z, normal (ny, nx, 3), inside, uu, vv for cell centres
    (xs[ix], ys[iy]) of the surface with power-basis coefficients ``a`` (p+1, q+1, 3), the
    normal oriented by ``sign``; ``tu``, ``tv`` (len(tx), len(ty)) the inverse table.
    Returns the number of cells on the part whose normal is not upward (n_z <= 1e-6): the
    surface is then no graph over XY."""
    tol2 = tol * tol
    jx, wx = table_cells(tx, xs)
    jy, wy = table_cells(ty, ys)
    bad = 0
    for iy in range(ys.shape[0]):
        y = ys[iy]
        j, t = jy[iy], wy[iy]
        for ix in range(xs.shape[0]):
            x = xs[ix]
            i, s = jx[ix], wx[ix]
            u = _bilinear(tu, i, j, s, t)
            v = _bilinear(tv, i, j, s, t)
            for k in range(iters + 1):
                px, py, sux, suy, svx, svy = _horner_xy(a, u, v)
                rx, ry = px - x, py - y
                res2 = rx * rx + ry * ry
                if k == iters or not res2 > tol2:
                    break
                det = sux * svy - svx * suy
                if not abs(det) > 1e-300:
                    det = 1e-300
                un = u - (svy * rx - svx * ry) / det
                vn = v - (sux * ry - suy * rx) / det
                u = _clip(un)
                v = _clip(vn)
            pz, suz, svz = _horner_z(a, u, v)
            bad += store_cell(z, normal, inside, uu, vv, iy, ix, u, v, res2, sign, pz,
                              sux, suy, suz, svx, svy, svz)
    return bad


@njit(cache=True, nogil=True, error_model="numpy")
def store_cell(z, normal, inside, uu, vv, iy, ix, u, v, res2, sign, pz, sux, suy, suz, svx,
               svy, svz):
    """Write cell (iy, ix) from its last iterate (u, v), squared XY residual res2, height pz
    and tangents S_u, S_v (rule 3 of the module docstring); 1 if it is on the part with a
    normal that is not upward, else 0."""
    ok = (u >= -1e-9) and (u <= 1 + 1e-9) and (v >= -1e-9) and (v <= 1 + 1e-9) \
        and (res2 < 1e-12)  # residual < 1e-6 mm
    nx_ = (suy * svz - suz * svy) * sign
    ny_ = (suz * svx - sux * svz) * sign
    nz_ = (sux * svy - suy * svx) * sign
    norm = math.sqrt(nx_ * nx_ + ny_ * ny_ + nz_ * nz_)
    normal[iy, ix, 0] = nx_ / norm
    normal[iy, ix, 1] = ny_ / norm
    normal[iy, ix, 2] = nz_ / norm
    inside[iy, ix] = ok
    if ok:
        z[iy, ix] = pz
        uu[iy, ix] = u
        vv[iy, ix] = v
        return 1 if nz_ / norm <= 1e-6 else 0
    z[iy, ix] = np.nan
    uu[iy, ix] = np.nan
    vv[iy, ix] = np.nan
    return 0
