"""Effective cutting radius R_eff of flat-end, toroidal and ball-end cutters.

R_eff is the radius of curvature, at the contact point, of the tool's silhouette projected
along the feed onto the plane normal to the feed (Redonnet et al. 2013; Djebali et al.
Sec. 2.2). The forms below are the ones ``docs/toolpath_formulas.md`` verified; Fountas Eq. 4 is
kept only for comparison (it agrees at tilt 0 and is wrong with tilt).

Notation: R cutter radius, r corner radius (0 flat-end, R ball, between: toroidal),
a unit tool axis, t unit feed tangent, n unit surface normal (tool side).

Accuracy (docs/toolpath_formulas.md): against a Z-map of the swept tool, the R_eff circle is
within 2-4 % for ball-end tools but only approximate (15-30 % off) for flat-end and toroidal
tools, whose true cross-feed profile is an ellipse (offset by r). The engine therefore
computes scallops from the exact projected profile (``silhouette.py``), whose curvature at
the contact is this R_eff; R_eff itself is reported as a criterion. The cutter methods
(``Cutter.effective_radius*``) call these functions; batched users (one row per tool) call
them with arrays of R and r.

Degenerate cases, guarded (never a division by zero):
- the bottom plane parallel to the surface (a = n, r < R): R_eff = inf (the flat cuts);
- the rim plane containing the feed (a.t = 0, a != n): R_eff = r (rim-only: 0 for a
  flat-end).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "effective_radius",
    "effective_radius_lead_tilt",
    "effective_radius_3axis",
    "effective_radius_fountas_eq4",
]

_EPS = 1e-14


def effective_radius(R, r, a_dot_t, a_dot_n):
    """General form: R_eff = (R - r) (a.t)^2 / (1 - (a.n)^2)^(3/2) + r (docs/toolpath_formulas.md).

    Arrays broadcast; returns inf where the flat bottom cuts (a = n and r < R).
    """
    R, r, at, an = np.broadcast_arrays(*(np.asarray(x, float) for x in (R, r, a_dot_t, a_dot_n)))
    s2 = np.maximum(1.0 - an * an, 0.0)  # sin^2 of the axis-normal angle
    flat = (s2 <= _EPS) & (R - r > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        val = (R - r) * at * at / np.where(flat, 1.0, np.maximum(s2, _EPS)) ** 1.5 + r
    return np.where(flat, np.inf, val)


def effective_radius_lead_tilt(R, r, lead, tilt):
    """5-axis: lead aL (about the cross-feed axis) then tilt aT (about the feed), radians.

    R_eff = (R - r) sin^2(aL) / (1 - cos^2(aL) cos^2(aT))^(3/2) + r
    (the general form with a.t = sin aL, a.n = cos aL cos aT). Flat-end at tilt 0:
    R / sin(aL). Lead = tilt = 0: inf (flat bottom); lead 0, tilt > 0: r (rim only).
    """
    lead = np.asarray(lead, float)
    tilt = np.asarray(tilt, float)
    return effective_radius(R, r, np.sin(lead), np.cos(lead) * np.cos(tilt))


def effective_radius_3axis(R, r, slope, feed_angle, steepest_angle):
    """3-axis torus, tool axis = z (Djebali et al., Eq. 1), angles in radians.

    R_eff = (R - r) cos^2(alpha - phi) / (sin S (1 - sin^2(alpha - phi) sin^2 S)) + r
    with S the slope angle, phi the steepest-slope direction, alpha the horizontal feed
    direction. Horizontal ground (S = 0): inf for r < R (the flat bottom cuts).
    """
    R, r, S, al, ph = np.broadcast_arrays(
        *(np.asarray(x, float) for x in (R, r, slope, feed_angle, steepest_angle)))
    d = al - ph
    sin_s = np.abs(np.sin(S))
    den = sin_s * (1.0 - np.sin(d) ** 2 * sin_s ** 2)
    flat = (sin_s <= _EPS) & (R - r > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        val = (R - r) * np.cos(d) ** 2 / np.where(flat, 1.0, den) + r
    return np.where(flat, np.inf, val)


def effective_radius_fountas_eq4(R, r, lead, tilt):
    """Fountas Eq. 4 AS PRINTED (radians), for comparison only: wrong when tilt != 0.

    R_eff = (R - r) cos^2 aT / (sin aL (1 - sin^2 aT sin^2 aL)) + r (r = 0 flat-end, R ball).
    """
    R, r, lead, tilt = np.broadcast_arrays(*(np.asarray(x, float) for x in (R, r, lead, tilt)))
    with np.errstate(divide="ignore"):
        val = (R - r) * np.cos(tilt) ** 2 / (
            np.sin(lead) * (1 - np.sin(tilt) ** 2 * np.sin(lead) ** 2)) + r
    return np.where(R - r <= 0, R, val)
