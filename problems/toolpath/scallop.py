"""Scallop height between adjacent passes, and the step-over it allows.

Two models:

1. The effective-radius (osculating circle) model of the papers, exact circle geometry:
   :func:`scallop_height` (flat, convex, concave), :func:`flat_scallop`, and the spacings of
   Djebali et al. Sec. 2.3 (:func:`stepover_djebali_eq2`, :func:`spacing_exact`).
2. The projected-profile model the simulator uses (:func:`profile_tables`,
   :func:`gap_heights`): the cutter is projected along the feed onto the plane normal to the
   feed, exactly (for a straight move this is the cross-section of the swept volume): the
   rim circle projects to an ellipse (a segment when the rim plane contains the feed), and
   the corner torus adds an offset r. Its curvature at the contact is R_eff (checked in the
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

from .effective_radius import effective_radius_lead_tilt

__all__ = [
    "flat_scallop",
    "scallop_height",
    "stepover_djebali_eq2",
    "spacing_exact",
    "spacing_flat_approx",
    "profile_tables",
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
# Projected-profile model (used by the simulator)
# -------------------------------------------------------------------------------------

def profile_tables(R, r, lead, tilt, m_fine: int = 192, m_uniform: int = 64,
                   m_ellipse: int = 256):
    """Cross-feed profile of the cutter on both sides of the contact point.

    R, r, lead, tilt: (n,) (mm, radians; lead about the cross-feed axis b, then tilt about
    the feed t, the axis leaning towards +b). In the travel frame (t, b, n) the axis is
    a = (sin aL, cos aL sin aT, cos aL cos aT). The rim circle (radius R - r, plane normal to
    a) projects along t to an ellipse E = M (unit disk) in the (b, n) plane (a segment when
    the rim plane contains t); the profile is the lower boundary of E + disk(r). Its points
    are sampled exactly in two ways and merged by x:

    - by outward normal nu = (sin p, -cos p): point(p) = G nu / sqrt(nu' G nu) + r nu,
      G = M M' (robust for segments and points); p = 0 is the contact point (for a flat
      bottom parallel to the surface: the bottom centre, the CC point of the tool axis);
      p clustered as arcsin(sigma / R_eff), sigma uniform in [0, R], plus a uniform set;
    - by the ellipse's own parameter theta (x spacing <= (R - r) 2 pi / m_ellipse): point
      M (cos th, sin th) + r nu(th) on the lower half.

    Returns (x, z, reach): x, z (2n, m) height z above the tangent plane at offset x >= 0
    (x ascending), rows 2i (+b side) and 2i+1 (-b side, mirrored); reach (2n,) the last x
    (the profile is vertical beyond: nothing is cut there).
    """
    R, r, lead, tilt = (np.atleast_1d(np.asarray(x, float)) for x in (R, r, lead, tilt))
    n = len(R)
    a = np.stack([np.sin(lead), np.cos(lead) * np.sin(tilt), np.cos(lead) * np.cos(tilt)], -1)
    e1 = np.array([1.0, 0.0, 0.0]) - a[:, :1] * a
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    e2 = np.cross(a, e1)
    rim = (R - r)[:, None]
    mb = np.stack([e1[:, 1], e2[:, 1]], -1) * rim  # (n, 2): b row of M
    mn = np.stack([e1[:, 2], e2[:, 2]], -1) * rim  # n row
    g_bb = (mb * mb).sum(-1)[:, None]
    g_bn = (mb * mn).sum(-1)[:, None]
    g_nn = (mn * mn).sum(-1)[:, None]
    tiny_len = 1e-12 * np.maximum(R[:, None], 1.0)
    # 1. samples by outward normal (support points), both sides
    r_eff = effective_radius_lead_tilt(R, r, lead, tilt)
    sig = np.linspace(0.0, 1.0, m_fine)[None, :] * R[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = sig / r_eff[:, None]  # 0/0 (rim-only, sigma 0) -> nan -> 0
    p_fine = np.arcsin(np.minimum(np.where(np.isnan(ratio), 0.0, ratio), 1.0))
    p_uni = np.broadcast_to(np.linspace(0.0, np.pi / 2, m_uniform), (n, m_uniform))
    ph = np.concatenate([p_fine, p_uni, -p_fine, -p_uni], axis=1)
    nb, nn = np.sin(ph), -np.cos(ph)
    gb = g_bb * nb + g_bn * nn  # G nu
    gn = g_bn * nb + g_nn * nn
    q = np.sqrt(np.maximum(nb * gb + nn * gn, 0.0))
    tiny = q <= tiny_len
    iq = np.where(tiny, 0.0, 1.0 / np.where(tiny, 1.0, q))
    pb = gb * iq + r[:, None] * nb
    pn = gn * iq + r[:, None] * nn
    cb, cn = pb[:, :1], pn[:, :1]  # contact point (p = 0)
    ok = np.ones(pb.shape, bool)
    # 2. samples by the ellipse's parameter, lower half
    th = np.linspace(0.0, 2 * np.pi, m_ellipse, endpoint=False)
    cos_t, sin_t = np.cos(th)[None, :], np.sin(th)[None, :]
    eb = mb[:, :1] * cos_t + mb[:, 1:] * sin_t  # ellipse point
    en = mn[:, :1] * cos_t + mn[:, 1:] * sin_t
    db = -mb[:, :1] * sin_t + mb[:, 1:] * cos_t  # tangent
    dn = -mn[:, :1] * sin_t + mn[:, 1:] * cos_t
    dl = np.hypot(db, dn)
    valid = dl > tiny_len
    vb, vn = dn / np.where(valid, dl, 1.0), -db / np.where(valid, dl, 1.0)
    out = vb * eb + vn * en  # > 0 when (vb, vn) points outwards
    proper = np.abs(out) > tiny_len * np.maximum(rim, 1e-300)
    flip = np.where(proper, np.sign(out), -np.sign(vn + (vn == 0)))  # segment: downwards
    vb, vn = vb * flip, vn * flip
    valid &= vn < 0
    pb = np.concatenate([pb, eb + r[:, None] * vb], axis=1)
    pn = np.concatenate([pn, en + r[:, None] * vn], axis=1)
    ok = np.concatenate([ok, valid], axis=1)
    xb, zn = pb - cb, np.maximum(pn - cn, 0.0)
    rows = []
    for side in (1.0, -1.0):
        use = ok & (side * xb >= 0)
        x = np.where(use, side * xb, 0.0)
        z = np.where(use, zn, 0.0)
        order = np.argsort(x, axis=1, kind="stable")
        rows.append((np.take_along_axis(x, order, 1), np.take_along_axis(z, order, 1)))
    x = np.stack([rows[0][0], rows[1][0]], axis=1).reshape(2 * n, -1)
    z = np.stack([rows[0][1], rows[1][1]], axis=1).reshape(2 * n, -1)
    z = np.maximum.accumulate(z, axis=1)  # round-off only: the profile rises from the contact
    return x, z, x[:, -1].copy()


def profile_height(tables, row, x):
    """Profile height at offsets x >= 0 on table rows ``row`` (one query per element).

    tables: (x, z, reach) from :func:`profile_tables`; returns inf beyond the reach.
    One np.interp over all rows (rows are laid end to end with offsets).
    """
    xt, zt, reach = tables
    span = float(np.max(reach)) + 1.0
    off = np.arange(xt.shape[0]) * span
    xq = np.asarray(x, float)
    out = np.interp(np.minimum(xq, reach[row]) + off[row], (xt + off[:, None]).ravel(), zt.ravel())
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
