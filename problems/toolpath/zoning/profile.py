"""Exact cross-feed profile of a 3-axis torus, and the CC spacing it allows under h_c.

Why not only the circle of radius R_eff: Djebali Eq. 1 is the exact curvature of the
swept profile AT the contact point, but a toroidal profile is an offset ellipse, and the
circle is a poor stand-in away from the contact. The worst case is a gentle slope fed
across the steepest direction: Eq. 1 gives R_eff = r there for any slope (1 mm, a 1.33 mm
step-over at h_c = 0.254), while the real profile is the corner arc followed by the flat
bottom rising at only the slope angle (S = 1 deg: a 5.6 mm step-over). ``model: circle``
keeps the paper's form for comparison.

Geometry (tool axis z; Redonnet et al. 2013, Djebali Sec. 2.2): in the plane normal to the
feed tangent t, with X the horizontal cross-feed direction c and Y the upward direction e,
the rim circle (radius R - r) projects to the ellipse of semi-axes a = R - r along X and
b = (R - r) |t_z| along Y; the corner adds an offset r. The point of the profile whose
outward normal is nu = (cos psi, sin psi) is

    Q(psi) = (a^2 cos psi, b^2 sin psi) / sqrt(a^2 cos^2 psi + b^2 sin^2 psi) + r nu

(well defined for a segment, b = 0, and a ball, a = b = 0). The surface's cross-section is
the line through the contact along the cross-feed tangent, at angle beta to X
(sin beta = b_z / cos(feed inclination)); the contact has nu = -n, psi_c = beta - pi/2.
Height above the section: n . (Q - Q_c) at the lateral offset x = b . (Q - Q_c). On each side the height rises
monotonically with psi; the width at h_c is found by bisection in psi and a final linear
interpolation (exact along the straight part of a segment). Adjacent zig-zag passes leave
the same profile (the tool is symmetric about its axis), so the CC spacing on the surface
is w = x_right(h_c) + x_left(h_c); a side that never rises to h_c is limited to the tool's
extent on that side.

Speed: the spacing on a plane depends only on |t_z| and |beta|, so it is solved once per
cutter on a 129 x 129 table (``ProfileTable``, cached) and read by bilinear interpolation.
The surface curvature across the feed enters to second order through the secant radius of
the profile, R_s = (w/2)^2 / (2 h_c): w_kappa = w / sqrt(1 - kappa R_s), the circle model's
correction (docs/toolpath_formulas.md) applied to the true profile; 1 - kappa R_s <= 0 (a
concave section tighter than the profile) leaves the physical cap.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.ndimage import map_coordinates

__all__ = ["ProfileTable", "profile_table", "profile_width", "side_width_exact"]


def _point(a, b, r, psi):
    c, s = np.cos(psi), np.sin(psi)
    c = np.where(np.abs(c) < 1e-12, 0.0, c)  # a segment facing nu: its centre, not an end
    norm = np.sqrt(a * a * c * c + b * b * s * s)
    inv = np.where(norm > 0, 1.0 / np.where(norm > 0, norm, 1.0), 0.0)
    return a * a * c * inv + r * c, b * b * s * inv + r * s


def side_width_exact(R, r, h, t_z, beta, iterations: int = 40):
    """Lateral offset (mm, >= 0) on the +b side where the profile rises to h; (N,).

    R, r, h: cutter radius, corner radius, height; t_z: |feed tangent z|; beta: angle of the
    cross-feed tangent to the horizontal in the plane normal to the feed (radians).
    The -b side is ``side_width_exact(..., -beta)`` (the mirror image).
    """
    t_z, beta = np.broadcast_arrays(np.asarray(t_z, float), np.asarray(beta, float))
    a = R - r
    b = a * np.abs(t_z)
    nx, ny = -np.sin(beta), np.cos(beta)
    tx, ty = np.cos(beta), np.sin(beta)
    psi_c = beta - 0.5 * np.pi
    qcx, qcy = _point(a, b, r, psi_c)

    def height(psi):
        qx, qy = _point(a, b, r, psi)
        dx, dy = qx - qcx, qy - qcy
        return nx * dx + ny * dy, dx * tx + dy * ty

    lo, hi = psi_c.copy(), psi_c + 0.5 * np.pi
    g_end, x_end = height(hi)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        below = height(mid)[0] < h
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    (g_lo, x_lo), (g_hi, x_hi) = height(lo), height(hi)
    frac = np.clip((h - g_lo) / np.where(g_hi > g_lo, g_hi - g_lo, 1.0), 0.0, 1.0)
    return np.where(g_end <= h, x_end, x_lo + frac * (x_hi - x_lo))


class ProfileTable:
    """CC spacing at h_c on a plane, W = x(beta) + x(-beta), over (|t_z|, |beta|), solved once.

    The two half-widths jump where the flat bottom lies on the section (t_z = beta = 0);
    their sum does not, so the sum is tabulated. Grids are uniform in sqrt(|t_z|) and
    sqrt(|beta|), dense near 0 where the width changes fastest.
    """

    def __init__(self, R: float, r: float, h: float, n_t: int = 129, n_b: int = 129):
        self.h = h
        self.n_t, self.n_b = n_t, n_b
        tt, bb = np.meshgrid(np.linspace(0.0, 1.0, n_t) ** 2,
                             np.linspace(0.0, 1.0, n_b) ** 2 * 0.5 * np.pi, indexing="ij")
        self.table = side_width_exact(R, r, h, tt, bb) + side_width_exact(R, r, h, tt, -bb)

    def width(self, t_z, beta) -> np.ndarray:
        """Bilinear lookup of W at |t_z|, |beta| (arrays)."""
        i = np.sqrt(np.minimum(np.abs(t_z), 1.0)) * (self.n_t - 1)
        j = np.sqrt(np.minimum(np.abs(beta) / (0.5 * np.pi), 1.0)) * (self.n_b - 1)
        return map_coordinates(self.table, [i, j], order=1, mode="nearest")


@lru_cache(maxsize=16)
def profile_table(R: float, r: float, h: float) -> ProfileTable:
    """The cached :class:`ProfileTable` of a cutter."""
    return ProfileTable(R, r, h)


def profile_width(cutter, t_z, b_z, kappa) -> np.ndarray:
    """CC spacing (mm, on the surface across the feed) with cusps of at most h_c.

    cutter: R, r, h_c; t_z: (N,) z component of the unit feed tangent; b_z: (N,) z component
    of the unit cross-feed tangent; kappa: (N,) curvature across the feed (> 0 concave).
    """
    t_z, b_z, kappa = np.broadcast_arrays(*(np.asarray(x, float) for x in (t_z, b_z, kappa)))
    table = profile_table(float(cutter.R), float(cutter.r), float(cutter.h_c))
    cos_g = np.sqrt(np.maximum(1.0 - t_z * t_z, 1e-300))
    beta = np.arcsin(np.clip(b_z / cos_g, -1.0, 1.0))
    w = table.width(t_z, beta)
    shrink = 1.0 - kappa * w * w / (8.0 * cutter.h_c)  # secant radius (w/2)^2 / (2 h_c)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(shrink > 0, w / np.sqrt(np.maximum(shrink, 1e-300)), np.inf)
