"""A height-field triangle mesh sampled on a regular XY grid: the triangle over each point.

For the grid points ``(x0 + i h, y0 + j h)`` :func:`rasterize` finds the triangle whose plan
view holds the point and interpolates its height linearly (barycentric coordinates), all in
numpy: each triangle's bounding box of grid points is expanded with ``np.repeat`` into
candidate points, the candidates are tested by their barycentric coordinates, and the ones
inside are written. Triangles are processed in chunks of at most ``CHUNK`` candidates, so
memory stays bounded for fine grids. A point on an edge shared by two triangles gets the same
height from both (within rounding); a point covered by two triangles at different heights is
two sheets over one (x, y): the mesh is no height field, and its place is reported.

Points over no triangle get ``nan`` and triangle index -1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .mesh_io import TriangleMesh

__all__ = ["Raster", "rasterize", "CHUNK"]

CHUNK = 1 << 19  # candidate points per batch (about 50 MB of temporaries)
_EDGE = 1e-9      # barycentric slack: a point on an edge belongs to both triangles


@dataclass(frozen=True)
class Raster:
    """``z`` (ny, nx) heights (nan off the mesh), ``face`` (ny, nx) triangle index (-1 off it);
    ``overlap``: (x, y, z1, z2) of a point two sheets cover, or None."""

    z: np.ndarray
    face: np.ndarray
    overlap: tuple[float, float, float, float] | None


def rasterize(mesh: TriangleMesh, x0: float, y0: float, h: float, nx: int, ny: int,
              chunk: int = CHUNK) -> Raster:
    """The mesh sampled at the grid points ``(x0 + ix h, y0 + iy h)``, ix < nx, iy < ny."""
    v = mesh.vertices
    f = mesh.faces
    xa, xb, xc = (v[f[:, k], 0] for k in range(3))
    ya, yb, yc = (v[f[:, k], 1] for k in range(3))
    za, zb, zc = (v[f[:, k], 2] for k in range(3))
    det = (yb - yc) * (xa - xc) + (xc - xb) * (ya - yc)  # twice the signed plan area
    ix0 = np.clip(np.ceil((np.minimum(np.minimum(xa, xb), xc) - x0) / h - 1e-9), 0, nx).astype(np.int64)
    ix1 = np.clip(np.floor((np.maximum(np.maximum(xa, xb), xc) - x0) / h + 1e-9), -1, nx - 1).astype(np.int64)
    iy0 = np.clip(np.ceil((np.minimum(np.minimum(ya, yb), yc) - y0) / h - 1e-9), 0, ny).astype(np.int64)
    iy1 = np.clip(np.floor((np.maximum(np.maximum(ya, yb), yc) - y0) / h + 1e-9), -1, ny - 1).astype(np.int64)
    w = np.maximum(ix1 - ix0 + 1, 0)
    rows = np.where(det == 0, 0, np.maximum(iy1 - iy0 + 1, 0))
    # work pieces: a triangle's box of grid points, split into bands of rows of <= chunk points
    per = np.maximum(chunk // np.maximum(w, 1), 1)
    npieces = -(-rows // per)
    tri = np.repeat(np.arange(len(f)), npieces)
    first = np.arange(len(tri)) - np.repeat(np.cumsum(npieces) - npieces, npieces)
    band0 = iy0[tri] + first * per[tri]
    band = np.minimum(per[tri], iy1[tri] + 1 - band0)
    count = w[tri] * band
    z = np.full(ny * nx, np.nan)
    face = np.full(ny * nx, -1, np.int64)
    ztol = 1e-6 * max(float(np.abs(v[:, 2]).max()), float(np.ptp(v[:, :2], axis=0).max()), 1.0)
    overlap = None
    ends = np.cumsum(count)
    start = 0
    while start < len(tri):
        base = ends[start - 1] if start else 0
        stop = max(int(np.searchsorted(ends, base + chunk, side="right")), start + 1)
        pieces = np.arange(start, stop)
        start = stop
        n = count[pieces]
        if n.sum() == 0:
            continue
        piece = np.repeat(pieces, n)
        t = tri[piece]
        k = np.arange(len(t)) - np.repeat(np.cumsum(n) - n, n)
        ix = ix0[t] + k % w[t]
        iy = band0[piece] + k // w[t]
        del piece, k
        px = x0 + ix * h
        py = y0 + iy * h
        d = det[t]
        l1 = ((yb[t] - yc[t]) * (px - xc[t]) + (xc[t] - xb[t]) * (py - yc[t])) / d
        l2 = ((yc[t] - ya[t]) * (px - xc[t]) + (xa[t] - xc[t]) * (py - yc[t])) / d
        l3 = 1.0 - l1 - l2
        hit = (l1 >= -_EDGE) & (l2 >= -_EDGE) & (l3 >= -_EDGE)
        t, l1, l2, l3, px, py = t[hit], l1[hit], l2[hit], l3[hit], px[hit], py[hit]
        cell = iy[hit] * nx + ix[hit]
        zz = l1 * za[t] + l2 * zb[t] + l3 * zc[t]
        before = z[cell]
        z[cell] = zz
        face[cell] = t
        if overlap is None:  # two heights at one point: against earlier chunks, then within
            for other in (before, z[cell]):
                bad = np.flatnonzero(np.isfinite(other) & (np.abs(other - zz) > ztol))
                if len(bad):
                    b = bad[0]
                    overlap = (float(px[b]), float(py[b]), float(other[b]), float(zz[b]))
                    break
    return Raster(z.reshape(ny, nx), face.reshape(ny, nx), overlap)
