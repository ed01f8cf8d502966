"""The design surface on the simulation grid: one ray per cell (a Z-map over XY).

A grid of square cells of side ``h`` (mm) covers the part's XY footprint. Every cell whose
centre lies over the surface gets the design point below it and the unit normal there (on
the tool side): the ray of that cell starts at the design point and climbs along the normal
(or vertically), so the entry parameter the kernel finds is the residual measured along it.

For a parametric surface the cell centres (x, y) are mapped back to (u, v): a bilinear seed
from a coarse inverse table, then Newton's method on (x(u, v), y(u, v)) = (x, y). A centre
whose Newton solution leaves the unit square, or does not converge, is off the part, and so
is one outside a trimmed footprint's loops (in a hole). The surface must be a graph over XY
(one point above each (x, y)); a fold is refused.

A polynomial surface (Fountas' part, Bezier nets) runs that per cell in one numba loop
(``design_poly.py``, about 45 ns a cell), a B-spline or NURBS surface likewise
(``design_spline.py``); any other surface in numpy batches of cells. A
surface with a ``design_cells`` method gives its cells itself: a mesh surface
(``geometry/mesh_surface.py``) puts the mesh's own triangles under the cell centres, so the
simulation measures against the mesh, not against the smooth fit the planner uses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import RegularGridInterpolator
from scipy.spatial import cKDTree

from ..geometry.crossings import inside_grid
from ..geometry.footprint import footprint_of
from ..geometry.bspline import BSplineSurface
from ..geometry.surface import Jet, PolynomialSurface, Surface, unit_normal
from .clip import clipped_fractions, footprint_polygon
from .design_poly import empty_plain, poly_cells
from .design_spline import spline_cells

__all__ = ["DesignGrid", "design_grid", "grid_bytes", "BYTES_PER_CELL"]

BYTES_PER_CELL = 8 * 6 + 1 + 8 * 2  # z, normal, residual, u, v, inside + working copies
_CHUNK = 1 << 16  # cells per batch: the jets of a batch stay in cache
_NOT_A_GRAPH = ("surface: not a graph over XY (a vertical wall or a fold): "
                "the cut simulation needs one surface point above each (x, y)")


@dataclass(frozen=True)
class DesignGrid:
    """Cell centres ``x0 + ix h``, ``y0 + iy h``; ``z`` (ny, nx) design height, ``normal``
    (ny, nx, 3) unit normal on the tool side, ``inside`` (ny, nx) cells over the part."""

    x0: float
    y0: float
    h: float
    z: np.ndarray
    normal: np.ndarray
    inside: np.ndarray
    u: np.ndarray | None = None
    v: np.ndarray | None = None
    weight: np.ndarray | None = None

    @property
    def shape(self) -> tuple[int, int]:
        return self.z.shape

    @property
    def xs(self) -> np.ndarray:
        return self.x0 + self.h * np.arange(self.z.shape[1])

    @property
    def ys(self) -> np.ndarray:
        return self.y0 + self.h * np.arange(self.z.shape[0])

    def cell_area(self) -> np.ndarray:
        """(ny, nx) surface area (mm^2) of each cell on the part, 0 off it: w h^2 / n_z, w
        the share of the cell's square on the part (``weight``, ``clip.py``: a cell that
        straddles the footprint's edge weighs only its inside part, plus the slivers of
        its neighbours off the part); without ``weight`` the whole cell."""
        nz = np.abs(self.normal[..., 2])
        w = self.inside if self.weight is None else self.weight
        return np.where(self.inside, w * self.h * self.h / np.where(nz > 1e-12, nz, 1.0), 0.0)


COARSEST_SHARE = 0.1  # the coarsest grid still puts 10 cells across the footprint's narrow side


def grid_bytes(extent_x: float, extent_y: float, h: float) -> float:
    """Memory (bytes) the simulation needs for a footprint of that size at cell size h
    (a float: a cell size near zero gives ``inf``, which any limit refuses)."""
    with np.errstate(over="ignore"):
        return float((extent_x / h + 2) * (extent_y / h + 2) * BYTES_PER_CELL)


def footprint(surface: Surface, n: int = 512) -> tuple[float, float, float, float]:
    """(xmin, xmax, ymin, ymax) of the surface, from its boundary and a coarse interior."""
    t = np.linspace(0.0, 1.0, n)
    g = np.linspace(0.0, 1.0, 33)
    gu, gv = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    u = np.concatenate([t, np.ones(n), t, np.zeros(n), gu])
    v = np.concatenate([np.zeros(n), t, np.ones(n), t, gv])
    p = surface.jet(u, v, order=0).p
    return float(p[:, 0].min()), float(p[:, 0].max()), float(p[:, 1].min()), float(p[:, 1].max())


def _newton_xy(surface: Surface, x, y, u, v, iters: int = 8):
    for _ in range(iters):
        u, v, _ = _newton_step(surface, x, y, u, v)
    return u, v


def _newton_step(surface: Surface, x, y, u, v):
    """One Newton step on (x(u, v), y(u, v)) = (x, y); also the jet at the start point and
    its XY residual."""
    j = surface.jet(u, v, order=1)
    rx, ry = j.p[:, 0] - x, j.p[:, 1] - y
    a, b, c, d = j.su[:, 0], j.sv[:, 0], j.su[:, 1], j.sv[:, 1]
    det = a * d - b * c
    det = np.where(np.abs(det) > 1e-300, det, 1e-300)
    un = np.clip(u - (d * rx - b * ry) / det, -0.05, 1.05)
    vn = np.clip(v - (a * ry - c * rx) / det, -0.05, 1.05)
    return un, vn, (j, np.hypot(rx, ry))


def _solve_xy(surface: Surface, x, y, u, v, iters: int = 4, tol: float = 1e-9):
    """(u, v, jet at (u, v), XY residual) after Newton steps from the seed (u, v); points
    whose residual is below ``tol`` mm stop early (the seed is close: two steps mostly)."""
    idx = np.arange(len(x))
    out_u, out_v = u.copy(), v.copy()
    p = np.empty((len(x), 3))
    su = np.empty((len(x), 3))
    sv = np.empty((len(x), 3))
    res = np.full(len(x), np.inf)
    for k in range(iters + 1):
        un, vn, (j, r) = _newton_step(surface, x[idx], y[idx], out_u[idx], out_v[idx])
        p[idx], su[idx], sv[idx], res[idx] = j.p, j.su, j.sv, r
        if k == iters:
            break
        go = r > tol
        idx, un, vn = idx[go], un[go], vn[go]
        out_u[idx], out_v[idx] = un, vn
        if not len(idx):
            break
    return out_u, out_v, Jet(p, su, sv), res


def _inverse_table(surface: Surface, xmin, xmax, ymin, ymax, nt: int = 161):
    """Coarse inverse table (x, y) -> (u, v) on an nt x nt regular grid over the footprint:
    the nearest of 301 x 301 samples, then 12 Newton steps. (tx, ty, tu, tv), tu (nt, nt)."""
    g = np.linspace(0.0, 1.0, 301)
    gu, gv = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    gp = surface.jet(gu, gv, order=0).p
    tx = np.linspace(xmin, xmax, nt)
    ty = np.linspace(ymin, ymax, nt)
    TX, TY = (a.ravel() for a in np.meshgrid(tx, ty, indexing="ij"))
    _, idx = cKDTree(gp[:, :2]).query(np.stack([TX, TY], axis=1))
    tu, tv = _newton_xy(surface, TX, TY, gu[idx], gv[idx], iters=12)
    return tx, ty, tu.reshape(nt, nt), tv.reshape(nt, nt)


def _numpy_cells(surface: Surface, xs, ys, table):
    """(z, normal, inside, u, v) of the cells (xs x ys), any surface: batches of numpy
    Newton steps from RegularGridInterpolator seeds."""
    tx, ty, tu, tv = table
    iu = RegularGridInterpolator((tx, ty), tu, bounds_error=False, fill_value=None)
    iv = RegularGridInterpolator((tx, ty), tv, bounds_error=False, fill_value=None)
    ny, nx = len(ys), len(xs)
    z = np.full(ny * nx, np.nan)
    normal = np.zeros((ny * nx, 3))
    inside = np.zeros(ny * nx, bool)
    U = np.full(ny * nx, np.nan)
    V = np.full(ny * nx, np.nan)
    X = np.broadcast_to(xs[None, :], (ny, nx)).ravel()
    Y = np.broadcast_to(ys[:, None], (ny, nx)).ravel()
    for a in range(0, ny * nx, _CHUNK):
        x, y = X[a:a + _CHUNK], Y[a:a + _CHUNK]
        pts = np.stack([x, y], axis=1)
        u, v, j, dist = _solve_xy(surface, x, y, iu(pts), iv(pts))
        ok = ((u >= -1e-9) & (u <= 1 + 1e-9) & (v >= -1e-9) & (v <= 1 + 1e-9) & (dist < 1e-6))
        nrm = unit_normal(j, surface.normal_sign)
        if (ok & (nrm[:, 2] <= 1e-6)).any():
            raise ValueError(_NOT_A_GRAPH)
        z[a:a + _CHUNK] = np.where(ok, j.p[:, 2], np.nan)
        normal[a:a + _CHUNK] = nrm
        inside[a:a + _CHUNK] = ok
        U[a:a + _CHUNK] = np.where(ok, u, np.nan)
        V[a:a + _CHUNK] = np.where(ok, v, np.nan)
    return (z.reshape(ny, nx), normal.reshape(ny, nx, 3), inside.reshape(ny, nx),
            U.reshape(ny, nx), V.reshape(ny, nx))


def _polynomial_cells(surface: PolynomialSurface, xs, ys, table):
    """The same as :func:`_numpy_cells` for a polynomial surface, one numba loop over the
    cells (``design_poly.py``): Horner jets, no temporary arrays, outputs on plain pages."""
    tx, ty, tu, tv = table
    ny, nx = len(ys), len(xs)
    z, inside = empty_plain((ny, nx)), empty_plain((ny, nx), bool)
    normal, U, V = empty_plain((ny, nx, 3)), empty_plain((ny, nx)), empty_plain((ny, nx))
    bad = poly_cells(np.ascontiguousarray(surface.coeffs, dtype=float),
                     float(surface.normal_sign), xs, ys, tx, ty,
                     np.ascontiguousarray(tu), np.ascontiguousarray(tv), 4, 1e-9,
                     z, normal, inside, U, V)
    if bad:
        raise ValueError(_NOT_A_GRAPH)
    return z, normal, inside, U, V


def _spline_cells(surface: BSplineSurface, xs, ys, table):
    """The same for a B-spline or NURBS surface, one numba loop over the cells
    (``design_spline.py``)."""
    tx, ty, tu, tv = table
    ny, nx = len(ys), len(xs)
    z, inside = empty_plain((ny, nx)), empty_plain((ny, nx), bool)
    normal, U, V = empty_plain((ny, nx, 3)), empty_plain((ny, nx)), empty_plain((ny, nx))
    h = surface._poles
    if h.shape[2] == 3:  # non-rational: weights 1
        h = np.concatenate([h, np.ones(h.shape[:2] + (1,))], axis=2)
    (lo_u, lo_v), (sp_u, sp_v) = surface._lo, surface._span
    bad = spline_cells(np.ascontiguousarray(h), surface.knots[0], surface.knots[1],
                       surface.degree[0], surface.degree[1], float(lo_u), float(sp_u),
                       float(lo_v), float(sp_v), float(surface.normal_sign), xs, ys, tx, ty,
                       np.ascontiguousarray(tu), np.ascontiguousarray(tv), 4, 1e-9,
                       z, normal, inside, U, V)
    if bad:
        raise ValueError(_NOT_A_GRAPH)
    return z, normal, inside, U, V


def design_grid(surface: Surface, h: float, margin: float = 0.0,
                max_bytes: float | None = None) -> DesignGrid:
    """The design surface sampled on square cells of side ``h`` mm over its footprint.

    ``margin`` widens the grid around the footprint (cells there are off the part).
    ``max_bytes``: refuse (ValueError with the estimate) a grid that would need more memory.
    A polynomial surface (Fountas' part, Bezier nets) or a spline takes a numba path, any
    other the numpy one; both give the same grid.
    """
    cells = _numpy_cells
    if isinstance(surface, PolynomialSurface):
        cells = _polynomial_cells
    elif isinstance(surface, BSplineSurface):
        cells = _spline_cells
    return _design_grid(surface, h, margin, max_bytes, cells)


def _design_grid(surface: Surface, h: float, margin: float, max_bytes: float | None,
                 cells) -> DesignGrid:
    """:func:`design_grid` with the cells computed by ``cells`` (the numpy or numba path)."""
    if not (h > 0 and np.isfinite(h)):
        raise ValueError(f"grid_mm: must be a positive number of mm, got {h!r}")
    xmin, xmax, ymin, ymax = footprint(surface)
    need = grid_bytes(xmax - xmin + 2 * margin, ymax - ymin + 2 * margin, h)
    if max_bytes is not None and need > max_bytes:
        size = f"{need / 2**30:.1f} GiB" if np.isfinite(need) else "more memory than exists"
        raise ValueError(f"grid_mm: a {h:g} mm grid over {xmax - xmin:.1f} x {ymax - ymin:.1f} mm "
                         f"needs about {size}, more than the "
                         f"{max_bytes / 2**30:.1f} GiB allowed; use a coarser grid")
    coarsest = COARSEST_SHARE * min(xmax - xmin, ymax - ymin)
    if h > coarsest:
        raise ValueError(f"grid_mm: a {h:g} mm grid is too coarse for a part of {xmax - xmin:.1f} x "
                         f"{ymax - ymin:.1f} mm (at most {coarsest:.3g} mm: {1 / COARSEST_SHARE:g} cells "
                         "across its narrow side)")
    x0, y0 = xmin - margin + 0.5 * h, ymin - margin + 0.5 * h
    nx = int(np.floor((xmax - xmin + 2 * margin) / h)) + 1
    ny = int(np.floor((ymax - ymin + 2 * margin) / h)) + 1
    xs = x0 + h * np.arange(nx)
    ys = y0 + h * np.arange(ny)
    own = getattr(surface, "design_cells", None)  # a surface with its own design (a mesh)
    if own is not None:
        z, normal, inside, U, V = own(float(x0), float(y0), float(h), nx, ny)
    else:
        table = _inverse_table(surface, xmin, xmax, ymin, ymax)
        z, normal, inside, U, V = cells(surface, xs, ys, table)
    fp = footprint_of(surface)
    if not fp.whole:  # a trimmed face: only its domain is part (no hole cell)
        inside &= inside_grid(fp.xy_loops(surface), xs, ys)
    weight, _ = clipped_fractions(footprint_polygon(surface), float(x0), float(y0), float(h),
                                  inside)
    return DesignGrid(float(x0), float(y0), float(h), z, normal, inside, U, V, weight)


def analytic_grid(fz, fgrad, bounds, h: float) -> DesignGrid:
    """A design grid from a graph z = fz(x, y) with gradient fgrad(x, y) -> (zx, zy) over
    ``bounds`` (xmin, xmax, ymin, ymax); fz returns nan off the part. For closed-form tests."""
    xmin, xmax, ymin, ymax = bounds
    xs = xmin + 0.5 * h + h * np.arange(int(np.floor((xmax - xmin) / h)))
    ys = ymin + 0.5 * h + h * np.arange(int(np.floor((ymax - ymin) / h)))
    X, Y = np.meshgrid(xs, ys)
    z = fz(X, Y)
    zx, zy = fgrad(X, Y)
    nrm = np.stack([-zx, -zy, np.ones_like(X)], axis=-1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    inside = np.isfinite(z) & np.isfinite(nrm).all(axis=-1)
    nrm[~inside] = (0.0, 0.0, 1.0)
    return DesignGrid(float(xs[0]), float(ys[0]), float(h), z, nrm, inside)
