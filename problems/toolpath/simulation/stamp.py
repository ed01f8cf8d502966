"""The sweep by stamps (the reference for the default sweep by moves, ``convex.py``).

The kernel stamps the cutter at poses a short distance apart along every feed move, keeps
for each cell the ``n_slots`` deepest poses of different stretches of path, and refines
each by golden-section search over the stretch of path between its neighbouring poses.
Dense stamps make it a reference that assumes nothing about the shape of the entry along
a move; at the default spacing it can miss a dip narrower than the stamps.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernel import INF, MISS, _golden, _pose, _ray, ray_entry


@njit(cache=True, nogil=True, error_model="numpy")
def _keep(fs, ks, iy, ix, f, k, near):
    """Offer pose k with entry f to the cell's slots: it competes with the slot of a pose
    within ``near`` poses (the same stretch of path), else with the worst slot."""
    n = fs.shape[0]
    j_near = -1
    j_worst = 0
    for j in range(n):
        if ks[j, iy, ix] >= 0 and abs(k - ks[j, iy, ix]) <= near:
            j_near = j
            break
        if fs[j, iy, ix] > fs[j_worst, iy, ix]:
            j_worst = j
    j = j_near if j_near >= 0 else j_worst
    if f < fs[j, iy, ix]:
        fs[j, iy, ix] = f
        ks[j, iy, ix] = k


@njit(cache=True, nogil=True, error_model="numpy")
def _stamp(fs, ks, x0, y0, h, pz, nrm, inside, vertical, tip, axis, pose_s, pose_lo, pose_hi,
           pose_reach, prm, near):
    """Phase 1 of :func:`sweep`: every pose on every cell within its reach (serial: a parallel
    region per pose costs more than it saves)."""
    n_slots, ny, nx = fs.shape
    for k in range(pose_s.shape[0]):
        cx, cy, cz, ax, ay, az = _pose(pose_s[k], pose_lo[k], pose_hi[k], tip, axis)
        reach = pose_reach[k]
        ix0 = max(int(math.floor((cx - reach - x0) / h)), 0)
        ix1 = min(int(math.ceil((cx + reach - x0) / h)), nx - 1)
        iy0 = max(int(math.floor((cy - reach - y0) / h)), 0)
        iy1 = min(int(math.ceil((cy + reach - y0) / h)), ny - 1)
        for iy in range(iy0, iy1 + 1):
            py = y0 + iy * h
            for ix in range(ix0, ix1 + 1):
                if not inside[iy, ix]:
                    continue
                px = x0 + ix * h
                if (px - cx) ** 2 + (py - cy) ** 2 > reach * reach:
                    continue
                # an entry above the worst slot is never kept: Newton may stop once it passes
                cap = fs[0, iy, ix]
                for j in range(1, n_slots):
                    cap = max(cap, fs[j, iy, ix])
                dx, dy, dz = _ray(iy, ix, vertical, nrm)
                f = ray_entry(px, py, pz[iy, ix], dx, dy, dz, cx, cy, cz, ax, ay, az, prm, cap)
                if f < cap:
                    _keep(fs, ks, iy, ix, f, k, near)


@njit(cache=True, nogil=True, error_model="numpy")
def _refine(res, fs, ks, x0, y0, h, pz, nrm, vertical, tip, axis, pose_s, pose_ds, pose_lo,
            pose_hi, prm, n_golden):
    """Phase 2 of :func:`sweep`: golden-section search around every kept pose. Serial, like
    the stamps: a simulation runs on one core, and a population's simulations run in
    parallel processes (numba's thread pool does not survive a fork)."""
    n_slots, ny, nx = fs.shape
    for iy in range(ny):
        py = y0 + iy * h
        for ix in range(nx):
            if ks[0, iy, ix] < 0:
                continue
            px = x0 + ix * h
            dx, dy, dz = _ray(iy, ix, vertical, nrm)
            best = res[iy, ix]
            for j in range(n_slots):
                k = ks[j, iy, ix]
                if k < 0:
                    continue
                best = min(best, fs[j, iy, ix])
                lo, hi = pose_lo[k], pose_hi[k]
                a = max(pose_s[k] - pose_ds[k], float(lo))
                b = min(pose_s[k] + pose_ds[k], float(hi))
                if b > a:
                    best = min(best, _golden(a, b, lo, hi, tip, axis, px, py, pz[iy, ix],
                                             dx, dy, dz, prm, n_golden))
            res[iy, ix] = best if best < 0.5 * MISS else INF


def sweep(res, x0, y0, h, pz, nrm, inside, vertical, tip, axis, pose_s, pose_ds, pose_lo,
          pose_hi, pose_reach, prm, n_slots, near, n_golden):
    """Lower ``res`` (ny, nx) to the deepest entry of the swept cutter; in place.

    Grid: cell (iy, ix) has its centre at (x0 + ix h, y0 + iy h), design point z ``pz``,
    unit normal ``nrm`` (ny, nx, 3); cells with ``inside`` False are skipped; ``vertical``:
    rays along +z instead of the normal. Path: ``tip``/``axis`` (m, 3) CL points. Poses
    (k of them, along the feed moves): path position ``pose_s`` (point index + fraction),
    the distance ``pose_ds`` to the neighbouring poses (in path position), the section
    ``pose_lo``/``pose_hi`` (first and last point), and the XY radius ``pose_reach`` around
    the tip inside which the pose can cut.

    1. Stamp: every pose is evaluated on every cell within its reach; each cell keeps its
       ``n_slots`` best poses from different stretches of path (more than ``near`` poses
       apart: the passes and links that meet at a cusp or an edge).
    2. Refine: around each kept pose, golden-section search over the neighbouring stretch
       [s - ds, s + ds] (``n_golden`` iterations) finds the deepest pose in between. Every
       kept pose is refined: a sharp rim or a tilted cutter moving sideways makes the entry
       a narrow V along the path, so no bound on what a stamp misses is safe.
    """
    ny, nx = res.shape
    fs = np.full((n_slots, ny, nx), INF)
    ks = np.full((n_slots, ny, nx), -1, np.int64)
    _stamp(fs, ks, x0, y0, h, pz, nrm, inside, vertical, tip, axis, pose_s, pose_lo, pose_hi,
           pose_reach, prm, near)
    _refine(res, fs, ks, x0, y0, h, pz, nrm, vertical, tip, axis, pose_s, pose_ds, pose_lo,
            pose_hi, prm, n_golden)
