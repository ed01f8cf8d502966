"""Exact cross-feed profile of a 3-axis torus, and the CC spacing it allows under h_c.

Why not only the circle of radius R_eff: Djebali Eq. 1 is the exact curvature of the
swept profile AT the contact point, but a toroidal profile is an offset ellipse, and the
circle is a poor stand-in away from the contact. The worst case is a gentle slope fed
across the steepest direction: Eq. 1 gives R_eff = r there for any slope (1 mm, a 1.33 mm
step-over at h_c = 0.254), while the real profile is the corner arc followed by the flat
bottom rising at only the slope angle (S = 1 deg: a 5.6 mm step-over). ``model: circle``
keeps the paper's form for comparison.

Geometry (tool axis z; Redonnet et al. 2013, Djebali Sec. 2.2): the cutter's silhouette in
the plane normal to the feed tangent t (``cutters/silhouette.py``: the rim projects to the
ellipse of semi-axes R - r across the feed and (R - r) |t_z| upwards, offset by r). The
surface's cross-section is the line through the contact along the cross-feed tangent, at
angle beta to the horizontal (sin beta = b_z / cos(feed inclination)); the profile's height
above it rises on each side, and ``Cutter.swept_side_width`` gives the lateral offset x
where it reaches h_c. Adjacent zig-zag passes leave the same profile (the tool is symmetric about its
axis), so the CC spacing on the surface is w = x_right(h_c) + x_left(h_c).

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

from .lookup_kernel import bilinear_nearest

__all__ = ["ProfileTable", "profile_table", "profile_width", "SideTable", "side_table", "side_width",
           "angle_grid", "grid_coords",
           "section_beta", "secant_width"]


def angle_grid(n_t: int, n_b: int):
    """(tt, bb) (n_t, n_b): the tables' nodes in |t_z| and |beta| (rad), uniform in
    sqrt(|t_z|) over [0, 1] and sqrt(|beta|) over [0, pi/2] (dense near the flat bottom)."""
    return np.meshgrid(np.linspace(0.0, 1.0, n_t) ** 2,
                       np.linspace(0.0, 1.0, n_b) ** 2 * 0.5 * np.pi, indexing="ij")


def grid_coords(t_z, beta, n_t: int, n_b: int):
    """(i, j): fractional indices of |t_z|, |beta| on :func:`angle_grid` (clamped to it)."""
    i = np.sqrt(np.minimum(np.abs(t_z), 1.0)) * (n_t - 1)
    j = np.sqrt(np.minimum(np.abs(beta) / (0.5 * np.pi), 1.0)) * (n_b - 1)
    return i, j


def section_beta(t_z, b_z) -> np.ndarray:
    """Slope angle beta (rad) of the section across the feed: sin beta = b_z / cos(gamma),
    gamma the feed inclination (cos gamma = sqrt(1 - t_z^2))."""
    cos_g = np.sqrt(np.maximum(1.0 - t_z * t_z, 1e-300))
    return np.arcsin(np.clip(b_z / cos_g, -1.0, 1.0))


def secant_width(w, kappa, h) -> np.ndarray:
    """A plane's CC spacing w at cusp height h on a section of curvature kappa (> 0
    concave): w / sqrt(1 - kappa R_s), R_s = (w/2)^2 / (2 h) the profile's secant radius;
    inf where 1 - kappa R_s <= 0 (a concave section tighter than the profile)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        shrink = 1.0 - kappa * w * w / (8.0 * h)
        return np.where(shrink > 0, w / np.sqrt(np.maximum(shrink, 1e-300)), np.inf)


class ProfileTable:
    """CC spacing at h_c on a plane, W = x(beta) + x(-beta), over (|t_z|, |beta|), solved once.

    The two half-widths jump where the flat bottom lies on the section (t_z = beta = 0);
    their sum does not, so the sum is tabulated. Grids are uniform in sqrt(|t_z|) and
    sqrt(|beta|), dense near 0 where the width changes fastest.
    """

    def __init__(self, cutter, h: float, n_t: int = 129, n_b: int = 129):
        self.h = h
        self.n_t, self.n_b = n_t, n_b
        tt, bb = angle_grid(n_t, n_b)
        self.table = cutter.swept_side_width(h, tt, bb) + cutter.swept_side_width(h, tt, -bb)

    def width(self, t_z, beta) -> np.ndarray:
        """Bilinear lookup of W at |t_z|, |beta| (arrays): ``lookup_kernel.bilinear_nearest``,
        the numbers of :meth:`width_numpy` bit for bit."""
        return bilinear_nearest(self.table, *grid_coords(t_z, beta, self.n_t, self.n_b))

    def width_numpy(self, t_z, beta) -> np.ndarray:
        """:meth:`width` through ``scipy.ndimage.map_coordinates`` (the reference)."""
        return map_coordinates(self.table, grid_coords(t_z, beta, self.n_t, self.n_b),
                               order=1, mode="nearest")


@lru_cache(maxsize=16)
def profile_table(cutter, h: float) -> ProfileTable:
    """The cached :class:`ProfileTable` of a cutter (a ``cutters.Cutter``) at height h."""
    return ProfileTable(cutter, h)


def profile_width(target, t_z, b_z, kappa) -> np.ndarray:
    """CC spacing (mm, on the surface across the feed) with cusps of at most h_c.

    target: a ``stepover.ScallopTarget`` (cutter, h_c); t_z: (N,) z component of the unit
    feed tangent; b_z: (N,) z component of the unit cross-feed tangent; kappa: (N,)
    curvature across the feed (> 0 concave).
    """
    t_z, b_z, kappa = np.broadcast_arrays(*(np.asarray(x, float) for x in (t_z, b_z, kappa)))
    table = profile_table(target.cutter, float(target.h_c))
    w = table.width(t_z, section_beta(t_z, b_z))
    return secant_width(w, kappa, target.h_c)


class SideTable:
    """One side's CC half-width of a 3-axis cutter, over the height, |t_z| and the signed
    section slope beta (``Cutter.swept_side_width``: the +b side; the -b side is -beta),
    solved once: x (n_h, n_t, n_b) at heights uniform in sqrt(h) over [0, h_top].

    :meth:`width` adds the surface's curvature across the feed EXACTLY to second order on
    each side: the profile's height above the tangent line minus the section's rise
    kappa x^2 / 2 (kappa > 0 concave) reaches h_c at the x where h' = h_c + kappa x(h')^2 / 2,
    solved by bisection in h' on the table. Why not the secant correction of
    :func:`secant_width` on the sum of the two sides: it treats the profile as one circle,
    while a torus's two sides differ (corner arc uphill, flat bottom rising at the slope
    downhill): on a convex section the flat side's width is overestimated by 10-15 %.
    """

    def __init__(self, cutter, h: float, n_h: int = 17, n_t: int = 33, n_b: int = 49):
        self.h, self.h_top = h, 4.0 * h
        self.n_h, self.n_t, self.n_b = n_h, n_t, n_b
        # beta nodes uniform in sign(beta) sqrt|beta|, none AT 0: the flat bottom's jump
        # (t_z = beta = 0) lies between the two innermost nodes, where :meth:`at` takes the
        # narrower one
        s = np.linspace(-1.0, 1.0, 2 * n_b)
        self.beta_0 = (s[n_b] ** 2) * 0.5 * np.pi
        tt = np.linspace(0.0, 1.0, n_t) ** 2
        bb = np.sign(s) * s * s * 0.5 * np.pi
        self.heights = np.linspace(0.0, 1.0, n_h) ** 2 * self.h_top
        H, T, B = np.meshgrid(self.heights, tt, bb, indexing="ij")
        self.table = cutter.swept_side_width(H, T, B)

    def _coords(self, hh, t_z, beta):
        k = np.sqrt(np.clip(hh / self.h_top, 0.0, 1.0)) * (self.n_h - 1)
        i = np.sqrt(np.minimum(np.abs(t_z), 1.0)) * (self.n_t - 1)
        s = np.sign(beta) * np.sqrt(np.minimum(np.abs(beta) / (0.5 * np.pi), 1.0))
        j = (s + 1.0) * 0.5 * (2 * self.n_b - 1)
        return np.stack([k, i, j])

    def _lookup(self, hh, t_z, beta):
        return map_coordinates(self.table, self._coords(hh, t_z, beta), order=1,
                               mode="nearest")

    def at(self, hh, t_z, beta) -> np.ndarray:
        """Trilinear lookup of the half-width at height hh (arrays); between the two
        innermost beta nodes, the narrower of them."""
        x = self._lookup(hh, t_z, beta)
        mid = np.abs(beta) < self.beta_0
        if mid.any():
            hm, tm = hh[mid], t_z[mid]
            x[mid] = np.minimum(self._lookup(hm, tm, np.full(len(hm), self.beta_0)),
                                self._lookup(hm, tm, np.full(len(hm), -self.beta_0)))
        return x

    def width(self, t_z, beta, kappa, iterations: int = 30) -> np.ndarray:
        """:meth:`width_numpy` in one compiled pass (``side_kernel.side_widths``: the same
        numbers to round-off, tested)."""
        from .side_kernel import side_widths

        t_z, beta, kappa = np.broadcast_arrays(*(np.asarray(x, float) for x in
                                                 (t_z, beta, kappa)))
        out = side_widths(self.table, self.h, self.h_top, self.beta_0,
                          np.ascontiguousarray(t_z.ravel()), np.ascontiguousarray(beta.ravel()),
                          np.ascontiguousarray(kappa.ravel()), iterations)
        return out.reshape(t_z.shape)

    def width_numpy(self, t_z, beta, kappa, iterations: int = 30) -> np.ndarray:
        """Half-width (mm, along the surface across the feed) where the cusp is h_c on the
        +b side of a contact with feed |t_z|, section slope beta (signed, the +b side)
        and curvature kappa across the feed, as an arc on the surface; heights past ``h_top`` (a concave section
        the profile hardly leaves) keep the width at h_top (narrower: on the safe side)."""
        t_z, beta, kappa = np.broadcast_arrays(*(np.asarray(x, float) for x in
                                                 (t_z, beta, kappa)))
        lo, hi = np.zeros(t_z.shape), np.full(t_z.shape, self.h_top)
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            x = self.at(mid, t_z, beta)
            below = mid - 0.5 * kappa * x * x < self.h
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        # x is the cusp's offset along the tangent line, h_c above the surface; the width
        # is measured on the surface, at the cusp's foot: x rho / (rho + h_c) on a convex
        # section of radius rho, x rho / (rho - h_c) on a concave one: x / (1 - kappa h_c)
        x = self.at(0.5 * (lo + hi), t_z, beta)
        return x / np.maximum(1.0 - kappa * self.h, 1e-3)


@lru_cache(maxsize=16)
def side_table(cutter, h: float) -> SideTable:
    """The cached :class:`SideTable` of a cutter at the cusp height h."""
    return SideTable(cutter, h)


def side_width(target, t_z, b_z, kappa) -> np.ndarray:
    """CC half-width (mm, on the surface along +b) at which the cusp on the +b side of a
    contact is h_c: the exact profile of that side with the curvature to second order
    (:class:`SideTable`). The spacing of two passes is the sum of the facing sides, each
    in its own pass's frame (t_z, b_z of the cross-feed tangent pointing at the other
    pass, kappa across its feed)."""
    t_z, b_z, kappa = np.broadcast_arrays(*(np.asarray(x, float) for x in (t_z, b_z, kappa)))
    return side_table(target.cutter, float(target.h_c)).width(t_z, section_beta(t_z, b_z),
                                                              kappa)
