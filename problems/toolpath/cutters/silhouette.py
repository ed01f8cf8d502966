"""The silhouette (swept cross-section) of a cutter: exact for the torus family, and from the
support points for any other shape.

A straight move of a cutter sweeps a cylinder whose cross-section, in the plane normal to the
feed t, is the cutter projected along t: its silhouette. The flat-end, toroidal and ball-end
cutters (``shapes.py``) are the rim disk (radius R0 = R - r, normal to the axis a) plus a ball
of radius r, so their silhouette is the projected rim, an ellipse E = M (unit disk) (a segment
when the rim plane contains t, a point for the ball), offset by r. With G = M M', the point of
E + disk(r) whose outward unit normal is nu is

    Q(nu) = G nu / sqrt(nu' G nu) + r nu                                  (*)

(the support point of E along nu plus r nu; Redonnet et al. 2013, Djebali et al. Sec. 2.2).
Its curvature at the contact point is the effective radius R_eff (Djebali Eq. 1 in 3-axis,
its general lead/tilt form in 5-axis; ``effective_radius.py``), but (*) stays exact where the
circle of radius R_eff does not: a flat bottom, a rim that cuts, a cusp past the corner arc.

- :func:`silhouette_point`: (*), batched; the one implementation.
- :func:`profile_tables`: 5-axis, lead/tilt, the profile on both sides of the contact as
  tables (the analytic criteria's 5-axis scallops, ``criteria/scallop.py``).
- :func:`side_width_exact`: 3-axis, vertical axis, the lateral offset where the profile rises
  to a height (the zoning's step-over, ``zoning/profile.py``).
- :func:`support_profile_tables`, :func:`support_side_width`: the same two for any cutter,
  the silhouette point of outward normal nu being its support point along nu
  (``Cutter.support_point``; the defaults of ``Cutter.swept_profile`` and
  ``Cutter.swept_side_width``).
"""

from __future__ import annotations

import numpy as np

from .effective_radius import effective_radius_lead_tilt

__all__ = ["silhouette_point", "profile_tables", "side_width_exact", "support_profile_tables",
           "support_side_width"]


def silhouette_point(g_xx, g_xy, g_yy, r, nx, ny, tiny=0.0):
    """Point (x, y) of the silhouette with outward unit normal nu = (nx, ny): Eq. (*) of the
    module docstring, Q = G nu / sqrt(nu' G nu) + r nu, G = [[g_xx, g_xy], [g_xy, g_yy]] the
    Gram matrix of the projected rim in a frame (x, y) of the plane normal to the feed.

    Where sqrt(nu' G nu) <= ``tiny`` (the ball: G = 0; a segment seen edge-on) the rim adds
    nothing and Q = r nu. Arrays broadcast.
    """
    gx = g_xx * nx + g_xy * ny  # G nu
    gy = g_xy * nx + g_yy * ny
    q = np.sqrt(np.maximum(nx * gx + ny * gy, 0.0))
    small = q <= tiny
    iq = np.where(small, 0.0, 1.0 / np.where(small, 1.0, q))
    return gx * iq + r * nx, gy * iq + r * ny


def profile_tables(R, r, lead, tilt, m_fine: int = 192, m_uniform: int = 64,
                   m_ellipse: int = 256):
    """5-axis: cross-feed profile of the cutter on both sides of the contact point.

    R, r, lead, tilt: (n,) (mm, radians; lead about the cross-feed axis b, then tilt about
    the feed t, the axis leaning towards +b). In the travel frame (t, b, n) the axis is
    a = (sin aL, cos aL sin aT, cos aL cos aT). The rim circle (radius R - r, plane normal to
    a) projects along t to an ellipse E = M (unit disk) in the (b, n) plane (a segment when
    the rim plane contains t); the profile is the lower boundary of E + disk(r). Its points
    are sampled exactly in two ways and merged by x:

    - by outward normal nu = (sin p, -cos p): :func:`silhouette_point`, Eq. (*) (robust
      for segments and points); p = 0 is the contact point (for a flat bottom parallel to
      the surface: the bottom centre, the CC point of the tool axis); p clustered as
      arcsin(sigma / R_eff), sigma uniform in [0, R], plus a uniform set;
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
    e2 = np.stack([a[:, 1] * e1[:, 2] - a[:, 2] * e1[:, 1], a[:, 2] * e1[:, 0] - a[:, 0] * e1[:, 2],
                   a[:, 0] * e1[:, 1] - a[:, 1] * e1[:, 0]], -1)  # a x e1 (np.cross's bits, less overhead)
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
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = sig / r_eff[:, None]  # 0/0 (rim-only, sigma 0) -> nan -> 0; tiny R_eff -> inf -> 1
    p_fine = np.arcsin(np.minimum(np.where(np.isnan(ratio), 0.0, ratio), 1.0))
    p_uni = np.broadcast_to(np.linspace(0.0, np.pi / 2, m_uniform), (n, m_uniform))
    ph = np.concatenate([p_fine, p_uni, -p_fine, -p_uni], axis=1)
    nb, nn = np.sin(ph), -np.cos(ph)
    pb, pn = silhouette_point(g_bb, g_bn, g_nn, r[:, None], nb, nn, tiny_len)
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
        order += np.arange(0, x.size, x.shape[1])[:, None]  # flat: np.take, not fancy indexing
        rows.append((np.take(x, order), np.take(z, order)))
    x = np.stack([rows[0][0], rows[1][0]], axis=1).reshape(2 * n, -1)
    z = np.stack([rows[0][1], rows[1][1]], axis=1).reshape(2 * n, -1)
    z = np.maximum.accumulate(z, axis=1)  # round-off only: the profile rises from the contact
    return x, z, x[:, -1].copy()


def side_width_exact(R, r, h, t_z, beta, iterations: int = 40):
    """3-axis: lateral offset (mm, >= 0) on the +b side where the profile rises to h; (N,).

    R, r, h: cutter radius, corner radius, height; t_z: |feed tangent z|; beta: angle of the
    cross-feed tangent to the horizontal in the plane normal to the feed (radians).
    The -b side is ``side_width_exact(..., -beta)`` (the mirror image).

    Vertical axis: in the plane normal to the feed t, with X the horizontal cross-feed
    direction and Y upwards, the rim projects to the ellipse of semi-axes a = R - r (X) and
    b = (R - r) |t_z| (Y), G = diag(a^2, b^2), and the profile point of outward normal
    nu = (cos psi, sin psi) is :func:`silhouette_point`. The surface's cross-section is the
    line through the contact at angle beta to X; the contact has psi_c = beta - pi/2. Height
    above the section: n . (Q - Q_c) at the lateral offset x = b . (Q - Q_c); it rises
    monotonically with psi on each side, so the offset at h is found by bisection in psi and a
    final linear interpolation (exact along the straight part of a segment). A side that
    never rises to h is limited to the tool's extent on that side.
    """
    t_z, beta = np.broadcast_arrays(np.asarray(t_z, float), np.asarray(beta, float))
    a = R - r
    b = a * np.abs(t_z)
    g_xx, g_yy = a * a, b * b  # the Gram matrix of the projected rim: diag(a^2, b^2)

    def point(psi):
        c, s = np.cos(psi), np.sin(psi)
        c = np.where(np.abs(c) < 1e-12, 0.0, c)  # a segment facing nu: its centre, not an end
        return silhouette_point(g_xx, 0.0, g_yy, r, c, s)
    return _side_width(point, h, beta, iterations)


def _side_width(point, h, beta, iterations):
    """The bisection of :func:`side_width_exact` for a silhouette given by its support
    point ``point(psi)`` (outward normal (cos psi, sin psi)); arrays broadcast with beta."""
    nx, ny = -np.sin(beta), np.cos(beta)
    tx, ty = np.cos(beta), np.sin(beta)
    psi_c = beta - 0.5 * np.pi
    qcx, qcy = point(psi_c)

    def height(psi):
        qx, qy = point(psi)
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


def support_side_width(cutter, h, t_z, beta, iterations: int = 40):
    """3-axis side width of any cutter from its support points (``Cutter.support_point``):
    :func:`side_width_exact`'s bisection in psi, the silhouette point of outward normal
    nu = (cos psi, sin psi) being the support point of the vertical cutter along
    d = cos psi X + sin psi Y, projected on the plane normal to the feed t = (c, 0, t_z)
    (X = (0, 1, 0) across the feed, Y = (-t_z, 0, c) upwards, c = sqrt(1 - t_z^2)). Where
    the support jumps across a straight stretch of the silhouette (a cone's generator), the
    final linear interpolation is exact."""
    h, t_z, beta = np.broadcast_arrays(*(np.asarray(x, float) for x in (h, t_z, beta)))
    tz = np.abs(t_z)
    c = np.sqrt(np.maximum(1.0 - tz * tz, 0.0))
    zero = np.zeros_like(tz)
    X = np.stack([zero, zero + 1.0, zero], -1)
    Y = np.stack([-tz, zero, c], -1)
    up = np.broadcast_to(np.array([0.0, 0.0, 1.0]), X.shape)

    def point(psi):
        d = np.cos(psi)[..., None] * X + np.sin(psi)[..., None] * Y
        q = cutter.support_point(up.reshape(-1, 3), d.reshape(-1, 3)).reshape(d.shape)
        return np.sum(q * X, -1), np.sum(q * Y, -1)
    return _side_width(point, h, beta, iterations)


def support_profile_tables(cutter, lead, tilt, m: int = 384):
    """5-axis profile tables (as :func:`profile_tables` returns them) of any cutter from its
    support points: in the travel frame (t, b, n) the axis is a = (sin aL, cos aL sin aT,
    cos aL cos aT); the silhouette point of outward normal nu = sin p b - cos p n is the
    support point along nu projected on (b, n), p = 0 the contact; m values of p from 0 to
    +-pi/2 on each side, three times denser at the contact than at the end. Consecutive samples are joined by
    straight lines, exact along a straight stretch (a cone's generator, across which the
    support point jumps) and within r (dp)^2 / 8 of a round one."""
    lead = np.atleast_1d(np.asarray(lead, float))
    tilt = np.broadcast_to(np.asarray(tilt, float), lead.shape)
    n = len(lead)
    a = np.stack([np.sin(lead), np.cos(lead) * np.sin(tilt), np.cos(lead) * np.cos(tilt)], -1)
    u = np.linspace(0.0, 1.0, m)
    p = 0.5 * np.pi * 0.5 * (u * u + u)  # denser at the contact
    out = []
    for side in (1.0, -1.0):
        ph = side * p
        d = np.stack([np.zeros_like(ph), np.sin(ph), -np.cos(ph)], -1)  # (m, 3) in (t, b, n)
        q = cutter.support_point(np.repeat(a, m, axis=0), np.tile(d, (n, 1))).reshape(n, m, 3)
        x = side * (q[..., 1] - q[:, :1, 1])
        z = np.maximum(q[..., 2] - q[:, :1, 2], 0.0)
        order = np.argsort(x, axis=1, kind="stable")
        x = np.maximum(np.take_along_axis(x, order, 1), 0.0)
        out.append((x, np.maximum.accumulate(np.take_along_axis(z, order, 1), axis=1)))
    x = np.stack([out[0][0], out[1][0]], axis=1).reshape(2 * n, -1)
    z = np.stack([out[0][1], out[1][1]], axis=1).reshape(2 * n, -1)
    return x, z, x[:, -1].copy()
