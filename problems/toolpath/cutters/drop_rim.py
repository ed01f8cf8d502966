"""Rim contacts of the drop-cutter (``drop.py``, candidates B and C), for profiles of finite
slope at the rim (the flat-end): the highest point of the surface on the rim circle, and
the rim's crossings with the patch edges. Both go through the XY of the surface: the rim
circle through the inverse map XY -> (u, v), the edges as the grid's boundary segments.
"""

from __future__ import annotations

import numpy as np

from ..geometry.footprint import footprint_of
from .surface_grid import uv_at_xy

__all__ = ["group_argmax", "rim_candidates", "edge_candidates"]


def group_argmax(key, val, n):
    """Index of the largest ``val`` of each key in 0..n-1 (-1 where a key has none).

    O(len) when ``key`` is non-decreasing (the grouped neighbour lists); a sort otherwise.
    """
    out = np.full(n, -1, np.int64)
    if len(key) == 0:
        return out
    if np.all(key[1:] >= key[:-1]):
        start = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
        top = np.maximum.reduceat(val, start)
        hit = np.flatnonzero(val == np.repeat(top, np.diff(np.r_[start, len(key)])))
        first = hit[np.r_[True, key[hit[1:]] != key[hit[:-1]]]]
        out[key[first]] = first
        return out
    order = np.lexsort((val, key))
    ks = key[order]
    last = np.flatnonzero(np.r_[ks[1:] != ks[:-1], True])
    out[ks[last]] = order[last]
    return out


def rim_candidates(cutter, surface, grid, c, g_rim, iterations=60):
    """Candidates B: the highest point of z on the rim circle, per query (k,).

    z is sampled on the circle about one grid spacing apart (through the inverse map;
    points outside the footprint are -inf), then a golden-section search refines the best
    sample between its two neighbours.
    """
    big, k = cutter.radius, len(c)
    m = max(32, int(np.ceil(2 * np.pi * big / grid.spacing)))
    dth = 2 * np.pi / m
    th = np.arange(m) * dth
    p = (c[:, None, :] + big * np.stack([np.cos(th), np.sin(th)], 1)[None]).reshape(-1, 2)
    near = grid.tree.query(p)[1]
    uv, ok = uv_at_xy(surface, p, np.stack([grid.u[near], grid.v[near]], 1))
    ok &= footprint_of(surface).contains(uv[:, 0], uv[:, 1])  # a trimmed face: not in a hole
    z = np.where(ok, surface.jet(uv[:, 0], uv[:, 1], order=0).p[:, 2], -np.inf).reshape(k, m)
    j = np.argmax(z, axis=1)
    rows = np.arange(k)
    best_z, best_uv = z[rows, j], uv.reshape(k, m, 2)[rows, j]

    def value(theta, uv0):
        q = c + big * np.stack([np.cos(theta), np.sin(theta)], 1)
        uv_q, ok_q = uv_at_xy(surface, q, uv0)
        return np.where(ok_q, surface.jet(uv_q[:, 0], uv_q[:, 1], order=0).p[:, 2], -np.inf), uv_q

    gr = 0.5 * (np.sqrt(5.0) - 1.0)
    lo, hi = th[j] - dth, th[j] + dth
    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1, uv1 = value(x1, best_uv)
    f2, uv2 = value(x2, best_uv)
    for _ in range(iterations):
        left = f1 >= f2  # keep [lo, x2], else [x1, hi]
        hi, lo = np.where(left, x2, hi), np.where(left, lo, x1)
        xn = np.where(left, hi - gr * (hi - lo), lo + gr * (hi - lo))
        fn, uvn = value(xn, np.where(left[:, None], uv1, uv2))
        lf, l2 = left, left[:, None]
        x1, x2 = np.where(lf, xn, x2), np.where(lf, x1, xn)
        f1, f2 = np.where(lf, fn, f2), np.where(lf, f1, fn)
        uv1, uv2 = np.where(l2, uvn, uv2), np.where(l2, uv1, uvn)
    for f_c, uv_c in ((f1, uv1), (f2, uv2)):
        better = f_c > best_z
        best_z, best_uv = np.where(better, f_c, best_z), np.where(better[:, None], uv_c, best_uv)
    return best_uv, best_z - g_rim


def edge_candidates(cutter, surface, grid, xy, g_rim, iterations=50):
    """Candidates C: crossings of the rim circle with the patch edges, per query (k,);
    and per query the best edge point nearest the axis inside the disk (a Newton seed).

    Returns (uv (k, 2), value (k,), seed uv (k, 2), seed value (k,)); -inf where none.
    """
    big = cutter.radius
    lists = grid.seg_tree.query_ball_point(xy, big + grid.seg_reach)
    counts = np.fromiter(map(len, lists), np.int64, len(lists))
    best_val = np.full(len(xy), -np.inf)
    best_uv = np.full((len(xy), 2), np.nan)
    seed_val, seed_uv = best_val.copy(), best_uv.copy()
    if counts.sum() == 0:
        return best_uv, best_val, seed_uv, seed_val
    seg = np.concatenate([np.asarray(x, np.int64) for x in lists])
    q = np.repeat(np.arange(len(xy)), counts)
    ends = grid.seg_xy[seg]
    phi = np.linalg.norm(ends - xy[q][:, None, :], axis=-1) - big
    # split each segment at the point of its chord nearest the axis: a disk that cuts the
    # segment between its ends has one crossing on each side of it
    chord = ends[:, 1] - ends[:, 0]
    lam = np.clip(np.einsum("ij,ij->i", xy[q] - ends[:, 0], chord)
                  / np.maximum(np.einsum("ij,ij->i", chord, chord), 1e-300), 0.0, 1.0)
    a, b = grid.seg_uv[seg, 0], grid.seg_uv[seg, 1]
    uv_m = a + lam[:, None] * (b - a)
    p_m = surface.jet(uv_m[:, 0], uv_m[:, 1], order=0).p
    rho_m = np.linalg.norm(p_m[:, :2] - xy[q], axis=1)
    phi_m = rho_m - big
    f_m = p_m[:, 2] - cutter.height(rho_m)
    arg = group_argmax(q[phi_m < 0], f_m[phi_m < 0], len(xy))
    has = arg >= 0
    inner = np.flatnonzero(phi_m < 0)
    seed_val[has], seed_uv[has] = f_m[inner[arg[has]]], uv_m[inner[arg[has]]]
    lo = np.concatenate([np.zeros(len(seg)), lam])
    hi = np.concatenate([lam, np.ones(len(seg))])
    f_lo = np.concatenate([phi[:, 0], phi_m])
    f_hi = np.concatenate([phi_m, phi[:, 1]])
    keep = (f_lo * f_hi <= 0) & (hi > lo)
    q, a, b = np.tile(q, 2)[keep], np.tile(a, (2, 1))[keep], np.tile(b, (2, 1))[keep]
    lo, hi, sign_lo = lo[keep], hi[keep], np.sign(f_lo[keep])
    if len(q) == 0:
        return best_uv, best_val, seed_uv, seed_val
    for _ in range(iterations):
        m = 0.5 * (lo + hi)
        uv = a + m[:, None] * (b - a)
        p = surface.jet(uv[:, 0], uv[:, 1], order=0).p
        same = np.sign(np.linalg.norm(p[:, :2] - xy[q], axis=1) - big) == sign_lo
        lo, hi = np.where(same, m, lo), np.where(same, hi, m)
    # the end inside the disk (rho <= R) is feasible
    t = np.where(sign_lo <= 0, lo, hi)
    uv = a + t[:, None] * (b - a)
    val = surface.jet(uv[:, 0], uv[:, 1], order=0).p[:, 2] - g_rim
    arg = group_argmax(q, val, len(xy))
    has = arg >= 0
    best_val[has], best_uv[has] = val[arg[has]], uv[arg[has]]
    return best_uv, best_val, seed_uv, seed_val
