"""Scallop height between adjacent passes, and the step-over it allows.

Two models:

1. The effective-radius (osculating circle) model of the papers, exact circle geometry:
   :func:`scallop_height` (flat, convex, concave), :func:`flat_scallop`, and the spacings of
   Djebali et al. Sec. 2.3 (:func:`stepover_djebali_eq2`, :func:`spacing_exact`).
2. The projected-profile model of the 5-axis analytic criteria (:func:`gap_heights` on the tables of
   ``cutters.silhouette.profile_tables``): the cutter is projected along the feed onto the
   plane normal to the feed, exactly (for a straight move this is the cross-section of the
   swept volume): the rim circle projects to an ellipse (a segment when the rim plane
   contains the feed), and the corner torus adds an offset r. Its curvature at the contact is R_eff (checked in the
   tests), but it stays exact where the circle model breaks down: a flat-end at lead 0
   (flat bottom: no scallop on a plane), a flat-end tilted across the feed (the rim cuts;
   the inclined bottom leaves the saw-tooth "undercut" Fountas mentions after Bedi et al.
   1996), toroidal tools whose cusp lies past the corner radius, and a step-over wider than
   the cutter (uncut strip).

Sign convention: kappa is the normal curvature across the feed, > 0 concave seen from the
tool (see ``surface.py``). A negative cusp height means the tool cuts below the surface
between the passes (gouge: its profile is flatter than a concave section).
"""

from __future__ import annotations

import numpy as np

from ..geometry.rows import interp_rows

__all__ = [
    "flat_scallop",
    "scallop_height",
    "stepover_djebali_eq2",
    "spacing_exact",
    "spacing_flat_approx",
    "profile_height",
    "gap_heights",
]


# -------------------------------------------------------------------------------------
# Effective-radius (circle) model
# -------------------------------------------------------------------------------------

def flat_scallop(r_eff, w):
    """Cusp height on a plane: h = R_eff - sqrt(R_eff^2 - w^2/4) (docs/toolpath_formulas.md).

    Written as (w^2/4) / (R_eff + sqrt(R_eff^2 - w^2/4)) (no cancellation); R_eff = inf
    gives 0; w/2 > R_eff gives nan (the circle does not reach).
    """
    r_eff = np.asarray(r_eff, float)
    w = np.asarray(w, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return 0.25 * w * w / (r_eff + np.sqrt(r_eff * r_eff - 0.25 * w * w))


def scallop_height(r_eff, w, kappa):
    """Cusp height between two circular tool profiles of radius R_eff whose contact points
    are a chord w apart on a surface section of curvature kappa (exact circle geometry).

    h = (w^2/4) [ kappa/(1 + cos th) + (1/R - 2 kappa) / (cos th + sqrt(1 - X^2)) ],
    sin th = w kappa / 2, X = (w/2)(1/R - kappa); measured along the bisector normal.
    Limits: flat h = R - sqrt(R^2 - w^2/4); to first order convex (kappa = -1/rho)
    (w^2/8)(1/R + 1/rho), concave (w^2/8)(1/R - 1/rho) (docs/toolpath_formulas.md). R_eff = inf
    (flat bottom) is allowed: h = -kappa w^2/8 to first order. Negative h: gouge.
    """
    r_eff, w, k = np.broadcast_arrays(*(np.asarray(x, float) for x in (r_eff, w, kappa)))
    with np.errstate(divide="ignore", invalid="ignore"):
        ir = 1.0 / r_eff
        cos_th = np.sqrt(1.0 - (0.5 * w * k) ** 2)
        x = 0.5 * w * (ir - k)
        return 0.25 * w * w * (k / (1.0 + cos_th) + (ir - 2 * k) / (cos_th + np.sqrt(1.0 - x * x)))


def stepover_djebali_eq2(h, r_eff, rho, convex=True):
    """Djebali et al. Eq. 2: P_t = sqrt(8 h R_eff (R_eff + rho) / rho), rho a RADIUS (mm).

    This is the spacing of the tool centres on a convex section (docs/toolpath_formulas.md);
    concave uses (rho - R_eff)/rho. Example: h 0.01, R_eff 6, rho 30 -> 0.7589 mm.
    """
    h, r, rho = (np.asarray(x, float) for x in (h, r_eff, rho))
    sign = 1.0 if convex else -1.0
    return np.sqrt(8 * h * r * (rho + sign * r) / rho)


def spacing_exact(h, r_eff, rho, convex=True):
    """Exact (centre spacing, CC spacing) for cusp height h on a circular section.

    Tool circles of radius R whose centres lie at rho + R (convex) or rho - R (concave) from
    the section centre O; the cusp lies at rho + h (convex) or rho - h (concave) from O;
    the law of cosines gives the half-angle psi, and the chords are 2 (rho +- R) sin psi
    (centres) and 2 rho sin psi (CC points). Example (h 0.01, R 6, rho 30, convex):
    0.7585 and 0.6321 mm.
    """
    h, r, rho = (np.asarray(x, float) for x in (h, r_eff, rho))
    sign = 1.0 if convex else -1.0
    c = rho + sign * r
    q = rho + sign * h
    cos_psi = (c * c + q * q - r * r) / (2 * c * q)
    sin_psi = np.sqrt(np.maximum(1 - cos_psi * cos_psi, 0.0))
    return 2 * np.abs(c) * sin_psi, 2 * rho * sin_psi


def spacing_flat_approx(h, r_eff):
    """Flat-surface spacing to first order, sqrt(8 h R_eff) (0.6928 mm for h 0.01, R 6)."""
    return np.sqrt(8 * np.asarray(h, float) * np.asarray(r_eff, float))


# -------------------------------------------------------------------------------------
# Projected-profile model (the 5-axis analytic criteria)
# -------------------------------------------------------------------------------------

def profile_height(tables, row, x):
    """Profile height at offsets x >= 0 on table rows ``row`` (one query per element).

    tables: (x, z, reach) from ``cutters.silhouette.profile_tables``; returns inf beyond
    the reach.
    Each query in its own row (``geometry.rows.interp_rows``: the result does not depend on
    the other rows of the batch).
    """
    xt, zt, reach = tables
    row = np.asarray(row)
    xq = np.asarray(x, float)
    out = interp_rows(xt, zt, np.minimum(xq, reach[row]), row)
    return np.where(xq > reach[row] * (1 + 1e-12), np.inf, out)


def gap_heights(tables, ind, side, w, kappa, allowance):
    """Material height at the middle of the gap between a pass and its neighbour (mm).

    ind: (m,) individual (table) index; side: (m,) +1 if the gap lies on the +b side of the
    tool in its travel frame, else -1; w: (m,) CC spacing across the feed on the surface;
    kappa: (m,) curvature across the feed (> 0 concave).

    Zig-zag passes alternate their travel direction, so the neighbour's tool is the mirror
    image of this one and the two profiles meet on the bisector: the near pair gives
    f_side(w/2) - kappa w^2/8. The passes one further out (at 3w/2, other side) can cut
    lower there (a flat-end tilted across the feed leaves the gap to them); the material
    left is the lower of the two. Surface curvature enters to second order (the surface
    rises kappa x^2/2 above each contact's tangent plane). The result is capped at the
    finishing ``allowance`` (an uncut strip leaves the whole stock). Negative: gouge.
    """
    base = 2 * np.asarray(ind)
    near_row = base + (np.asarray(side) < 0)
    far_row = base + (np.asarray(side) > 0)
    half = 0.5 * np.asarray(w, float)
    with np.errstate(invalid="ignore"):
        near = profile_height(tables, near_row, half) - 0.5 * kappa * half * half
        far = profile_height(tables, far_row, 3 * half) - 4.5 * kappa * half * half
    return np.minimum(np.minimum(near, far), allowance)
