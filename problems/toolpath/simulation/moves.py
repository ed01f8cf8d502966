"""The sweep by moves over the grid: every cell, every feed move that can reach it.

The cells are visited tile by tile, row by row; each tile lists the moves whose reach (the
XY radius around the tip's segment within which the cutter can cut) touches it. For each
cell the move that gave the previous cell its deepest entry goes first (searched from that
cell's pose; the first cell of a row follows the row above), then the others nearest first
in XY. A move is skipped without computing any entry when a geometric bound
(:func:`_geo_bound`: the cutter lies above its tip plane and above its lower profile at the
ray's least distance from the axis) shows it cannot cut below the best entry found so far;
where the bound over the whole move fails, it is taken again over spans of the move
(:func:`_geo_spans`), which may still skip it or leave only a stretch [lo, hi] to search.
Otherwise the ends within that stretch are evaluated (a CL point's entry and gradient serve
both moves that meet there) and ``convex._move_min`` searches it. Each move remembers, within
a tile's row, where its search found its lowest entry in the last two cells and the
curvature there: the next cell's search starts from that pose extrapolated. The first move a
cell searches (no best entry yet, the whole move) starts there without its ends' entries,
unless that pose misses.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .convex import _HALF, _axis_rate, _curl, _move_min, _slope
from .kernel import INF, _entry, _ray, entry_gradient, piece_height

#: a move whose whole-move geometric bound fails is bounded again over this many spans
SPANS = 4


@njit(cache=True, nogil=True, error_model="numpy")
def _seg_dist2(px, py, x0, y0, x1, y1):
    """Squared XY distance from (px, py) to the segment (x0, y0) - (x1, y1)."""
    vx, vy = x1 - x0, y1 - y0
    vv = vx * vx + vy * vy
    lam = 0.0 if vv <= 0.0 else min(max(((px - x0) * vx + (py - y0) * vy) / vv, 0.0), 1.0)
    ex, ey = px - x0 - lam * vx, py - y0 - lam * vy
    return ex * ex + ey * ey


@njit(cache=True, error_model="numpy")
def tiles(x0, y0, h, ny, nx, ts, tip, mv_i, mv_j, mv_reach):
    """(ptr, moves): for every tile of ts x ts cells (row-major), the moves whose reach
    (distance from the tip's segment) can touch one of its cells."""
    ty, tx = (ny + ts - 1) // ts, (nx + ts - 1) // ts
    half = 0.5 * ts * h * math.sqrt(2.0)
    count = np.zeros(ty * tx + 1, np.int64)
    for rnd in range(2):
        if rnd == 1:
            for k in range(ty * tx):
                count[k + 1] += count[k]
            out = np.empty(count[ty * tx], np.int64)
            fill = count[:-1].copy()
        for m in range(mv_i.shape[0]):
            i, j = mv_i[m], mv_j[m]
            reach = mv_reach[m] + half
            lo_x = min(tip[i, 0], tip[j, 0]) - reach
            hi_x = max(tip[i, 0], tip[j, 0]) + reach
            lo_y = min(tip[i, 1], tip[j, 1]) - reach
            hi_y = max(tip[i, 1], tip[j, 1]) + reach
            kx0 = max(int(math.floor((lo_x - x0) / (ts * h))), 0)
            kx1 = min(int(math.floor((hi_x - x0) / (ts * h))), tx - 1)
            ky0 = max(int(math.floor((lo_y - y0) / (ts * h))), 0)
            ky1 = min(int(math.floor((hi_y - y0) / (ts * h))), ty - 1)
            for ky in range(ky0, ky1 + 1):
                cy = y0 + (ky * ts + 0.5 * (ts - 1)) * h
                for kx in range(kx0, kx1 + 1):
                    cx = x0 + (kx * ts + 0.5 * (ts - 1)) * h
                    if _seg_dist2(cx, cy, tip[i, 0], tip[i, 1], tip[j, 0], tip[j, 1]) > reach * reach:
                        continue
                    if rnd == 0:
                        count[ky * tx + kx + 1] += 1
                    else:
                        out[fill[ky * tx + kx]] = m
                        fill[ky * tx + kx] += 1
    return count, out


@njit(cache=True, nogil=True, error_model="numpy")
def _point(k, tip, axis, px, py, pz, dx, dy, dz, prm, g):
    t, face = _entry(px, py, pz, dx, dy, dz, tip[k, 0], tip[k, 1], tip[k, 2], axis[k, 0],
                     axis[k, 1], axis[k, 2], prm, INF)
    g[0], g[1], g[2], g[3], g[4], g[5] = entry_gradient(
        t, face, px, py, pz, dx, dy, dz, tip[k, 0], tip[k, 1], tip[k, 2], axis[k, 0],
        axis[k, 1], axis[k, 2], prm)
    return t


@njit(cache=True, nogil=True, error_model="numpy")
def _end_slope(g, k, i, j, tip, axis):
    """Slope of the entry at CL point k (i or j) along move i -> j."""
    dax, day, daz = axis[j, 0] - axis[i, 0], axis[j, 1] - axis[i, 1], axis[j, 2] - axis[i, 2]
    ax, ay, az, wax, way, waz = _axis_rate(axis[k, 0], axis[k, 1], axis[k, 2], dax, day, daz)
    vcx, vcy, vcz = tip[j, 0] - tip[i, 0], tip[j, 1] - tip[i, 1], tip[j, 2] - tip[i, 2]
    sl = _slope(g[:3], g[3:], vcx, vcy, vcz, wax, way, waz)
    return sl, _curl(g, ax, ay, az, wax, way, waz, vcx, vcy, vcz, sl)


@njit(cache=True, nogil=True, error_model="numpy")
def _geo(i, j, tip, axis, px, py, pz, dx, dy, dz, e):
    """What bounds the entry over move i -> j without computing one: e = (U, w0 max,
    |w0| max, a . d min, a . d max, |d - (a . d) a| max) with U a lower bound of the
    distance from the ray's start to the axis over the move. The axis turns by at most
    ``turn`` (chord of the axes), which moves any point at distance l from the tip by at
    most l turn; it is added to every figure (see :func:`_geo_bound`)."""
    ex, ey, ez = axis[j, 0] - axis[i, 0], axis[j, 1] - axis[i, 1], axis[j, 2] - axis[i, 2]
    turn = math.sqrt(ex * ex + ey * ey + ez * ez)
    ax, ay, az = axis[i, 0], axis[i, 1], axis[i, 2]
    qx, qy, qz = px - tip[i, 0], py - tip[i, 1], pz - tip[i, 2]
    rx, ry, rz = px - tip[j, 0], py - tip[j, 1], pz - tip[j, 2]
    wi = qx * ax + qy * ay + qz * az
    wj = rx * ax + ry * ay + rz * az
    lmax = max(math.sqrt(qx * qx + qy * qy + qz * qz), math.sqrt(rx * rx + ry * ry + rz * rz))
    # distance from p to the tip's segment in the plane across the axis a_i
    ux, uy, uz = qx - wi * ax, qy - wi * ay, qz - wi * az
    vx, vy, vz = (rx - wj * ax) - ux, (ry - wj * ay) - uy, (rz - wj * az) - uz
    vv = vx * vx + vy * vy + vz * vz
    lam = 0.0 if vv <= 0.0 else min(max(-(ux * vx + uy * vy + uz * vz) / vv, 0.0), 1.0)
    dd = math.sqrt((ux + lam * vx) ** 2 + (uy + lam * vy) ** 2 + (uz + lam * vz) ** 2)
    da_i = dx * ax + dy * ay + dz * az
    da_j = dx * axis[j, 0] + dy * axis[j, 1] + dz * axis[j, 2]
    e[0] = dd - lmax * turn
    e[1] = max(wi, wj) + lmax * turn
    e[2] = max(abs(wi), abs(wj)) + lmax * turn
    e[3] = min(da_i, da_j) - turn
    e[4] = min(max(da_i, da_j) + turn, 1.0)
    e[5] = math.sqrt(max(1.0 - min(da_i, da_j) ** 2, 0.0)) + turn


@njit(cache=True, nogil=True, error_model="numpy")
def _geo_spans(i, j, tip, axis, px, py, pz, T, prm, whole, e):
    """(lo, hi): the stretch of move i -> j (in s) outside which it cannot cut below T, from
    :func:`_geo_bound` over the move cut into ``SPANS`` equal spans; lo > hi where no span
    can. Over a whole move the height of the ray's start above the tip plane changes by the
    lead times the move's length, and the axis turns; the whole-move figures (``whole``, of
    :func:`_geo`) take the worst of both, a span's far less (each span's U, w0 and turn as
    :func:`_geo` finds them for the move, the ray's direction figures of the whole move)."""
    vx, vy, vz = tip[j, 0] - tip[i, 0], tip[j, 1] - tip[i, 1], tip[j, 2] - tip[i, 2]
    wx, wy, wz = axis[j, 0] - axis[i, 0], axis[j, 1] - axis[i, 1], axis[j, 2] - axis[i, 2]
    e[3], e[4], e[5] = whole[3], whole[4], whole[5]
    lo, hi = 1.0, 0.0
    bx, by, bz = axis[i, 0], axis[i, 1], axis[i, 2]
    nb = 1.0 / math.sqrt(bx * bx + by * by + bz * bz)
    bx, by, bz = bx * nb, by * nb, bz * nb
    rx, ry, rz = px - tip[i, 0], py - tip[i, 1], pz - tip[i, 2]
    lr = math.sqrt(rx * rx + ry * ry + rz * rz)
    for k in range(SPANS):
        s1 = (k + 1.0) / SPANS
        ax, ay, az = bx, by, bz
        bx, by, bz = axis[i, 0] + s1 * wx, axis[i, 1] + s1 * wy, axis[i, 2] + s1 * wz
        nb = 1.0 / math.sqrt(bx * bx + by * by + bz * bz)
        bx, by, bz = bx * nb, by * nb, bz * nb
        tx, ty, tz = ax - bx, ay - by, az - bz
        turn = math.sqrt(tx * tx + ty * ty + tz * tz)
        # the ray's start from the span's two tips (q, then r), in the frame of its first axis
        qx, qy, qz, lq = rx, ry, rz, lr
        rx, ry, rz = px - tip[i, 0] - s1 * vx, py - tip[i, 1] - s1 * vy, pz - tip[i, 2] - s1 * vz
        lr = math.sqrt(rx * rx + ry * ry + rz * rz)
        wi = qx * ax + qy * ay + qz * az
        wj = rx * ax + ry * ay + rz * az
        ux, uy, uz = qx - wi * ax, qy - wi * ay, qz - wi * az
        cx, cy, cz = (rx - wj * ax) - ux, (ry - wj * ay) - uy, (rz - wj * az) - uz
        cc = cx * cx + cy * cy + cz * cz
        lam = 0.0 if cc <= 0.0 else min(max(-(ux * cx + uy * cy + uz * cz) / cc, 0.0), 1.0)
        dd = math.sqrt((ux + lam * cx) ** 2 + (uy + lam * cy) ** 2 + (uz + lam * cz) ** 2)
        lt = max(lq, lr) * turn
        e[0] = dd - lt
        e[1] = max(wi, wj) + lt
        e[2] = max(abs(wi), abs(wj)) + lt
        if not _geo_bound(e, T, prm) >= T:  # (nan where the ray runs along the axis)
            lo, hi = min(lo, s1 - 1.0 / SPANS), s1
    return lo, hi


@njit(cache=True, nogil=True, error_model="numpy")
def _geo_bound(e, T, prm):
    """A lower bound of every entry below T over the move (-inf if none is known): an entry
    at t lies in the cutter above its tip plane (t >= -w0 / (a . d), so |t| <= tau), within
    the radius of the axis, where the ray is at least U - tau |d_perp| from it, and there
    the cutter's lower profile h(rho) is at least h(U - tau |d_perp|)."""
    if e[3] <= 1e-9:
        return -INF
    tau = max(abs(T), e[2] / e[3])
    rho = e[0] - tau * e[5]
    if rho > prm[0]:
        return INF
    hr = piece_height(max(rho, 0.0), prm)
    num = hr - e[1]
    return num / e[4] if num > 0.0 else num / e[3]


@njit(cache=True, nogil=True, error_model="numpy")
def sweep_moves(res, x0, y0, h, pz, nrm, inside, vertical, tip, axis, mv_i, mv_j, mv_reach,
                ts, ptr, tile_mv, prm, tol, bend_tol, near_miss, n_golden, stats):
    """Lower ``res`` (ny, nx) to the deepest entry over all moves (see the module doc).
    ``stats`` (4,) counts: entries at CL points, moves searched, entries in the searches,
    golden-section fallbacks."""
    ny, nx = res.shape
    tx = (nx + ts - 1) // ts
    n_max = 1
    for k in range(ptr.shape[0] - 1):
        n_max = max(n_max, ptr[k + 1] - ptr[k])
    cm = np.empty(n_max, np.int64)
    cf = np.empty((n_max, 6))
    key = np.empty(n_max)
    order = np.empty(n_max, np.int64)
    stk = np.empty((64, 9))
    geo = np.empty(6)  # the figures of the move being tested (:func:`_geo`)
    cg = np.empty((n_max, 2, 6))
    have = np.zeros((n_max, 2), np.bool_)  # the entries at a candidate's ends computed
    gs = np.empty(6)
    # per move, within a tile's row: where its search found its lowest entry in the last
    # two cells it searched (mv_cell: iy nx + ix) and the curvature there
    n_mv = mv_i.shape[0]
    mv_s1, mv_s2, mv_c = np.full(n_mv, -1.0), np.full(n_mv, -1.0), np.full(n_mv, -1.0)
    mv_cell1, mv_cell2 = np.full(n_mv, -1, np.int64), np.full(n_mv, -1, np.int64)
    for tile in range(ptr.shape[0] - 1):
        if ptr[tile + 1] == ptr[tile]:
            continue
        ky, kx = tile // tx, tile % tx
        top_m, top_s = -1, -1.0  # the deepest move and pose of the row's first cell
        for iy in range(ky * ts, min(ky * ts + ts, ny)):
            py = y0 + iy * h
            # the deepest move and pose of the previous cell (the cell above for the first)
            hint_m, hint_s = top_m, top_s
            first = True
            for ix in range(kx * ts, min(kx * ts + ts, nx)):
                if not inside[iy, ix]:
                    continue
                px = x0 + ix * h
                dx, dy, dz = _ray(iy, ix, vertical, nrm)
                p_z = pz[iy, ix]
                best = res[iy, ix]
                best_m, best_s = -1, -1.0
                cell, row0 = iy * nx + ix, iy * nx + kx * ts  # and the tile row's first cell
                nc = 0
                for q in range(ptr[tile], ptr[tile + 1]):
                    m = tile_mv[q]
                    i, j = mv_i[m], mv_j[m]
                    reach = mv_reach[m]
                    d2 = _seg_dist2(px, py, tip[i, 0], tip[i, 1], tip[j, 0], tip[j, 1])
                    if d2 > reach * reach:
                        continue
                    cm[nc] = m
                    key[nc] = -INF if m == hint_m else d2
                    have[nc, 0] = have[nc, 1] = False
                    order[nc] = nc
                    k = nc
                    while k > 0 and key[order[k - 1]] > key[order[k]]:
                        order[k - 1], order[k] = order[k], order[k - 1]
                        k -= 1
                    nc += 1
                # the previous cell's deepest move first, then the nearest in XY; a move
                # whose geometric bound is above the best entry found so far is skipped
                # without computing any entry
                for o in range(nc):
                    c = order[o]
                    m = cm[c]
                    i, j = mv_i[m], mv_j[m]
                    lo, hi = 0.0, 1.0
                    if best < _HALF:
                        _geo(i, j, tip, axis, px, py, p_z, dx, dy, dz, geo)
                        if _geo_bound(geo, best, prm) >= best:
                            continue
                        if m != hint_m:
                            lo, hi = _geo_spans(i, j, tip, axis, px, py, p_z, best, prm,
                                                geo, gs)
                            if lo > hi:
                                continue
                    near = mv_cell1[m] == cell - 1 and cell - 1 >= row0
                    s0, c0 = (hint_s if m == hint_m else -1.0), -1.0
                    if near:
                        s0, c0 = mv_s1[m], mv_c[m]
                        if mv_cell2[m] == cell - 2 and cell - 2 >= row0:
                            s0 = 2.0 * mv_s1[m] - mv_s2[m]  # the minimum moves on steadily
                    # the first move searched, from a pose inside it: its ends' entries are
                    # not needed unless that pose misses (``convex._move_min``)
                    ends = not (best >= _HALF and lo == 0.0 and hi == 1.0 and i != j
                                and 0.02 < s0 < 0.98)
                    # a CL point's entry serves both moves that meet there; an end outside
                    # [lo, hi], or skipped, is not needed (its entry stays 0, a placeholder)
                    f0 = f1 = 0.0
                    if ends and lo == 0.0:
                        if c > 0 and have[c - 1, 1] and mv_j[cm[c - 1]] == i:
                            f0 = cf[c - 1, 3]
                            cg[c, 0, :] = cg[c - 1, 1, :]
                        else:
                            stats[0] += 1
                            f0 = _point(i, tip, axis, px, py, p_z, dx, dy, dz, prm, cg[c, 0])
                        have[c, 0] = True
                        cf[c, 1], cf[c, 2] = _end_slope(cg[c, 0], i, i, j, tip, axis)
                    if ends and hi == 1.0:
                        if j == i:
                            f1 = f0
                            cg[c, 1, :] = cg[c, 0, :]
                        elif c + 1 < nc and have[c + 1, 0] and mv_i[cm[c + 1]] == j:
                            f1 = cf[c + 1, 0]
                            cg[c, 1, :] = cg[c + 1, 0, :]
                        else:
                            stats[0] += 1
                            f1 = _point(j, tip, axis, px, py, p_z, dx, dy, dz, prm, cg[c, 1])
                        have[c, 1] = True
                        cf[c, 4], cf[c, 5] = _end_slope(cg[c, 1], j, i, j, tip, axis)
                    cf[c, 0] = f0
                    cf[c, 3] = f1
                    stats[1] += 1
                    if have[c, 0] and f0 < best:
                        best, best_m, best_s = f0, m, 0.0
                    if have[c, 1] and f1 < best:
                        best, best_m, best_s = f1, m, 1.0
                    got, s_got, s_low, c_got = _move_min(
                        i, j, tip, axis, px, py, p_z, dx, dy, dz, prm, cf[c, 0], cf[c, 1],
                        cf[c, 2], cf[c, 3], cf[c, 4], cf[c, 5], best, tol, bend_tol,
                        near_miss, n_golden, gs, stk, stats, s0, lo, hi, c0, ends)
                    if s_low >= 0.0:
                        mv_s2[m], mv_cell2[m] = mv_s1[m], mv_cell1[m]
                        mv_s1[m], mv_cell1[m], mv_c[m] = s_low, cell, c_got
                    if got < best:
                        best, best_m, best_s = got, m, s_got
                res[iy, ix] = best if best < _HALF else INF
                hint_m, hint_s = best_m, best_s
                if first:
                    top_m, top_s, first = best_m, best_s, False
