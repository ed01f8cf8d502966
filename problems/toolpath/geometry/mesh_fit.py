"""A smooth height field fitted to a triangle mesh, and its largest deviation from the mesh.

The mesh (a checked :class:`~.mesh_io.TriangleMesh`) is sampled on a regular XY grid
(:func:`~.mesh_raster.rasterize`, ``SAMPLES`` points per knot interval each way), and a
bicubic B-spline f(x, y) with uniform clamped knots ``spacing`` mm apart is fitted to those
heights by least squares. On a full grid the tensor-product problem
min ||B_x C B_y^T - Z||_F separates into two one-dimensional ones (C = B_x^+ Z (B_y^+)^T):
along x for every row, then along y for every column of coefficients (the 1-D least-squares
operators are small dense matrices).
When grid points lie over no triangle (a footprint that is not the whole rectangle, a hole)
the fit is the least-squares fit of the points on the mesh alone, solved as one sparse
system with a small smoothness penalty that extends it across the gaps
(:func:`_least_squares`).

The default spacing is ``SPACING_EDGES`` times the mesh's median edge length in plan view:
coarse enough that the facets' kinks (the piecewise-linear mesh's curvature is all at its
edges) are not followed, fine enough for the shape the facets approximate.

The fit is then measured against the mesh at every vertex, every edge midpoint, every
triangle's centroid and every sample point: :class:`Deviation` holds the largest
|f(x, y) - mesh(x, y)|, where it is, and the root mean square.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline

from .heightfield import HeightFieldSurface
from .mesh_io import TriangleMesh, _edge_keys
from .mesh_raster import rasterize

__all__ = ["Fit", "Deviation", "fit_height_field", "deviation", "SPACING_EDGES", "SAMPLES", "MAX_INTERVALS"]

SPACING_EDGES = 3.0   # default knot spacing, in median mesh edge lengths
SAMPLES = 3           # sample points per knot interval, each way
MAX_INTERVALS = 600   # knot intervals per axis at most (a finer spacing is widened)
SMOOTHING = 1e-6      # second-difference penalty when samples lie off the mesh (relative)


@dataclass(frozen=True)
class Fit:
    """The fitted height field, its knot spacing (mm) and the samples it was fitted to:
    ``xs`` (nx,), ``ys`` (ny,), ``z`` (ny, nx) mesh heights (nan off the mesh)."""

    surface: HeightFieldSurface
    spacing: float
    xs: np.ndarray
    ys: np.ndarray
    z: np.ndarray


@dataclass(frozen=True)
class Deviation:
    """Largest |fit - mesh| (mm) at ``where`` (x, y), the RMS, and the points it was taken at."""

    max_mm: float
    where: tuple[float, float]
    rms_mm: float
    points: int


def median_edge(mesh: TriangleMesh) -> float:
    """Median plan-view (XY) length of the mesh's edges, mm."""
    e = mesh.edges()
    d = mesh.vertices[e[:, 0], :2] - mesh.vertices[e[:, 1], :2]
    return float(np.median(np.hypot(d[:, 0], d[:, 1])))


def _knots(lo: float, hi: float, intervals: int) -> np.ndarray:
    inner = np.linspace(lo, hi, intervals + 1)
    return np.concatenate([[lo] * 3, inner, [hi] * 3])


def fit_height_field(mesh: TriangleMesh, spacing: float | None = None, key: str = "surface") -> Fit:
    """The smooth height field of ``mesh`` (module docstring); ValueError (one line naming
    ``key`` and the file) when two sheets of the mesh cover one (x, y)."""
    xmin, xmax, ymin, ymax = mesh.bounds
    lx, ly = xmax - xmin, ymax - ymin
    if not (lx > 0 and ly > 0):
        raise ValueError(f"{key}: {mesh.label}: degenerate: it has no extent in plan view")
    if spacing is None:
        spacing = SPACING_EDGES * median_edge(mesh)
    spacing = max(float(spacing), max(lx, ly) / MAX_INTERVALS)
    nkx, nky = (max(int(np.ceil(s / spacing - 1e-9)), 1) for s in (lx, ly))
    g = min(lx / nkx, ly / nky) / SAMPLES
    nx, ny = int(np.floor(lx / g)) + 1, int(np.floor(ly / g)) + 1
    x0 = xmin + 0.5 * (lx - (nx - 1) * g)
    y0 = ymin + 0.5 * (ly - (ny - 1) * g)
    raster = rasterize(mesh, x0, y0, g, nx, ny)
    if raster.overlap is not None:
        x, y, z1, z2 = raster.overlap
        raise ValueError(f"{key}: {mesh.label}: not a height field over XY: two sheets at (x, y) = "
                         f"({x:.2f}, {y:.2f}), z = {z1:.2f} and {z2:.2f}")
    z = raster.z
    off = ~np.isfinite(z)
    if off.all():
        raise ValueError(f"{key}: {mesh.label}: degenerate: no sample point lies on a triangle")
    xs, ys = x0 + g * np.arange(nx), y0 + g * np.arange(ny)
    tx, ty = _knots(xmin, xmax, nkx), _knots(ymin, ymax, nky)
    coeffs = _least_squares(xs, ys, z, off, tx, ty)
    surface = HeightFieldSurface((tx, ty), coeffs, (xmin, xmax, ymin, ymax), name="mesh")
    return Fit(surface, spacing, xs, ys, raster.z)


def _least_squares(xs, ys, z, off, tx, ty):
    """Coefficients (nbx, nby) of the least-squares fit to the samples z (ny, nx) that are
    on the mesh (``~off``). With every sample on the mesh, one separable solve
    C = P_x Z^T P_y^T (P = (B^T B)^-1 B^T, B the B-spline design matrix of one axis). With
    samples off the mesh (a hole, a footprint that is not the rectangle), the normal
    equations of the samples on the mesh alone, A^T A c = A^T z with A = B_y (x) B_x
    restricted to them, plus a small penalty ``SMOOTHING`` x mean(diag A^T A) on the
    coefficients' second differences, which decides the coefficients no sample reaches
    (they extend the fit linearly) and leaves a plane exact; solved banded
    (:func:`_solve_banded`)."""
    from scipy import sparse

    bx = BSpline.design_matrix(xs, tx, 3)
    by = BSpline.design_matrix(ys, ty, 3)
    if not off.any():
        bx, by = bx.toarray(), by.toarray()
        px = np.linalg.solve(bx.T @ bx, bx.T)
        py = np.linalg.solve(by.T @ by, by.T)
        return px @ z.T @ py.T
    nbx, nby = bx.shape[1], by.shape[1]
    on = ~off
    normal = sparse.csr_matrix((nbx * nby, nbx * nby))
    rhs = np.zeros(nbx * nby)
    rows = max(1, (1 << 18) // len(xs))  # sample rows per block: A stays a few MB
    by = by.tocsr()
    for r0 in range(0, len(ys), rows):  # A^T A and A^T z accumulated over blocks of sample rows
        keep = on[r0:r0 + rows].ravel()
        a = sparse.kron(by[r0:r0 + rows], bx, format="csr")[np.flatnonzero(keep)]  # cols (j, i)
        normal = normal + a.T @ a
        rhs += a.T @ z[r0:r0 + rows].ravel()[keep]
    normal = normal.tocsc()

    def second_differences(n):
        return sparse.diags([1.0, -2.0, 1.0], [0, 1, 2], shape=(max(n - 2, 1), n))

    dx, dy = second_differences(nbx), second_differences(nby)
    penalty = sparse.kron(sparse.eye(nby), dx.T @ dx) + sparse.kron(dy.T @ dy, sparse.eye(nbx))
    lam = SMOOTHING * float(normal.diagonal().mean())
    return _solve_banded(normal + lam * penalty, rhs, nbx, nby)


def _solve_banded(matrix, rhs, nbx: int, nby: int) -> np.ndarray:
    """Coefficients (nbx, nby) of the symmetric positive definite system ``matrix`` c = rhs
    (unknowns ordered (j, i): j over y outer, i over x inner), by a banded Cholesky
    (LAPACK pbsv through ``scipy.linalg.solveh_banded``) with the shorter axis inner: cubic
    B-splines couple unknowns at most 3 apart on each axis, so the band is 3 (inner + 1)."""
    from scipy import sparse
    from scipy.linalg import solveh_banded

    if nbx > nby:  # reorder to (i, j): y inner
        perm = np.arange(nbx * nby).reshape(nby, nbx).T.ravel()
        matrix, rhs, inner = matrix.tocsr()[perm][:, perm], rhs[perm], nby
    else:
        inner = nbx
    band = 3 * (inner + 1)
    upper = sparse.triu(matrix, format="coo")
    ab = np.zeros((band + 1, matrix.shape[0]))
    ab[band + upper.row - upper.col, upper.col] = upper.data
    c = solveh_banded(ab, rhs, check_finite=False)
    return c.reshape(nbx, nby) if nbx > nby else c.reshape(nby, nbx).T


def deviation(fit: Fit, mesh: TriangleMesh) -> Deviation:
    """The fit measured against the mesh (module docstring): vertices, edge midpoints,
    centroids and the sample points that lie on the mesh."""
    v, f = mesh.vertices, mesh.faces
    e = mesh.edges()
    _, first = np.unique(_edge_keys(e, len(v)), return_index=True)
    e = e[first]
    gx, gy = np.meshgrid(fit.xs, fit.ys)
    zs = fit.z
    on = np.isfinite(zs)
    pts = np.concatenate([v, 0.5 * (v[e[:, 0]] + v[e[:, 1]]), v[f].mean(axis=1),
                          np.column_stack([gx[on], gy[on], zs[on]])])
    d = np.abs(fit.surface.height(pts[:, 0], pts[:, 1]) - pts[:, 2])
    i = int(np.argmax(d))
    return Deviation(float(d[i]), (float(pts[i, 0]), float(pts[i, 1])),
                     float(np.sqrt(np.mean(d * d))), len(d))
