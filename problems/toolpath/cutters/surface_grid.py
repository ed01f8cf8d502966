"""A dense (u, v) grid of a surface with an XY KD-tree, and the inverse map XY -> (u, v).

The drop-cutter (``drop.py``) needs, for a tool at XY, the surface points within its radius
(the XY of a dense parameter grid, boundary rows included so that the patch edges are
sampled, bucketed into XY cells for the seeds and in a KD-tree for nearest points) and the
patch boundary as XY segments (where the cutter's rim crosses
an edge). Grids are cached per surface and spacing (weakly: they go with the surface). On
a trimmed face (``surface.footprint``) only the points inside its loops are kept and the
boundary segments run along the loops, holes included: a tool over a hole drops past it.

``uv_at_xy`` inverts a surface that is a graph over XY (z = f(x, y), det J != 0): Newton's
method on xy(u, v) = target, clipped to the unit square; points outside the footprint end
on the boundary with a residual and are flagged.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..geometry.footprint import footprint_of
from .drop_seeds import Buckets, bucket_points

__all__ = ["SurfaceGrid", "surface_grid", "uv_at_xy"]

_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


@dataclass(frozen=True)
class SurfaceGrid:
    """Grid points (N,): u, v, xy (N, 2), z; ``tree`` over xy; boundary segments (S,) with
    end parameters ``seg_uv`` (S, 2, 2), end XY ``seg_xy`` (S, 2, 2) and a tree over their
    midpoints; ``spacing`` the largest XY step between neighbours (mm); ``buckets`` the
    points in XY cells of four steps (the drop-cutter's seeds)."""

    u: np.ndarray
    v: np.ndarray
    xy: np.ndarray
    z: np.ndarray
    tree: cKDTree
    seg_uv: np.ndarray
    seg_xy: np.ndarray
    seg_tree: cKDTree
    seg_reach: float
    spacing: float
    buckets: Buckets


def _iso_lengths(surface) -> tuple[float, float]:
    t = np.linspace(0.0, 1.0, 33)
    uu, vv = np.meshgrid(t, t, indexing="ij")
    pts = surface.jet(uu.ravel(), vv.ravel(), order=0).p[:, :2].reshape(33, 33, 2)
    len_u = np.linalg.norm(np.diff(pts, axis=0), axis=-1).sum(axis=0).max()
    len_v = np.linalg.norm(np.diff(pts, axis=1), axis=-1).sum(axis=1).max()
    return float(len_u), float(len_v)


def surface_grid(surface, spacing: float = 0.25, max_per_axis: int = 2000) -> SurfaceGrid:
    """The (cached) grid of ``surface`` with points about ``spacing`` mm apart in XY."""
    key = round(float(spacing), 9)
    per = _CACHE.setdefault(surface, {})
    if key in per:
        return per[key]
    len_u, len_v = _iso_lengths(surface)
    nu = int(np.clip(np.ceil(len_u / spacing), 8, max_per_axis)) + 1
    nv = int(np.clip(np.ceil(len_v / spacing), 8, max_per_axis)) + 1
    uu, vv = np.meshgrid(np.linspace(0, 1, nu), np.linspace(0, 1, nv), indexing="ij")
    p = surface.jet(uu.ravel(), vv.ravel(), order=0).p
    xy = np.ascontiguousarray(p[:, :2])
    grid_xy = xy.reshape(nu, nv, 2)
    step = max(np.linalg.norm(np.diff(grid_xy, axis=0), axis=-1).max(),
               np.linalg.norm(np.diff(grid_xy, axis=1), axis=-1).max())
    uv = np.stack([uu, vv], -1)
    uu, vv, z = uu.ravel(), vv.ravel(), p[:, 2].copy()
    fp = footprint_of(surface)
    if fp.whole:
        ends_uv, ends_xy = [], []
        for sl in ((0, slice(None)), (-1, slice(None)), (slice(None), 0), (slice(None), -1)):
            e_uv, e_xy = uv[sl], grid_xy[sl]
            ends_uv.append(np.stack([e_uv[:-1], e_uv[1:]], 1))
            ends_xy.append(np.stack([e_xy[:-1], e_xy[1:]], 1))
        seg_uv, seg_xy = np.concatenate(ends_uv), np.concatenate(ends_xy)
    else:  # a trimmed face: its points inside the loops, its edges along them (holes too)
        keep = fp.contains(uu, vv)
        uu, vv, z, xy = uu[keep], vv[keep], z[keep], np.ascontiguousarray(xy[keep])
        du = 1.0 / max(nu, nv)
        loops = fp.dense(du)
        seg_uv = np.concatenate([np.stack([lp, np.roll(lp, -1, 0)], 1) for lp in loops])
        flat = seg_uv.reshape(-1, 2)
        seg_xy = surface.jet(flat[:, 0], flat[:, 1], order=0).p[:, :2].reshape(-1, 2, 2)
    half = 0.5 * np.linalg.norm(seg_xy[:, 1] - seg_xy[:, 0], axis=-1)
    grid = SurfaceGrid(uu, vv, xy, z, cKDTree(xy), seg_uv, seg_xy,
                       cKDTree(seg_xy.mean(axis=1)), float(half.max()), float(step),
                       bucket_points(xy, max(4.0 * float(step), 1e-9)))
    per[key] = grid
    return grid


def uv_at_xy(surface, xy, uv0, iterations: int = 30, tol: float = 1e-13):
    """(uv (k, 2), ok (k,)): parameters whose XY is ``xy`` (k, 2), Newton from ``uv0``.

    Iterates to a residual of ``tol`` times the coordinates' size; ok is False where the
    residual stays above 1e-7 mm: the XY lies outside the footprint (the clipped iteration
    stalls on the boundary) or the map is singular; those uv are the last iterate.
    """
    xy = np.asarray(xy, float).reshape(-1, 2)
    uv = np.clip(np.array(uv0, float).reshape(-1, 2), 0.0, 1.0)
    active = np.ones(len(uv), bool)
    res = np.full(len(uv), np.inf)
    scale = tol * max(1.0, float(np.abs(xy).max(initial=0.0)))
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if len(idx) == 0:
            break
        jet = surface.jet(uv[idx, 0], uv[idx, 1], order=1)
        r = jet.p[:, :2] - xy[idx]
        res[idx] = np.hypot(r[:, 0], r[:, 1])
        a, b = jet.su[:, :2], jet.sv[:, :2]
        det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        good = np.abs(det) > 1e-300
        det = np.where(good, det, 1.0)
        du = (b[:, 1] * r[:, 0] - b[:, 0] * r[:, 1]) / det
        dv = (-a[:, 1] * r[:, 0] + a[:, 0] * r[:, 1]) / det
        new = np.clip(uv[idx] - np.stack([du, dv], 1) * good[:, None], 0.0, 1.0)
        moved = np.abs(new - uv[idx]).max(axis=1)
        uv[idx] = new
        active[idx] = (res[idx] > scale) & (moved > 1e-15) & good
    p = surface.jet(uv[:, 0], uv[:, 1], order=0).p[:, :2]
    res = np.hypot(*(p - xy).T)
    return uv, res <= max(scale, 1e-7)
