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
points (tool-centre-point control, the axis renormalized), and the residual is the exact
minimum over that continuous motion, not over sampled poses (a sampled sweep would leave
feed-mark ridges of about step^2 / (8 r)). ``moves.py`` and ``convex.py`` find it move by
move (the default); ``stamp.py`` by stamped poses and golden-section refinement (the
reference). :func:`entry_gradient` gives the searches the entry's derivative along a move.
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


@njit(cache=True, nogil=True, error_model="numpy")
def _entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap):
    """(t, face) of :func:`ray_entry`; face: 0 none (a miss or inf), 1 the corner torus or
    flat bottom of a torus, 2 the ball's sphere, 3 the shank's side, 4 the plane w = r (a
    flat end's bottom, or the shank's bottom disc)."""
    qx, qy, qz = px - cx, py - cy, pz - cz
    w0 = qx * ax + qy * ay + qz * az
    da = dx * ax + dy * ay + dz * az
    if da <= 1e-9:
        return INF, 0
    ux, uy, uz = qx - w0 * ax, qy - w0 * ay, qz - w0 * az
    vx, vy, vz = dx - da * ax, dy - da * ay, dz - da * az
    A = vx * vx + vy * vy + vz * vz
    B = ux * vx + uy * vy + uz * vz
    C = ux * ux + uy * uy + uz * uz
    # the stretch [t1, t2] of the ray within the radius (rho <= R): every piece lies there
    if A < 1e-14:
        if C > R * R:
            return MISS + math.sqrt(C) - R, 0
        t1, t2 = -INF, INF
    else:
        disc = B * B - A * (C - R * R)
        if disc < 0.0:
            return MISS + math.sqrt(max(C - B * B / A, 0.0)) - R, 0
        sq = math.sqrt(disc)
        t1, t2 = (-B - sq) / A, (-B + sq) / A
    # shank: rho(t) <= R and w(t) >= r (for r = 0 the whole flat-end cutter)
    tw = (r - w0) / da
    best, face = INF, 0
    if tw <= t2:
        best, face = (tw, 4) if tw >= t1 else (t1, 3)
    if r > 0.0 and R - r <= 1e-12 * R:
        # ball-end: the sphere of radius r about the centre c + r a, in closed form
        ox, oy, oz = qx - r * ax, qy - r * ay, qz - r * az
        b = ox * dx + oy * dy + oz * dz
        disc = b * b - (ox * ox + oy * oy + oz * oz - r * r)
        if disc >= 0.0:
            t = -b - math.sqrt(disc)
            if t < best:
                best, face = t, 2
    elif r > 0.0:
        # flat bottom and corner torus (points within r of the disc of radius R - r at
        # height r), below w = r (above it the shank holds them): Newton on the distance,
        # from the first point of the ray that can be inside (w >= 0 and rho <= R)
        rp = R - r
        t = max(-w0 / da, t1)
        stop = min(tw, t2)
        for _ in range(60):
            if t > stop or t > cap:
                break
            rho2 = A * t * t + 2.0 * B * t + C
            rho = math.sqrt(rho2) if rho2 > 0.0 else 0.0
            w = w0 + t * da
            re = rho - rp
            if re < 0.0:
                re = 0.0
            dist = math.sqrt(re * re + (w - r) * (w - r))
            g = dist - r
            if g <= 1e-10:
                if t < best:
                    best, face = t, 1
                break
            drho = (A * t + B) / rho if rho > 1e-300 else 0.0
            gp = (re * drho + (w - r) * da) / dist
            if gp >= 0.0:
                break
            t -= g / gp
        if t > cap and t < best:
            return t, 0
    if best < INF:
        return best, face
    return MISS, 0


@njit(cache=True, nogil=True, error_model="numpy")
def ray_entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap=INF):
    """Smallest t with p + t d inside the cutter (tip c, unit axis a, radii R, r).

    A ray that misses scores ``MISS`` plus how far outside the radius it passes; a ray that
    does not climb along the axis (d . a <= 0) never enters from below: inf.
    ``cap``: the caller only needs entries below it; once the monotone Newton iterate passes
    it, that iterate (a lower bound of the entry, above the cap) is returned at once.
    """
    return _entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap)[0]


@njit(cache=True, nogil=True, error_model="numpy")
def entry_gradient(t, face, px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r):
    """How the entry t moves with the pose: (gc, ga), two 3-vectors with
    dt = gc . dc - ga . da for a shift dc of the tip and a turn da (perpendicular to a) of
    the axis. At the entry point x (from the tip) the boundary g(x; c, a) = 0 holds, so by
    the implicit function theorem dt = (grad g . dc - dg/da . da) / (grad g . d); g is
    written in the tool frame as g(w, rho) (w = x . a, rho = |x - w a|), for which
    dg/da = (g_w - g_rho w / rho) x. Zeros for face 0 (no entry)."""
    if face == 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    x = px - cx + t * dx
    y = py - cy + t * dy
    z = pz - cz + t * dz
    w = x * ax + y * ay + z * az
    rx, ry, rz = x - w * ax, y - w * ay, z - w * az
    rho = math.sqrt(rx * rx + ry * ry + rz * rz)
    if rho > 1e-300:
        rx, ry, rz = rx / rho, ry / rho, rz / rho
    gw, gr = -1.0, 0.0  # face 4: g = r - w
    if face == 1:
        re = max(rho - (R - r), 0.0)
        dist = math.sqrt(re * re + (w - r) * (w - r))
        gw, gr = (w - r) / dist, re / dist
    elif face == 2:  # the sphere about c + r a: gradient along x - r a
        ox, oy, oz = x - r * ax, y - r * ay, z - r * az
        n = math.sqrt(ox * ox + oy * oy + oz * oz)
        ox, oy, oz = ox / n, oy / n, oz / n
        den = min(ox * dx + oy * dy + oz * dz, -1e-12)  # < 0: the ray goes in
        return ox / den, oy / den, oz / den, -r * ox / den, -r * oy / den, -r * oz / den
    elif face == 3:
        gw, gr = 0.0, 1.0
    nx, ny, nz = gw * ax + gr * rx, gw * ay + gr * ry, gw * az + gr * rz
    den = min(nx * dx + ny * dy + nz * dz, -1e-12)
    k = (gw - gr * w / rho) / den if rho > 1e-300 else gw / den
    return nx / den, ny / den, nz / den, k * x, k * y, k * z


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, nogil=True, error_model="numpy")
def _entry_at(s, lo, hi, tip, axis, px, py, pz, dx, dy, dz, R, r, cap):
    cx, cy, cz, ax, ay, az = _pose(s, lo, hi, tip, axis)
    return ray_entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, R, r, cap)


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, nogil=True, error_model="numpy")
def _ray(iy, ix, vertical, nrm):
    if vertical:
        return 0.0, 0.0, 1.0
    return nrm[iy, ix, 0], nrm[iy, ix, 1], nrm[iy, ix, 2]
