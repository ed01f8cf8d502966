"""The tapered ball-end mill: a cone of half-angle beta ending in a ball of radius r.

Parameters: the largest diameter D = 2 R (where the taper meets the cylindrical shank), the
ball's radius r (``corner_radius``, 0 < r <= R) and the taper half-angle beta
(``taper_angle``, degrees, 0 < beta < 90). In the tool frame (w up the axis from the tip,
rho the distance from it) the ball is centred at w = r; the cone is tangent to it along the
circle

    rho_t = r cos beta,  w_t = r (1 - sin beta),

its apex at w_a = r - r / sin beta, and it widens to R at the top of the cutting end

    H = w_t + (R - rho_t) / tan beta.

Lower profile of a vertical cutter (tip at the origin) and its inverse, the half-width:

    height(rho) = r - sqrt(r^2 - rho^2)             rho <= rho_t   (the ball)
                = w_t + (rho - rho_t) / tan beta     rho_t < rho <= R  (the cone)
                = inf                                rho > R

    width(h)    = sqrt(2 r h - h^2)                  0 <= h <= w_t
                = rho_t + (h - w_t) tan beta         w_t < h < H
                = R                                  h >= H        (the shank)

The cutting end is the convex hull of the ball and the top rim (the circle of radius R at
height H), so its support point along a unit direction d is the better of the two:

    S(d) = r a + r d          if r (a.d) + r >= H (a.d) + R |d - (d.a) a|
         = H a + R e          otherwise (e the unit projection of d normal to a).

A contact on the ball has the ball's effective radius r in every feed direction; a contact
on the cone (a surface normal n with a.n < sin beta) has none: the cone is developable, its
Gaussian curvature 0, so its silhouette is the straight generator (R_eff = inf).

APT ``CUTTER/d,r,e,f,a,b,h``: d the diameter where the cone's side line meets the bottom
line (the plane of the tip, a = 0): d = 2 r (1 - sin beta) / cos beta; e = 0, f = r; b = beta;
h = H, so that D = d + 2 h tan beta.
"""

from __future__ import annotations

import numpy as np

from .base import CONE, CYLINDER, ROUND, Cutter, register

__all__ = ["TaperedBallCutter"]


@register("tapered_ball", "tapered-ball", "taper_ball")
class TaperedBallCutter(Cutter):
    """Tapered ball-end mill (module docstring): D, r (the ball), ``taper_angle`` (deg)."""

    extra_parameters = ("taper_angle",)

    @classmethod
    def accepts(cls, diameter, corner_radius, taper_angle=None, **extra):
        return (not extra and taper_angle is not None and 0 < taper_angle < 90
                and 0 < corner_radius <= diameter / 2)

    @classmethod
    def check(cls, diameter, corner_radius, key, taper_angle=None, **extra):
        if taper_angle is not None and not 0 < taper_angle < 90:
            raise ValueError(f"{key}.taper_angle: must be in (0, 90) degrees, got {taper_angle:g}")
        if not corner_radius > 0:
            raise ValueError(f"{key}.corner_radius: a tapered ball needs the ball's radius r > 0, "
                             f"got {corner_radius:g}")

    # -- the geometry of the module docstring --------------------------------------------
    @property
    def beta(self) -> float:
        """The taper half-angle (radians)."""
        return np.radians(self.taper_angle)

    @property
    def tangency(self) -> tuple[float, float]:
        """(rho_t, w_t): where the cone touches the ball."""
        r, b = self.corner_radius, self.beta
        return r * np.cos(b), r * (1.0 - np.sin(b))

    @property
    def cutting_height(self) -> float:
        """H: the cone reaches the radius R there (the shank above)."""
        rho_t, w_t = self.tangency
        return w_t + (self.radius - rho_t) / np.tan(self.beta)

    @property
    def centre_height(self) -> float:
        """r: the ball's centre."""
        return self.corner_radius

    def pieces(self):
        """The shank above H, the cone frustum between w_t and H, the ball."""
        b, r, top = self.beta, self.corner_radius, self.cutting_height
        return [(CYLINDER, top), (CONE, r - r / np.sin(b), np.sin(b), np.cos(b), self.tangency[1], top),
                (ROUND, 0.0, r, r)]

    def height_jet(self, s):
        """(g, g', g'') at s = rho^2 / 2: the ball's g = r - w, 1 / w, 1 / w^3 (w =
        sqrt(r^2 - 2 s)), the cone's g = w_t + (rho - rho_t) cot beta, cot beta / rho,
        -cot beta / rho^3; inf beyond R."""
        s = np.maximum(np.asarray(s, float), 0.0)
        rho = np.sqrt(2.0 * s)
        r, big = self.corner_radius, self.radius
        rho_t, w_t = self.tangency
        cot = 1.0 / np.tan(self.beta)
        ball = rho <= rho_t
        inside = rho <= big * (1 + 1e-12)
        w = np.sqrt(np.maximum(r * r - 2.0 * s, 1e-300))
        with np.errstate(divide="ignore", invalid="ignore"):
            g = np.where(ball, r - w, w_t + (rho - rho_t) * cot)
            g1 = np.where(ball, 1.0 / w, cot / rho)
            g2 = np.where(ball, 1.0 / w ** 3, -cot / rho ** 3)
        return np.where(inside, g, np.inf), np.where(inside, g1, 0.0), np.where(inside, g2, 0.0)

    def width(self, h):
        """Half-width at height h: the ball's sqrt(2 r h - h^2) to w_t, the cone's
        rho_t + (h - w_t) tan beta to H, R above."""
        h = np.asarray(h, float)
        r = self.corner_radius
        rho_t, w_t = self.tangency
        hb = np.clip(h, 0.0, w_t)
        w = np.where(h <= w_t, np.sqrt(np.maximum(2 * r * hb - hb * hb, 0.0)),
                     np.minimum(rho_t + (h - w_t) * np.tan(self.beta), self.radius))
        return np.where(h < 0, np.nan, w)

    def support_point(self, axis, direction):
        """S(d) of the module docstring, relative to the tip; batched (k, 3)."""
        d = np.asarray(direction, float)
        d = d / np.linalg.norm(d, axis=-1, keepdims=True)
        a = np.asarray(axis, float)
        a = np.broadcast_to(a / np.linalg.norm(a, axis=-1, keepdims=True), d.shape)
        da = np.sum(d * a, axis=-1, keepdims=True)
        proj = d - da * a
        norm = np.linalg.norm(proj, axis=-1, keepdims=True)
        e = np.where(norm > 1e-12, proj / np.where(norm > 1e-12, norm, 1.0), 0.0)
        r, top = self.corner_radius, self.cutting_height
        ball = r * da + r >= top * da + self.radius * norm
        return np.where(ball, r * a + r * d, top * a + self.radius * e)

    def ring_heights(self):
        """The ball at 0, 20 and 45 degrees from the bottom (below the tangency), then the
        cone at its foot, middle and top."""
        r, top = self.corner_radius, self.cutting_height
        w_t = self.tangency[1]
        ball = r * (1.0 - np.cos(np.radians([0.0, 20.0, 45.0])))
        return np.r_[ball[ball < w_t], w_t, 0.5 * (w_t + top), top]

    # -- the effective radius: the ball's r, or inf on the cone ----------------------------
    def _on_ball(self, a_dot_n):
        return np.asarray(a_dot_n, float) >= np.sin(self.beta) - 1e-12

    def effective_radius(self, a_dot_t, a_dot_n):
        """r where the contact is on the ball (a.n >= sin beta), inf on the cone."""
        shape = np.broadcast_shapes(np.shape(a_dot_t), np.shape(a_dot_n))
        return np.broadcast_to(np.where(self._on_ball(a_dot_n), self.corner_radius, np.inf), shape)

    def effective_radius_lead_tilt(self, lead, tilt):
        """The same with a.n = cos aL cos aT."""
        an = np.cos(np.asarray(lead, float)) * np.cos(np.asarray(tilt, float))
        return self.effective_radius(np.sin(lead), an)

    def effective_radius_3axis(self, slope, steepest, alpha):
        """The same with a.n = cos S (tool axis z)."""
        shape = np.broadcast_shapes(np.shape(slope), np.shape(steepest), np.shape(alpha))
        return np.broadcast_to(self.effective_radius(0.0, np.cos(np.asarray(slope, float))), shape)

    # -- APT -----------------------------------------------------------------------------
    def apt_parameters(self):
        """(d, r, 0, r, 0, beta, H) with d = 2 r (1 - sin beta) / cos beta (module docstring)."""
        r, b = self.corner_radius, self.beta
        return (2 * r * (1 - np.sin(b)) / np.cos(b), r, 0.0, r, 0.0, self.taper_angle,
                self.cutting_height)

    @classmethod
    def from_apt(cls, values):
        """A tapered ball from ``CUTTER/d,r,0,r,0,b,h`` (b > 0; D = d + 2 h tan b), else None."""
        if len(values) != 7:
            return None
        d, r, e, f, a, b, h = values
        tol = 1e-6 * max(d, 1.0)
        if not (r > 0 and 0 < b < 90 and abs(a) <= 1e-9 and abs(e) <= tol and abs(f - r) <= tol):
            return None
        big = d + 2 * h * np.tan(np.radians(b))
        return cls(big, r, taper_angle=b) if cls.accepts(big, r, taper_angle=b) else None
