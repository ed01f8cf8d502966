"""Numba kernels of the cut simulation: where does a ray first enter the swept cutter?

The part is a grid of rays, one per cell: from the design-surface point ``p`` along the
unit direction ``d`` (the design-surface normal, or +z). The cutter is the solid of a
flat-end, toroidal or ball-end mill of radius R and corner radius r with its shank, in the
pose (tip ``c``, unit axis ``a``). In the tool frame (w along the axis from the tip, rho
the distance to the axis) the solid is

    { rho <= R, w >= h(rho) },   h(rho) = 0 for rho <= R - r,
                                 h(rho) = r - sqrt(r^2 - (rho - R + r)^2) up to R,

which is convex. It is the union of two convex pieces that are easy to intersect with a
line: the shank cylinder {rho <= R, w >= r} (a quadratic in t) and, for r > 0, the
Minkowski sum of the disc of radius R - r at height r with a ball of radius r (all points
within r of that disc): the flat bottom and the corner torus. The distance from a point to
the disc is closed form, and along a line it is convex, so Newton's method from a point
below the cutter (w = 0) climbs monotonically to the first root (no overshoot, no
bracketing needed).

The residual of a cell is the smallest ray parameter t at which the ray enters any swept
cutter pose: t > 0 is material left above the design surface (a scallop), t < 0 a cut
below it (a gouge), +inf a ray no pose reaches.

The sweep: the machine interpolates the tip and the axis linearly between consecutive CL
points (tool-centre-point control, the axis renormalized). The kernel stamps the cutter at
poses a short distance apart along every feed move, keeps for each cell the two deepest
poses of different passes, and refines each by golden-section search over the stretch of
path between its neighbouring poses: the exact minimum over the continuous motion, not
over the stamps (a sampled sweep would leave feed-mark ridges of about step^2 / (8 r)).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

INF = np.inf
#: a ray that misses a pose scores MISS + its distance outside the cutter's radius, so that a
#: search along the path still moves towards where the pose reaches it (a flat end's sharp
#: rim is only in reach over a short stretch); any score above MISS / 2 is a miss
MISS = 1e6
_GOLD = 0.5 * (math.sqrt(5.0) - 1.0)


@njit(cache=True, nogil=True)
def ray_entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap=INF):
    """Smallest t with p + t d inside the cutter (tip c, unit axis a, radii R, r).

    A ray that misses scores ``MISS`` plus how far outside the radius it passes; a ray that
    does not climb along the axis (d . a <= 0) never enters from below: inf.
    ``cap``: the caller only needs entries below it; once the monotone Newton iterate passes
    it, that iterate (a lower bound of the entry, above the cap) is returned at once.
    """
    qx, qy, qz = px - cx, py - cy, pz - cz
    w0 = qx * ax + qy * ay + qz * az
    da = dx * ax + dy * ay + dz * az
    if da <= 1e-9:
        return INF
    ux, uy, uz = qx - w0 * ax, qy - w0 * ay, qz - w0 * az
    vx, vy, vz = dx - da * ax, dy - da * ay, dz - da * az
    A = vx * vx + vy * vy + vz * vz
    B = ux * vx + uy * vy + uz * vz
    C = ux * ux + uy * uy + uz * uz
    best = INF
    tw = (r - w0) / da
    if r > 0.0 and R - r <= 1e-12 * R:
        # ball-end: the sphere of radius r about the centre c + r a, in closed form
        ox, oy, oz = qx - r * ax, qy - r * ay, qz - r * az
        b = ox * dx + oy * dy + oz * dz
        disc = b * b - (ox * ox + oy * oy + oz * oz - r * r)
        if disc >= 0.0:
            best = -b - math.sqrt(disc)
        if best <= tw:
            return best
    elif r > 0.0:
        rp = R - r
        t = -w0 / da
        for _ in range(60):
            if t > cap:
                return t
            rho2 = A * t * t + 2.0 * B * t + C
            rho = math.sqrt(rho2) if rho2 > 0.0 else 0.0
            w = w0 + t * da
            re = rho - rp
            if re < 0.0:
                re = 0.0
            dist = math.sqrt(re * re + (w - r) * (w - r))
            g = dist - r
            if g <= 1e-10:
                best = t
                break
            drho = (A * t + B) / rho if rho > 1e-300 else 0.0
            gp = (re * drho + (w - r) * da) / dist
            if gp >= 0.0:
                break
            t -= g / gp
        if best <= tw:
            return best
    # shank: rho(t) <= R and w(t) >= r (for r = 0 the whole flat-end cutter)
    if A < 1e-14:
        if C <= R * R and tw < best:
            best = tw
        rho_min2 = C
    else:
        disc = B * B - A * (C - R * R)
        if disc >= 0.0:
            sq = math.sqrt(disc)
            t = max((-B - sq) / A, tw)
            if t <= (-B + sq) / A and t < best:
                best = t
        rho_min2 = C - B * B / A
    if best < INF:
        return best
    return MISS + max(math.sqrt(max(rho_min2, 0.0)) - R, 0.0)


@njit(cache=True, nogil=True)
def _pose(s, lo, hi, tip, axis):
    """Tip and unit axis at path position s in [lo, hi] (linear interpolation)."""
    if hi <= lo:  # a section of one point
        return tip[lo, 0], tip[lo, 1], tip[lo, 2], axis[lo, 0], axis[lo, 1], axis[lo, 2]
    j = int(math.floor(s))
    if j >= hi:
        j = hi - 1
    if j < lo:
        j = lo
    lam = s - j
    if lam < 0.0:
        lam = 0.0
    if lam > 1.0:
        lam = 1.0
    cx = tip[j, 0] + lam * (tip[j + 1, 0] - tip[j, 0])
    cy = tip[j, 1] + lam * (tip[j + 1, 1] - tip[j, 1])
    cz = tip[j, 2] + lam * (tip[j + 1, 2] - tip[j, 2])
    ax = axis[j, 0] + lam * (axis[j + 1, 0] - axis[j, 0])
    ay = axis[j, 1] + lam * (axis[j + 1, 1] - axis[j, 1])
    az = axis[j, 2] + lam * (axis[j + 1, 2] - axis[j, 2])
    n = math.sqrt(ax * ax + ay * ay + az * az)
    return cx, cy, cz, ax / n, ay / n, az / n


@njit(cache=True, nogil=True)
def _entry_at(s, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, cap):
    cx, cy, cz, ax, ay, az = _pose(s, lo, hi, tip, axis)
    return ray_entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap)


@njit(cache=True, nogil=True)
def _golden(a, b, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, n_iter):
    """min of the entry parameter over path positions [a, b] by golden-section search."""
    x1 = b - _GOLD * (b - a)
    x2 = a + _GOLD * (b - a)
    f1 = _entry_at(x1, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, INF)
    f2 = _entry_at(x2, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, INF)
    for _ in range(n_iter):
        if f1 <= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - _GOLD * (b - a)
            f1 = _entry_at(x1, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, INF)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + _GOLD * (b - a)
            f2 = _entry_at(x2, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, INF)
    return min(f1, f2)


@njit(cache=True, nogil=True)
def _ray(iy, ix, vertical, nrm):
    if vertical:
        return 0.0, 0.0, 1.0
    return nrm[iy, ix, 0], nrm[iy, ix, 1], nrm[iy, ix, 2]


@njit(cache=True, nogil=True)
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


@njit(cache=True, nogil=True)
def _stamp(fs, ks, x0, y0, h, pz, nrm, inside, vertical, tip, axis, pose_s, pose_lo, pose_hi,
           pose_reach, R, r, near):
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
                f = ray_entry(px, py, pz[iy, ix], dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap)
                if f < cap:
                    _keep(fs, ks, iy, ix, f, k, near)


@njit(cache=True, nogil=True)
def _refine(res, fs, ks, x0, y0, h, pz, nrm, vertical, tip, axis, pose_s, pose_ds, pose_lo,
            pose_hi, R, r, n_golden):
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
                                             dx, dy, dz, R, r, n_golden))
            res[iy, ix] = best if best < 0.5 * MISS else INF


def sweep(res, x0, y0, h, pz, nrm, inside, vertical, tip, axis, pose_s, pose_ds, pose_lo,
          pose_hi, pose_reach, R, r, n_slots, near, n_golden):
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
           pose_reach, R, r, near)
    _refine(res, fs, ks, x0, y0, h, pz, nrm, vertical, tip, axis, pose_s, pose_ds, pose_lo,
            pose_hi, R, r, n_golden)
