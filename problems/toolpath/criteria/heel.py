"""Pose gouge: how deep a leaned or tilted cutter, placed at a CC point, cuts below the surface
anywhere under its end: its heel along the feed and its flanks beside the pass.

The across-feed model (``criteria/scallop.py``) looks only at the middle of the gap between
passes. A 5-axis cutter with a lead angle touches the surface at one point of its corner (a
flat end: its rim), and its inclined bottom reaches up to a diameter behind that contact
(or ahead of it, or beside it, with the other sign of the lead or a tilt). Where the surface
is concave under that bottom it rises into the tool. For a flat end fed over a surface
concave along the feed (normal curvature kappa_f > 0 along the travel direction, seen from
the tool), at a distance x behind the contact the bottom is x tan(lead) above the tangent
plane while the surface rises kappa_f x^2 / 2: the heel cuts max over x in [0, ~2R] of
(kappa_f x^2 / 2 - x tan lead). Beside the pass the twist of the surface adds to it: on
Fountas' part the deepest cut of a leaned flat end lies about 6 mm behind and 8 mm beside
the contact, in the neighbouring pass's strip, which no gap model sees.

:func:`pose_gouge` measures the depth over the whole cutter end. In the frame of a CC point
p (unit normal n, unit travel tangent t, b = n x t) the surface is its osculating quadric

    z(x, y) = (k_tt x^2 + 2 k_tb x y + k_bb y^2) / 2        (exact to second order),

k_tt = kappa_f, k_bb the normal curvatures along t and b and k_tb = II(t, b) the twist. A
point X of the cutter's lower surface (a ring of radius rho at the height h(rho) of the
profile above the tip: ``Cutter.width`` / ``Cutter.height``) lies below the surface by
d = z(X.t, X.b) - X.n, which is the distance from the surface to the cutter along n (the
lower surface of a cutter whose axis is near n is a graph over the tangent plane). The pose
gouge of the point is the largest d over the rings (the flat bottom's edge, where a
quadric's maximum over a flat disc lies unless the surface is convex, and rings up the
corner) and angles around the axis, refined by a parabola through the best angle and its
neighbours; 0 where no d is positive. The heel of the along-feed estimate is its y = 0 line.

The pose is the tangent placement the analytic criteria assume throughout: the tip of
``Cutter.cc_to_tip(p, n, a)`` (or given). A ball-end's lower surface is its sphere, which
stays above any surface of normal curvature below 1/R: its pose gouge is 0 there.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..geometry.rows import present
from ..geometry.vectors import take_rows

__all__ = ["N_ANGLES", "footprint_rings", "pose_gouge"]

#: angles around the axis per ring
N_ANGLES = 16
#: a depth below this (mm) is the round-off of the contact itself (the cutter touches the
#: quadric there), not a gouge
_ROUND_OFF = 1e-9


def footprint_rings(cutter):
    """(rho, h): the rings of the cutter's lower surface sampled by :func:`pose_gouge`, at the
    heights ``cutter.ring_heights()`` (the torus family: h = r (1 - cos theta) of the corner
    angles theta in 0, 20, 45 and 90 deg), rho = ``cutter.width(h)``; duplicate radii (a
    flat end's single rim) and the ball's tip (rho = 0) dropped."""
    h = np.asarray(cutter.ring_heights(), float)
    rho = np.asarray(cutter.width(h), float)
    _, first = np.unique(np.round(rho, 12), return_index=True)
    keep = np.sort(first)
    keep = keep[rho[keep] > 1e-12 * cutter.radius]
    return np.ascontiguousarray(rho[keep]), np.ascontiguousarray(h[keep])


@njit(cache=True, nogil=True, error_model="numpy")
def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


@njit(cache=True, nogil=True, error_model="numpy")
def _along(u, v, k):
    """u + k v (3-tuples)."""
    return (u[0] + k * v[0], u[1] + k * v[1], u[2] + k * v[2])


@njit(cache=True, nogil=True, error_model="numpy")
def _scale(u, k):
    return (k * u[0], k * u[1], k * u[2])


@njit(cache=True, nogil=True, error_model="numpy")
def _unit(u):
    return _scale(u, 1.0 / math.sqrt(_dot(u, u)))


@njit(cache=True, nogil=True, error_model="numpy")
def _cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


@njit(cache=True, nogil=True, error_model="numpy")
def _second_form(i, su, sv, suu, suv, svv, n, t, b):
    """(k_tt, k_tb, k_bb) at point i: II on the unit tangents t, b written in the (su, sv)
    basis by the 2x2 normal equations of the first form (> 0 concave seen from n)."""
    e, f, g = _dot(su[i], su[i]), _dot(su[i], sv[i]), _dot(sv[i], sv[i])
    el, m, nn = _dot(suu[i], n), _dot(suv[i], n), _dot(svv[i], n)
    det = e * g - f * f
    tu, tv, bu, bv = _dot(su[i], t), _dot(sv[i], t), _dot(su[i], b), _dot(sv[i], b)
    at, bt = (g * tu - f * tv) / det, (e * tv - f * tu) / det
    ab, bb = (g * bu - f * bv) / det, (e * bv - f * bu) / det
    return (el * at * at + 2.0 * m * at * bt + nn * bt * bt,
            el * at * ab + m * (at * bb + bt * ab) + nn * bt * bb,
            el * ab * ab + 2.0 * m * ab * bb + nn * bb * bb)


@njit(cache=True, nogil=True, error_model="numpy")
def _pose_depths(p, nrm, tangent, axis, tips, su, sv, suu, suv, svv, tool, rho, hgt, n_rings,
                 n_angles):
    """Per point: the largest d = z(x, y) - X.n over the rings and angles (module docstring);
    -inf for no ring. Point i has cutter tool[i]: rings rho, hgt (rows, the first n_rings)
    and its tip tips[i] (k, 3)."""
    k = p.shape[0]
    out = np.full(k, -np.inf)
    d = np.empty(n_angles)
    cs = np.cos(2.0 * np.pi * np.arange(n_angles) / n_angles)
    sn = np.sin(2.0 * np.pi * np.arange(n_angles) / n_angles)
    for i in range(k):
        n = (nrm[i, 0], nrm[i, 1], nrm[i, 2])
        a = (axis[i, 0], axis[i, 1], axis[i, 2])
        t = _unit(_along(tangent[i], n, -_dot(tangent[i], n)))
        b = _cross(n, t)
        ktt, ktb, kbb = _second_form(i, su, sv, suu, suv, svv, n, t, b)
        an = _dot(a, n)
        c = tool[i]
        rel = (tips[i, 0] - p[i, 0], tips[i, 1] - p[i, 1], tips[i, 2] - p[i, 2])
        # e1: the travel tangent normal to the axis, e2 = a x e1
        e1 = _unit(_along(t, a, -_dot(t, a)))
        e2 = _cross(a, e1)
        rt, rb, rn = _dot(rel, t), _dot(rel, b), _dot(rel, n)
        at, ab = _dot(a, t), _dot(a, b)
        e1t, e1b, e1n = _dot(e1, t), _dot(e1, b), _dot(e1, n)
        e2t, e2b, e2n = _dot(e2, t), _dot(e2, b), _dot(e2, n)
        best = -np.inf
        for q in range(n_rings[c]):
            r0, h0 = rho[c, q], hgt[c, q]
            x0, y0, z0 = rt + h0 * at, rb + h0 * ab, rn + h0 * an
            for j in range(n_angles):  # no branch: the angles run as one vector loop
                x = x0 + r0 * (cs[j] * e1t + sn[j] * e2t)
                y = y0 + r0 * (cs[j] * e1b + sn[j] * e2b)
                z = z0 + r0 * (cs[j] * e1n + sn[j] * e2n)
                d[j] = 0.5 * (ktt * x * x + 2.0 * ktb * x * y + kbb * y * y) - z
            jmax = 0
            for j in range(1, n_angles):
                if d[j] > d[jmax]:
                    jmax = j
            dm, d0, dp = d[(jmax - 1) % n_angles], d[jmax], d[(jmax + 1) % n_angles]
            curv = dm - 2.0 * d0 + dp
            top = d0 - 0.125 * (dm - dp) * (dm - dp) / curv if curv < 0.0 else d0
            best = max(best, top)
        out[i] = best
    return out


def pose_gouge(cutters, tool, p, normal, tangent, axis, jet, tip=None,
               n_angles: int = N_ANGLES) -> np.ndarray:
    """Depth (mm, >= 0) the cutter placed at each CC point cuts below the surface's osculating
    quadric there (module docstring). cutters: the ``Cutter`` objects; tool: (k,) the index
    of each point's cutter; p, normal (unit, on the tool side), tangent (the travel
    direction), axis (unit): (k, 3); jet: the surface's order-2 ``Jet`` at the points (its
    second form is taken on n); tip: (k, 3), or None for the tangent placement of
    ``Cutter.cc_to_tip``."""
    p = np.ascontiguousarray(p, float)
    if len(p) == 0:
        return np.zeros(0)
    tool = np.broadcast_to(tool, len(p))
    if tip is None:
        ax = np.broadcast_to(axis, p.shape)
        tip = np.empty_like(p)
        normal = np.asarray(normal, float)
        for j in present(tool):
            rows = np.flatnonzero(tool == j)
            tip[rows] = cutters[int(j)].cc_to_tip(take_rows(p, rows), take_rows(normal, rows),
                                                  take_rows(ax, rows))
    c = np.ascontiguousarray
    rings = [footprint_rings(cu) for cu in cutters]
    m = max(len(r[0]) for r in rings)
    rho, hgt = np.zeros((len(rings), m)), np.zeros((len(rings), m))
    for j, (r, h) in enumerate(rings):
        rho[j, :len(r)], hgt[j, :len(h)] = r, h
    depth = _pose_depths(
        p, c(normal, float), c(tangent, float), c(np.broadcast_to(axis, p.shape), float),
        c(tip, float), jet.su, jet.sv, jet.suu, jet.suv, jet.svv, c(tool, np.int64), rho, hgt,
        np.array([len(r[0]) for r in rings], np.int64), n_angles)
    return np.where(depth > _ROUND_OFF, depth, 0.0)
