"""Shared pieces of the strategies whose passes are curves: the cross-feed width that
leaves h_c, a step across the surface by a distance, runs of a mask, arc resampling."""

from __future__ import annotations

import numpy as np

from ...cutters.profile_kernel import window_bottom
from ...geometry.rows import interp_rows
from ...geometry.surface import normal_curvature, unit_normal
from ..zoning.profile import profile_width, side_width
from ..zoning.stepover import ScallopTarget
from .walk_kernel import walk_rate

__all__ = ["cross_width", "profile_cross_width", "facing_width", "march", "runs", "resample", "zone_mask",
           "pass_frame", "extend_to_edge", "untangle", "cusp_heights"]


def _ray_to_box(x, d, reach: float):
    """The point where the ray x + s d (s > 0) leaves [0, 1]^2, or None beyond ``reach``."""
    s_hit = np.inf
    for k in range(2):
        if d[k] > 1e-15:
            s_hit = min(s_hit, (1.0 - x[k]) / d[k])
        elif d[k] < -1e-15:
            s_hit = min(s_hit, -x[k] / d[k])
    if not np.isfinite(s_hit) or s_hit * np.linalg.norm(d) > reach:
        return None
    return np.clip(x + max(s_hit, 0.0) * d, 0.0, 1.0)


def extend_to_edge(uv, reach: float = 0.25, eps: float = 1e-9):
    """The polyline uv (M, 2), its ends carried straight on (in the parameters, along the end
    segments) to the edge of [0, 1]^2 when they stop short of it (at most ``reach`` in u, v):
    an offset pass ends inside the footprint wherever the cross-feed is oblique to the
    edge, and would leave the triangle beyond it uncut."""
    if len(uv) < 2:
        return uv
    out = [uv]
    on = lambda x: bool(np.any((x <= eps) | (x >= 1 - eps)))
    if not on(uv[-1]):
        hit = _ray_to_box(uv[-1], uv[-1] - uv[-2], reach)
        if hit is not None:
            out.append(hit[None])
    if not on(uv[0]):
        hit = _ray_to_box(uv[0], uv[0] - uv[1], reach)
        if hit is not None:
            out.insert(0, hit[None])
    return np.concatenate(out)


def pass_frame(surface, uv):
    """(jet, n, t, b) along a pass polyline uv (M, 2): unit normal, travel tangent (central
    differences in the tangent plane), cross-feed tangent b = n x t."""
    jet = surface.jet(uv[:, 0], uv[:, 1], order=2)
    n = unit_normal(jet, surface.normal_sign)
    t = np.gradient(jet.p, axis=0) if len(uv) > 1 else np.tile([1.0, 0, 0], (len(uv), 1))
    t -= np.einsum("ij,ij->i", t, n)[:, None] * n
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
    return jet, n, t, np.cross(n, t)


def cross_width(surface, cutter, h_c, jet, t, b, lead_tilt=None):
    """CC spacing (mm, on the surface along b) that leaves a cusp of exactly h_c.

    3-axis (``lead_tilt`` None): the vertical cutter's exact swept profile in the
    cross-feed plane (``zoning/profile.profile_width``, the model the parallel planes are
    spaced by), capped by the cutter's width at h_c. 5-axis (lead, tilt radians): the
    projected profile of the cutter swept at that lead and tilt against the normal curvature
    kappa across the feed (:func:`profile_cross_width`: the model the analytic criteria judge
    a 5-axis plan by), capped the same way."""
    kappa = normal_curvature(jet, b, surface.normal_sign)
    target = ScallopTarget(cutter, float(h_c))
    if lead_tilt is None:
        w = profile_width(target, t[:, 2], b[:, 2], kappa)
    else:
        w = profile_cross_width(cutter, h_c, kappa, *lead_tilt)
    return np.minimum(w, target.width_cap)


def profile_cross_width(cutter, h_c, kappa, lead, tilt, grid: int = 64,
                        iterations: int = 40) -> np.ndarray:
    """5-axis: the CC spacing w (mm, across the feed on the surface) at which two passes of
    ``cutter`` swept at ``lead`` / ``tilt`` (radians) leave a cusp of exactly h_c on a
    section of normal curvature ``kappa`` (k,) (> 0 concave): f(w/2) - kappa (w/2)^2 / 2 =
    h_c, with f the cutter's projected profile across the feed (``Cutter.swept_profile``),
    the near pair of ``criteria/scallop.gap_heights``. With a tilt the profile's two sides
    differ and the pass's travel (zig-zag or not) decides which one faces the gap: the
    narrower width of the two is taken.

    The first offset where the cusp reaches h_c: a scan of ``grid`` offsets up to the
    profile's reach (and half the cutter's width at h_c), then bisection in that cell, the
    width returned on the side under h_c. Where the cusp stays under h_c up to there (a
    section concave enough), the width is twice that limit.

    It replaces the circle of the lead/tilt effective radius, which a toroidal cutter's
    profile (an offset ellipse) leaves above the circle away from the contact: by it, the
    torus D16 r3's iso-scallop plan of Fountas' part at lead 10 deg had an analytic scallop
    max of 0.0208 against h_c 0.02 (0.0200 now, ``tests/problems/toolpath/test_strategies.py``)."""
    kappa = np.atleast_1d(np.asarray(kappa, float))
    n = len(kappa)
    xt, zt, reach = cutter.swept_profile(np.array([float(lead)]), np.array([float(tilt)]))
    cap = float(cutter.width(float(h_c)))  # half the cutter's width at h_c
    half = np.full(n, np.inf)
    for row in (0, 1):
        x_max = min(float(reach[row]), cap)
        xs = np.linspace(0.0, x_max, grid + 1)[1:]

        def excess(x, k):  # the cusp over h_c at half-spacing x, rows k of kappa
            return interp_rows(xt, zt, x, np.full(len(x), row)) - 0.5 * kappa[k] * x * x - h_c

        over = excess(np.tile(xs, n), np.repeat(np.arange(n), grid)).reshape(n, grid) >= 0
        found = over.any(axis=1)
        k = np.argmax(over, axis=1)
        lo = np.where(k > 0, xs[np.maximum(k - 1, 0)], 0.0)
        hi = xs[k]
        idx = np.arange(n)
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            under = excess(mid, idx) < 0
            lo, hi = np.where(under, mid, lo), np.where(under, hi, mid)
        half = np.minimum(half, np.where(found, lo, x_max))
    return 2.0 * half


def facing_width(surface, cutter, h_c, jet, t, b) -> np.ndarray:
    """3-axis: the half-width (mm, along +b) of a vertical cutter's cusp of h_c on the +b
    side of each contact (``zoning/profile.side_width``: the exact profile of that side,
    the curvature across the feed to second order). Two passes are spaced by the sum of
    their facing sides, each in its own frame: the torus's two sides differ (corner arc
    uphill, flat bottom downhill) and change with the slope from one pass to the next."""
    kappa = normal_curvature(jet, b, surface.normal_sign)
    return side_width(ScallopTarget(cutter, float(h_c)), t[:, 2], b[:, 2], kappa)


def cusp_heights(surface, cutter, uv, nxt, b, w, samples: int = 9, reach: int = 4):
    """3-axis: the material a vertical cutter leaves between a pass uv (M, 2) and its
    offset nxt (M, 2), measured the way the cut simulation does: at ``samples`` points on
    the surface between each pair (a walk along b by fractions of w), the lower of the two
    passes' swept bottoms (each pass's tool, tangent at its CC points, at the 2 reach + 1
    positions around the pair: the sweep along the feed) above the surface, along the
    normal; the largest per pair (M,). The width models assume each cross-section is one
    curvature and each pass straight; this check holds on ridges and bends."""
    m = len(uv)
    prm = cutter.kernel_params()
    envs = []
    for pts in (uv, nxt):
        j = surface.jet(pts[:, 0], pts[:, 1], order=1)
        n = unit_normal(j, surface.normal_sign)
        if pts is uv:
            js, ns = j, n  # where the walk starts
        envs.append(np.ascontiguousarray(cutter.cc_to_tip(j.p, n)))  # (M, 3)
    gap = np.full(m, -np.inf)
    s_uv, d = uv, b
    h = (np.asarray(w / (samples + 1), float))[:, None]
    for _ in range(samples):  # one midpoint step from sample to sample (``march``, one
        # substep), the jet at each sample serving both its check and the next step
        k1, d = _velocity(js, ns, d)
        x = s_uv + 0.5 * h * k1
        jm = surface.jet(x[:, 0], x[:, 1], order=1)
        k2, d = _velocity(jm, unit_normal(jm, surface.normal_sign), d)
        s_uv = s_uv + h * k2
        js = surface.jet(s_uv[:, 0], s_uv[:, 1], order=1)
        ns = unit_normal(js, surface.normal_sign)
        at = np.ascontiguousarray(js.p)
        low = np.minimum(*(window_bottom(at, tips, reach, prm) for tips in envs))
        gap = np.maximum(gap, (low - js.p[:, 2]) * np.abs(ns[:, 2]))
    return gap


def _velocity(j, n, d):
    """The (u, v) rate of a unit-speed walk along the tangent direction d (M, 3) at the
    jet j with unit normal n, and d projected onto the tangent plane there (unit):
    ``walk_kernel.walk_rate``."""
    return walk_rate(j.su, j.sv, n, d)


def march(surface, uv, direction, dist, substeps: int = 2):
    """(u, v) reached from uv (M, 2) by walking ``dist`` (M,) mm on the surface along the
    tangent ``direction`` (M, 3): ``substeps`` midpoint (second-order) steps, the direction
    re-projected onto the tangent plane where each velocity is taken (the parameters may
    leave [0, 1]: the surface's extension is evaluated there). A first-order (Euler) step
    overshoots where the metric changes along the walk (1.5 % over 2.4 mm on a 28 deg slope
    of a cylinder of radius 20 mm)."""

    def velocity(x, d):
        j = surface.jet(x[:, 0], x[:, 1], order=1)
        return _velocity(j, unit_normal(j, surface.normal_sign), d)

    x = uv.copy()
    d = direction.copy()
    h = (np.asarray(dist, float) / substeps)[:, None]
    for _ in range(substeps):
        k1, d = velocity(x, d)
        k2, d_mid = velocity(x + 0.5 * h * k1, d)
        x = x + h * k2
        d = d_mid
    return x


def untangle(uv, eps: float = 1e-12, crossings: list | None = None):
    """The polyline uv (M, 2) with its loops cut out: wherever segment i crosses a later,
    non-adjacent segment j, the points between them are replaced by the crossing point
    (the farthest j first: the whole swallowtail an offset forms where the previous pass
    bends towards its offsets). All segment pairs are tested at once (M^2 / 2 pairs: a
    pass holds a few hundred points). ``crossings``: a list that receives, per cut, the
    crossing point kept (the sharp corner the cut leaves) and the middle index of the
    points cut out: ((2,), int)."""
    m = len(uv) - 1
    if m < 3:
        return uv
    a, d = uv[:-1], np.diff(uv, axis=0)
    i, j = np.triu_indices(m, 2)
    den = d[i, 0] * d[j, 1] - d[i, 1] * d[j, 0]
    ok = np.abs(den) > eps
    i, j, den = i[ok], j[ok], den[ok]
    w = a[j] - a[i]
    s = (w[:, 0] * d[j, 1] - w[:, 1] * d[j, 0]) / den
    t = (w[:, 0] * d[i, 1] - w[:, 1] * d[i, 0]) / den
    hit = (s >= 0) & (s < 1) & (t >= 0) & (t < 1)
    if not hit.any():
        return uv
    i, j, s = i[hit], j[hit], s[hit]
    far = np.full(m, -1)
    np.maximum.at(far, i, j)
    s_at = {(int(x), int(y)): float(z) for x, y, z in zip(i, j, s)}
    out, k = [uv[0]], 0
    while k < m:
        if far[k] > k:
            out.append(a[k] + s_at[(k, int(far[k]))] * d[k])
            if crossings is not None:
                crossings.append((out[-1], (k + 1 + int(far[k])) // 2))
            k = int(far[k])
        out.append(uv[k + 1])
        k += 1
    return np.asarray(out)


def side_of(xy):
    """(M, 3) the unit horizontal directions to the left of the XY polyline ``xy`` (M, 2),
    the last segment's at the last point: the cross-feed of a pass cut along it (corner
    passes, which no scallop is measured against)."""
    seg = np.diff(xy, axis=0)
    side = np.column_stack([-seg[:, 1], seg[:, 0]])
    side = np.vstack([side, side[-1:]])
    side /= np.maximum(np.linalg.norm(side, axis=1, keepdims=True), 1e-300)
    return np.column_stack([side, np.zeros(len(xy))])


def runs(mask):
    """[(a, b)]: the maximal stretches mask[a:b] that are True."""
    m = np.r_[False, np.asarray(mask, bool), False]
    edges = np.flatnonzero(m[1:] != m[:-1])
    return list(zip(edges[::2], edges[1::2]))


def resample(surface, uv, ds: float):
    """The polyline uv (M, 2) resampled every ~ds mm of its surface arc (ends kept)."""
    if len(uv) < 2:
        return uv
    p = surface.jet(uv[:, 0], uv[:, 1], order=0).p
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]
    k = max(int(np.ceil(arc[-1] / ds)), 1)
    s = np.linspace(0.0, arc[-1], k + 1)
    return np.column_stack([np.interp(s, arc, uv[:, 0]), np.interp(s, arc, uv[:, 1])])


def zone_mask(labels, z, uv):
    """Whether each (u, v) lies in a mesh cell of zone z (and in [0, 1]^2)."""
    n, m = labels.shape
    inside = np.all((uv >= 0) & (uv <= 1), axis=1)
    i = np.clip((uv[:, 0] * n).astype(np.int64), 0, n - 1)
    j = np.clip((uv[:, 1] * m).astype(np.int64), 0, m - 1)
    return inside & (labels[i, j] == z)
