"""3-axis scallop heights from the exact swept profile of a vertical cutter.

With a vertical axis the cutter's profile across the feed is not symmetric on a slope, and
for a toroidal or flat-end tool it is far from the circle of radius R_eff away from the
contact (a flat bottom, then the corner arc). The planner spaces 3-axis passes with that
profile (``plan/zoning/profile.py``: the CC spacing at a cusp height h is
W(h) = x(h, beta) + x(h, -beta), the two sides' offsets where the profile rises to h,
``Cutter.swept_side_width``, with the curvature across the feed entering through the secant
radius: W_kappa = W / sqrt(1 - kappa W^2 / (8 h))). The criteria measure with the same
model, inverted: the cusp height of a gap w is the smallest h whose width spans it,

    h(w) = min { h : W_kappa(h) >= w },

read from a table of W over (|t_z|, |beta|, h) solved once per cutter (cached) and
interpolated (bilinear in the two angles, linear in W^2 between the h levels: W^2 is
proportional to h for a circle, so a ball-end's cusp is exact up to the table's angles).
A gap no level spans leaves the whole stock (``inf`` here; the caller caps it).

Where the section is more concave than the profile at the contact the tool cuts below the
surface beside the contact; that gouge is the circle model's negative height
(``scallop.scallop_height`` with R_eff, exact in curvature at the contact). A ball-end's
profile is a circle of radius R on every slope, so its cusps and gouges are the circle
model's, exactly. See :func:`gap_heights_3axis`.

Accuracy of the table against the solved profile (``Cutter.swept_side_width``, flat
sections, |t_z| < 0.8, |beta| < 1 rad, h 0.002-0.5 mm): median error well under 1 %, 95th
percentile 0.7 % (flat-end D16) and 0.2 % (toroidal D12 r2), at most about 4 %, next to the
flat bottom (t_z and beta near 0, h of a few microns).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..plan.zoning.profile import angle_grid, grid_coords, secant_width, section_beta
from .cusp_kernel import cusp_search
from .scallop import scallop_height

__all__ = ["WidthTable", "width_table", "cusp_heights", "gap_heights_3axis"]


class WidthTable:
    """W(h) over (|t_z|, |beta|) at the h levels ``h``, one cutter.

    The angle grid, its index mapping, the section angle and the secant correction are
    ``plan/zoning/profile.py``'s (the planner's spacing model that the criteria invert).
    """

    def __init__(self, cutter, n_t: int = 49, n_b: int = 49, n_h: int = 40):
        self.n_t, self.n_b = n_t, n_b
        # levels: ~0 (the width of the contact itself: a flat bottom's 2 (R - r)), then
        # geometric from 1e-5 R to R
        self.h = np.r_[1e-9, np.geomspace(1e-5, 1.0, n_h - 1)] * cutter.radius
        tt, bb = angle_grid(n_t, n_b)
        h = self.h[None, None, :]
        self.table = (cutter.swept_side_width(h, tt[..., None], bb[..., None])
                      + cutter.swept_side_width(h, tt[..., None], -bb[..., None]))
        self.table = np.maximum.accumulate(self.table, axis=2)  # round-off: W rises with h
        self.ordered = not np.isnan(self.table).any()  # so W rises with h at every point

    def widths(self, t_z, beta) -> np.ndarray:
        """(N, n_h) W at every h level, bilinear in the angles."""
        fi, fj = grid_coords(t_z, beta, self.n_t, self.n_b)
        i = np.minimum(fi.astype(int), self.n_t - 2)
        j = np.minimum(fj.astype(int), self.n_b - 2)
        a, b = (fi - i)[:, None], (fj - j)[:, None]
        t = self.table
        return ((1 - a) * (1 - b) * t[i, j] + a * (1 - b) * t[i + 1, j]
                + (1 - a) * b * t[i, j + 1] + a * b * t[i + 1, j + 1])


@lru_cache(maxsize=32)
def width_table(cutter) -> WidthTable:
    """The cached :class:`WidthTable` of a cutter."""
    return WidthTable(cutter)


def cusp_heights(cutter, w, t_z, b_z, kappa) -> np.ndarray:
    """Cusp height (mm, >= 0; inf where no level spans the gap) between two passes of a
    vertical cutter whose CC points are w apart on the surface; t_z, b_z the z components of
    the unit feed and cross-feed tangents, kappa the curvature across the feed (> 0
    concave). See the module docstring. One compiled pass (``cusp_kernel.cusp_search``):
    the numbers of :func:`cusp_heights_numpy`, bit for bit."""
    w, t_z, b_z, kappa = (np.asarray(x, float) for x in np.broadcast_arrays(w, t_z, b_z, kappa))
    tab = width_table(cutter)
    fi, fj = grid_coords(t_z, section_beta(t_z, b_z), tab.n_t, tab.n_b)
    i = np.minimum(fi.astype(int), tab.n_t - 2)
    j = np.minimum(fj.astype(int), tab.n_b - 2)
    c = np.ascontiguousarray
    return cusp_search(tab.table, tab.h, c(i.ravel()), c(j.ravel()), c((fi - i).ravel()),
                       c((fj - j).ravel()), c(kappa.ravel()), c(w.ravel()),
                       tab.ordered).reshape(w.shape)


def cusp_heights_numpy(cutter, w, t_z, b_z, kappa) -> np.ndarray:
    """:func:`cusp_heights` in numpy (the reference its compiled pass,
    ``cusp_kernel.cusp_search``, is tested against)."""
    w, t_z, b_z, kappa = (np.asarray(x, float) for x in np.broadcast_arrays(w, t_z, b_z, kappa))
    tab = width_table(cutter)
    W = tab.widths(t_z, section_beta(t_z, b_z))
    wk = secant_width(W, kappa[:, None], tab.h[None, :])
    spans = wk >= w[:, None]
    k = np.argmax(spans, axis=1)
    rows = np.arange(len(w))
    lo = np.maximum(k - 1, 0)
    w0, w1 = wk[rows, lo], wk[rows, k]
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.clip((w * w - w0 * w0) / (w1 * w1 - w0 * w0), 0.0, 1.0)
    frac = np.where(np.isfinite(frac), frac, 1.0)
    out = tab.h[lo] + frac * (tab.h[k] - tab.h[lo])
    return np.where(spans.any(axis=1), np.where(k == 0, 0.0, out), np.inf)


def gap_heights_3axis(cutter, w, tangent, normal, kappa, allowance) -> np.ndarray:
    """Signed material height (mm, < 0 gouge) in the gaps of a vertical cutter's passes:
    the exact-profile cusp (:func:`cusp_heights`), or the circle model's gouge where the
    section is more concave than the profile at the contact; capped at ``allowance``.

    tangent, normal: (N, 3) unit travel direction and surface normal at the CC points
    (b = n x t the cross-feed tangent; R_eff from a = z: a.t = t_z, a.n = n_z).
    """
    t_z = tangent[:, 2]
    b_z = np.cross(normal, tangent)[:, 2]
    r_eff = cutter.effective_radius(t_z, normal[:, 2])
    with np.errstate(invalid="ignore", divide="ignore"):
        circle = scallop_height(r_eff, w, kappa)
    if cutter.spherical:  # a ball's profile IS the circle: exact
        h = np.where(np.isnan(circle), np.inf, circle)
    else:
        h = np.where(circle < 0, circle, cusp_heights(cutter, w, t_z, b_z, kappa))
    return np.minimum(h, allowance)
