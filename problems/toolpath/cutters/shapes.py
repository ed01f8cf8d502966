"""Flat-end, ball-end and toroidal (bull-nose) cutters: one torus geometry, three shapes.

The cutting end of all three is the Minkowski sum of the rim disk (radius R0 = R - r, in the
plane normal to the axis a, centred r above the tip) and a ball of radius r: r = 0 is the
flat-end (the disk), R0 = 0 the ball-end (the ball), both > 0 the torus. Above the height r
the cutter is the cylindrical shank of radius R.

Exact circle geometry of the lower profile of a vertical cutter (tip at the origin):

    height(rho) = 0                                 rho <= R0      (flat bottom)
                = r - sqrt(r^2 - (rho - R0)^2)      R0 < rho <= R  (corner arc)
                = inf                               rho > R

    width(h)    = R0 + sqrt(2 r h - h^2)            0 <= h < r
                = R                                 h >= r         (the shank)

Support point along a unit direction d (the contact of a cutter resting on a plane of
normal n is the support point along -n):

    S(d) = r a + R0 e + r d,   e = (d - (d.a) a) / |d - (d.a) a|   (e = 0 when d = +-a)
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .base import CYLINDER, ROUND, Cutter, register
from .silhouette import profile_tables, side_width_exact

__all__ = ["ToroidalCutter", "FlatEndCutter", "BallEndCutter"]

_TOL = 1e-12


def _is_ball(d: float, r: float) -> bool:
    return abs(r - d / 2) <= _TOL * max(d / 2, 1.0)


class _Revolved(Cutter):
    """The torus geometry of the module docstring; the registered shapes specialise it."""

    @property
    def rim_radius(self) -> float:
        """R0 = R - r: radius of the circle of corner-arc centres (flat bottom)."""
        return self.radius - self.corner_radius

    def swept_profile(self, lead, tilt):
        """The 5-axis silhouette tables (``silhouette.profile_tables``) at lead/tilt (k,)."""
        lead = np.atleast_1d(np.asarray(lead, float))
        return profile_tables(np.full(lead.shape, self.radius),
                              np.full(lead.shape, self.corner_radius), lead, tilt)

    def swept_side_width(self, h, t_z, beta):
        """The 3-axis side width (``silhouette.side_width_exact``)."""
        return side_width_exact(self.radius, self.corner_radius, h, t_z, beta)

    @property
    def cutting_height(self) -> float:
        """r: the corner arc ends there (the shank above)."""
        return self.corner_radius

    def pieces(self):
        """The shank {rho <= R, w >= r} (for r = 0 the whole flat end) and, for r > 0, the
        points within r of the rim disc (radius R - r, height r): the flat bottom and the
        corner torus, a sphere for the ball."""
        r = self.corner_radius
        return [(CYLINDER, r)] + ([(ROUND, self.rim_radius, r, r)] if r > 0 else [])

    @property
    def centre_height(self) -> float:
        """r: the centre of the ball (ball-end) or the plane of the tube circle (torus); the
        tip itself for a flat-end."""
        return self.corner_radius

    def height_jet(self, s):
        """(g, g', g'') of the lower profile at s = rho^2 / 2 (module docstring), with
        g' = h'(rho) / rho and g'' = (h''(rho) - h'(rho) / rho) / rho^2; inf beyond R."""
        s = np.asarray(s, float)
        rho = np.sqrt(2.0 * np.maximum(s, 0.0))
        r, r0, big = self.corner_radius, self.rim_radius, self.radius
        inside = rho <= big * (1 + _TOL)
        corner = inside & (rho > r0) & (r > 0)
        dx = np.where(corner, rho - r0, 0.0)
        w = np.sqrt(np.maximum(r * r - dx * dx, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            g1 = np.where(corner, dx / (w * rho), 0.0)
            g2 = np.where(corner, (r * r / (w * w * w) - g1) / (rho * rho), 0.0)
        g = np.where(inside, np.where(corner, r - w, 0.0), np.inf)
        return g, g1, g2

    def width(self, h):
        """Half-width at height h above the tip: R0 + sqrt(2 r h - h^2) below r, R above."""
        h = np.asarray(h, float)
        r = self.corner_radius
        hc = np.clip(h, 0.0, r)
        w = np.where(h >= r, self.radius, self.rim_radius + np.sqrt(np.maximum(2 * r * hc - hc * hc, 0.0)))
        return np.where(h < 0, np.nan, w)

    def support_point(self, axis, direction):
        """S(d) = r a + R0 e + r d (module docstring), relative to the tip; batched (k, 3).

        The cutting end only (below the height r): for directions with d.a > 0 the shank
        above would reach further.
        """
        d = np.asarray(direction, float)
        d = d / np.linalg.norm(d, axis=-1, keepdims=True)
        a = np.asarray(axis, float)
        a = np.broadcast_to(a / np.linalg.norm(a, axis=-1, keepdims=True), d.shape)
        proj = d - np.sum(d * a, axis=-1, keepdims=True) * a
        norm = np.linalg.norm(proj, axis=-1, keepdims=True)
        e = np.where(norm > 1e-12, proj / np.where(norm > 1e-12, norm, 1.0), 0.0)
        r = self.corner_radius
        return r * a + self.rim_radius * e + r * d

    def cc_to_tip(self, cc, normal, axis=(0.0, 0.0, 1.0)):
        """``Cutter.cc_to_tip`` (tip = cc - S(a, -n)) in one compiled pass over the points:
        the same operations in the same order as the numpy of ``Cutter.cc_to_tip`` and
        :meth:`support_point`, so the same bits (``_tips``)."""
        cc, normal = np.asarray(cc, float), np.asarray(normal, float)
        if cc.ndim != 2 or normal.shape != cc.shape:
            return super().cc_to_tip(cc, normal, axis)
        axis = np.asarray(axis, float)
        ax = np.ascontiguousarray(np.broadcast_to(axis, cc.shape) if axis.ndim == 2 else
                                  np.broadcast_to(axis.reshape(1, 3), (1, 3)))
        return _tips(np.ascontiguousarray(cc), np.ascontiguousarray(normal), ax,
                     float(self.corner_radius), float(self.rim_radius))


@njit(cache=True, nogil=True, error_model="numpy")
def _norm3(x, y, z):
    """|v| as ``np.linalg.norm(v, axis=-1)`` rounds it: sqrt((x^2 + y^2) + z^2), numpy's
    add.reduce over a row of three, left to right."""
    return math.sqrt((x * x + y * y) + z * z)


@njit(cache=True, nogil=True, error_model="numpy")
def _tips(cc, normal, axis, r, r0):
    """tip = cc - (r a + r0 e + r d), d = -n (n, a normalized as Cutter.cc_to_tip does, then
    again as support_point does), e the unit projection of d normal to a (0 if shorter than
    1e-12); axis (k, 3) or (1, 3) shared."""
    k = cc.shape[0]
    out = np.empty((k, 3))
    for i in range(k):
        j = i if axis.shape[0] == k else 0
        ln = _norm3(normal[i, 0], normal[i, 1], normal[i, 2])
        n0, n1, n2 = normal[i, 0] / ln, normal[i, 1] / ln, normal[i, 2] / ln
        la = _norm3(axis[j, 0], axis[j, 1], axis[j, 2])
        a0, a1, a2 = axis[j, 0] / la, axis[j, 1] / la, axis[j, 2] / la
        ld = _norm3(-n0, -n1, -n2)
        d0, d1, d2 = -n0 / ld, -n1 / ld, -n2 / ld
        la = _norm3(a0, a1, a2)
        a0, a1, a2 = a0 / la, a1 / la, a2 / la
        da = (d0 * a0 + d1 * a1) + d2 * a2
        p0, p1, p2 = d0 - da * a0, d1 - da * a1, d2 - da * a2
        pn = _norm3(p0, p1, p2)
        if pn > 1e-12:
            e0, e1, e2 = p0 / pn, p1 / pn, p2 / pn
        else:
            e0, e1, e2 = 0.0, 0.0, 0.0
        out[i, 0] = cc[i, 0] - (r * a0 + r0 * e0 + r * d0)
        out[i, 1] = cc[i, 1] - (r * a1 + r0 * e1 + r * d1)
        out[i, 2] = cc[i, 2] - (r * a2 + r0 * e2 + r * d2)
    return out


@register("flat", "flat-end", "flat_end")
class FlatEndCutter(_Revolved):
    """Flat-end mill: r = 0 (the end face cuts; on a slope the rim touches)."""

    sharp_rim = True

    @classmethod
    def accepts(cls, diameter, corner_radius, **extra):
        return not extra and diameter > 0 and corner_radius == 0

    @classmethod
    def default_corner_radius(cls, diameter):
        return 0.0


@register("ball", "ball-end", "ball_end")
class BallEndCutter(_Revolved):
    """Ball-end mill: r = R (a sphere centred R above the tip)."""

    spherical = True

    @classmethod
    def accepts(cls, diameter, corner_radius, **extra):
        return not extra and diameter > 0 and _is_ball(diameter, corner_radius)

    @classmethod
    def default_corner_radius(cls, diameter):
        return diameter / 2

    def height_jet(self, s):
        """Sphere: g = R - sqrt(R^2 - 2 s), g' = 1 / w, g'' = 1 / w^3 (w = sqrt(R^2 - 2 s))."""
        s = np.asarray(s, float)
        big = self.radius
        w2 = big * big - 2.0 * np.maximum(s, 0.0)
        inside = w2 >= -_TOL * big * big
        w = np.sqrt(np.maximum(w2, 0.0))
        with np.errstate(divide="ignore"):
            g1 = np.where(inside, 1.0 / w, 0.0)
        return np.where(inside, big - w, np.inf), g1, np.where(inside, g1 ** 3, 0.0)

    def effective_radius_3axis(self, slope, steepest, alpha):
        """A ball-end's R_eff is R for every slope and feed (Djebali Eq. 1 with r = R)."""
        shape = np.broadcast_shapes(np.shape(slope), np.shape(steepest), np.shape(alpha))
        return np.full(shape, self.radius)


@register("toroidal", "torus", "bull-nose", "bullnose")
class ToroidalCutter(_Revolved):
    """Toroidal (bull-nose) mill: 0 < r < R."""

    @classmethod
    def accepts(cls, diameter, corner_radius, **extra):
        return (not extra and diameter > 0 and 0 < corner_radius < diameter / 2
                and not _is_ball(diameter, corner_radius))
