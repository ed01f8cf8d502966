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

from ..cutters.base import CONE, CYLINDER, PIECE, ROUND
from ..cutters.profile_kernel import piece_height  # noqa: F401 (the sweep's bounds use it)

INF = np.inf
#: a ray that misses a pose scores MISS + its distance outside the cutter's radius, so that a
#: search along the path still moves towards where the pose reaches it (a flat end's sharp
#: rim is only in reach over a short stretch); any score above MISS / 2 is a miss
MISS = 1e6
_GOLD = 0.5 * (math.sqrt(5.0) - 1.0)


@njit(cache=True, nogil=True, error_model="numpy")
def _entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, prm, cap):
    """(t, face) of :func:`ray_entry`; face 0: none (a miss or inf), else 1 + 3 k + sub for
    piece k of the kernel array: sub 0 its curved face (a cylinder's side, a torus or
    sphere, a cone's side), 1 its bottom plane w = w_lo (a cylinder's or cone's)."""
    R = prm[0]
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
    best, face = INF, 0
    lower = INF  # an iterate past the cap: a lower bound of an entry above the cap
    for k in range(int(prm[1])):
        b = 2 + PIECE * k
        code = prm[b]
        if code == CYLINDER:
            # rho(t) <= R and w(t) >= w_lo: closed form
            tw = (prm[b + 1] - w0) / da
            if tw <= t2:
                t, sub = (tw, 1) if tw >= t1 else (t1, 0)
                if t < best:
                    best, face = t, 1 + 3 * k + sub
        elif code == ROUND and prm[b + 1] <= 1e-12 * R:
            # a sphere of radius q about c a, in closed form
            c, q = prm[b + 2], prm[b + 3]
            ox, oy, oz = qx - c * ax, qy - c * ay, qz - c * az
            bb = ox * dx + oy * dy + oz * dz
            disc = bb * bb - (ox * ox + oy * oy + oz * oz - q * q)
            if disc >= 0.0:
                t = -bb - math.sqrt(disc)
                if t < best:
                    best, face = t, 1 + 3 * k
        else:
            # a torus piece (within q of the disc) or a cone frustum: Newton on a convex
            # function of the point (the distance to the disc minus q; rho cos beta -
            # (w - w_a) sin beta), convex along the line, from the first point of the ray
            # that can be inside: it climbs monotonically to the first root
            if code == ROUND:
                e, c, q = prm[b + 1], prm[b + 2], prm[b + 3]
                t_lo, t_hi = (c - q - w0) / da, (c + q - w0) / da
            else:
                wa, sb, cb = prm[b + 1], prm[b + 2], prm[b + 3]
                t_lo, t_hi = (prm[b + 4] - w0) / da, (prm[b + 5] - w0) / da
            t = max(t_lo, t1)
            stop = min(t_hi, t2)
            for _ in range(60):
                if t > stop or t > cap or t > best:
                    break
                rho2 = A * t * t + 2.0 * B * t + C
                rho = math.sqrt(rho2) if rho2 > 0.0 else 0.0
                w = w0 + t * da
                drho = (A * t + B) / rho if rho > 1e-300 else 0.0
                if code == ROUND:
                    re = rho - e
                    if re < 0.0:
                        re = 0.0
                    dist = math.sqrt(re * re + (w - c) * (w - c))
                    g = dist - q
                    gp = (re * drho + (w - c) * da) / dist if dist > 0.0 else -1.0
                else:
                    g = rho * cb - (w - wa) * sb
                    gp = drho * cb - da * sb
                if g <= 1e-10:
                    if t < best:
                        sub = 1 if code == CONE and t == t_lo else 0
                        best, face = t, 1 + 3 * k + sub
                    break
                if gp >= 0.0:
                    break
                t -= g / gp
            if t > cap:
                lower = min(lower, t)
    if lower < best:
        return lower, 0
    if best < INF:
        return best, face
    return MISS, 0


@njit(cache=True, nogil=True, error_model="numpy")
def ray_entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, prm, cap=INF):
    """Smallest t with p + t d inside the cutter (tip c, unit axis a, the cutter's kernel
    array ``prm``: ``Cutter.kernel_params``).

    A ray that misses scores ``MISS`` plus how far outside the radius it passes; a ray that
    does not climb along the axis (d . a <= 0) never enters from below: inf.
    ``cap``: the caller only needs entries below it; once a monotone Newton iterate passes
    it, that iterate (a lower bound of the entry, above the cap) is returned at once.
    """
    return _entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, prm, cap)[0]


@njit(cache=True, nogil=True, error_model="numpy")
def entry_gradient(t, face, px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, prm):
    """How the entry t moves with the pose: (gc, ga), two 3-vectors with
    dt = gc . dc - ga . da for a shift dc of the tip and a turn da (perpendicular to a) of
    the axis. At the entry point x (from the tip) the boundary g(x; c, a) = 0 holds, so by
    the implicit function theorem dt = (grad g . dc - dg/da . da) / (grad g . d); g is
    written in the tool frame as g(w, rho) (w = x . a, rho = |x - w a|), for which
    dg/da = (g_w - g_rho w / rho) x. Zeros for face 0 (no entry)."""
    if face == 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    b = 2 + PIECE * ((face - 1) // 3)
    sub = (face - 1) % 3
    code = prm[b]
    x = px - cx + t * dx
    y = py - cy + t * dy
    z = pz - cz + t * dz
    w = x * ax + y * ay + z * az
    rx, ry, rz = x - w * ax, y - w * ay, z - w * az
    rho = math.sqrt(rx * rx + ry * ry + rz * rz)
    if rho > 1e-300:
        rx, ry, rz = rx / rho, ry / rho, rz / rho
    gw, gr = -1.0, 0.0  # a bottom plane: g = w_lo - w
    if sub == 1:
        pass
    elif code == CYLINDER:
        gw, gr = 0.0, 1.0
    elif code == ROUND and prm[b + 1] <= 1e-12 * prm[0]:  # the sphere about c a
        c = prm[b + 2]
        ox, oy, oz = x - c * ax, y - c * ay, z - c * az
        n = math.sqrt(ox * ox + oy * oy + oz * oz)
        ox, oy, oz = ox / n, oy / n, oz / n
        den = min(ox * dx + oy * dy + oz * dz, -1e-12)  # < 0: the ray goes in
        return ox / den, oy / den, oz / den, -c * ox / den, -c * oy / den, -c * oz / den
    elif code == ROUND:
        e, c = prm[b + 1], prm[b + 2]
        re = max(rho - e, 0.0)
        dist = math.sqrt(re * re + (w - c) * (w - c))
        gw, gr = (w - c) / dist, re / dist
    else:
        gw, gr = -prm[b + 2], prm[b + 3]
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
def _entry_at(s, lo, hi, tip, axis, px, py, pz, dx, dy, dz, prm, cap):
    cx, cy, cz, ax, ay, az = _pose(s, lo, hi, tip, axis)
    return ray_entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, prm, cap)


@njit(cache=True, nogil=True, error_model="numpy")
def _golden(a, b, lo, hi, tip, axis, px, py, pz, dx, dy, dz, prm, n_iter):
    """min of the entry parameter over path positions [a, b] by golden-section search."""
    x1 = b - _GOLD * (b - a)
    x2 = a + _GOLD * (b - a)
    f1 = _entry_at(x1, lo, hi, tip, axis, px, py, pz, dx, dy, dz, prm, INF)
    f2 = _entry_at(x2, lo, hi, tip, axis, px, py, pz, dx, dy, dz, prm, INF)
    for _ in range(n_iter):
        if f1 <= f2:
            b, x2, f2 = x2, x1, f1
            x1 = b - _GOLD * (b - a)
            f1 = _entry_at(x1, lo, hi, tip, axis, px, py, pz, dx, dy, dz, prm, INF)
        else:
            a, x1, f1 = x1, x2, f2
            x2 = a + _GOLD * (b - a)
            f2 = _entry_at(x2, lo, hi, tip, axis, px, py, pz, dx, dy, dz, prm, INF)
    return min(f1, f2)


@njit(cache=True, nogil=True, error_model="numpy")
def _ray(iy, ix, vertical, nrm):
    if vertical:
        return 0.0, 0.0, 1.0
    return nrm[iy, ix, 0], nrm[iy, ix, 1], nrm[iy, ix, 2]
