"""Seeds of the drop-cutter (``drop.py``, candidates A): the best grid points under the tool.

For a vertical cutter with its axis at XY c, every grid point q of the surface within the
radius R scores f = z_q - h(rho_q), h the cutter's lower profile (``profile_kernel``): the
tip height that point alone would ask for. The seeds of a query are the best point overall
and the best of each quadrant about c (dx >= 0, dy >= 0, as x + 2 y) when its score is
within ``slack`` of the best; ties go to the lowest grid index.

The grid points are bucketed once per grid into square XY cells (:class:`Buckets`), so a
query reads only the cells its disk overlaps: one compiled pass over the queries, linear in
the points under each tool.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from .profile_kernel import piece_height

__all__ = ["Buckets", "bucket_points", "drop_seeds"]


@dataclass(frozen=True)
class Buckets:
    """Points sorted into ``shape`` (ny, nx) square cells of side ``cell`` from ``origin``:
    the points of cell k (row-major) are ``order[ptr[k]:ptr[k + 1]]``."""

    origin: tuple[float, float]
    cell: float
    shape: tuple[int, int]
    ptr: np.ndarray
    order: np.ndarray


def bucket_points(xy: np.ndarray, cell: float) -> Buckets:
    """The points ``xy`` (N, 2) bucketed into cells of side ``cell`` mm."""
    xy = np.asarray(xy, float).reshape(-1, 2)
    lo = xy.min(axis=0) if len(xy) else np.zeros(2)
    hi = xy.max(axis=0) if len(xy) else np.zeros(2)
    nx, ny = (int(np.floor((hi[k] - lo[k]) / cell)) + 1 for k in range(2))
    ix = np.minimum(((xy[:, 0] - lo[0]) / cell).astype(np.int64), nx - 1)
    iy = np.minimum(((xy[:, 1] - lo[1]) / cell).astype(np.int64), ny - 1)
    key = iy * nx + ix
    order = np.argsort(key, kind="stable")
    ptr = np.zeros(nx * ny + 1, np.int64)
    np.cumsum(np.bincount(key, minlength=nx * ny), out=ptr[1:])
    return Buckets((float(lo[0]), float(lo[1])), float(cell), (ny, nx), ptr, order)


@njit(cache=True, nogil=True, error_model="numpy")
def _seeds(qxy, gxy, gz, x0, y0, cell, ny, nx, ptr, order, prm, slack):
    k = qxy.shape[0]
    out = np.full((k, 5), -1, np.int64)
    big = prm[0]
    big2 = big * big
    bf = np.empty(5)
    bi = np.empty(5, np.int64)
    for q in range(k):
        cx, cy = qxy[q, 0], qxy[q, 1]
        kx0 = max(int(math.floor((cx - big - x0) / cell)), 0)
        kx1 = min(int(math.floor((cx + big - x0) / cell)), nx - 1)
        ky0 = max(int(math.floor((cy - big - y0) / cell)), 0)
        ky1 = min(int(math.floor((cy + big - y0) / cell)), ny - 1)
        bf[:] = -np.inf
        bi[:] = -1
        for ky in range(ky0, ky1 + 1):
            for kx in range(kx0, kx1 + 1):
                b = ky * nx + kx
                for n in range(ptr[b], ptr[b + 1]):
                    p = order[n]
                    dx, dy = gxy[p, 0] - cx, gxy[p, 1] - cy
                    dd = dx * dx + dy * dy
                    if dd > big2:
                        continue
                    f = gz[p] - piece_height(math.sqrt(dd), prm)
                    quad = 1 + (1 if dx >= 0.0 else 0) + (2 if dy >= 0.0 else 0)
                    for j in (0, quad):
                        if bi[j] < 0 or f > bf[j] or (f == bf[j] and p < bi[j]):
                            bf[j], bi[j] = f, p
        if bi[0] < 0:
            continue
        out[q, 0] = bi[0]
        for j in range(1, 5):
            if bi[j] >= 0 and bf[j] >= bf[0] - slack:
                out[q, j] = bi[j]
    return out


def drop_seeds(cutter, grid, xy: np.ndarray) -> np.ndarray:
    """Grid indices (k, 5) of the seeds of each query XY (k, 2) (module doc; -1: none),
    with ``slack`` a tenth of the cutter's radius."""
    b = grid.buckets
    return _seeds(np.ascontiguousarray(xy, dtype=float), grid.xy, grid.z, b.origin[0],
                  b.origin[1], b.cell, b.shape[0], b.shape[1], b.ptr, b.order,
                  cutter.kernel_params(), 0.1 * cutter.radius)
