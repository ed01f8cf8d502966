"""The sweep by moves: the deepest entry of each cell's ray over every feed move, exactly.

Along one straight move with a constant axis the cutter is a convex solid C translated
along a line, so the set {(t, s): p + t d in C + s v} is the preimage of C under an affine
map, hence convex, and the entry f(s) = min t is a convex function of the move parameter s
on the stretch where the ray hits (an interval). The axis interpolated between two CL
points turns only a little over one move, so f stays convex to within far less than the
tolerance. The derivative f'(s) follows from the entry point by the implicit function
theorem (``kernel.entry_gradient``), so:

- an end of the move where f climbs into the move (f'(0) >= 0, f'(1) <= 0) is the move's
  minimum; no search;
- otherwise the tangents at both ends bound f from below (they cross at the lower bound L):
  a move whose L is above the best entry found so far cannot deepen the cell;
- else the minimum is bracketed and the bracket shrinks by secant steps on f' (exact for a
  smooth, nearly quadratic f) or by the tangents' crossing (exact for a V-shaped f: a
  sharp rim passing the ray), until the best value found is within ``tol`` mm of L. The
  neighbouring cells' minimum along the move, extrapolated, is tried first, and a Newton
  step with their curvature follows it: in a row of cells the minimum moves on steadily.

A move whose one end misses the ray is bisected towards the end that hits until the hit
stretch is bracketed; a move whose both ends miss is tried where its tip passes closest to
the cell, and searched by golden section on the miss score (``kernel.MISS`` plus the
distance outside the radius) only when that pose passes within ``near_miss`` mm.

The axis interpolated between two CL points turns the cutter while it moves, which bends f
away from convex by a bounded amount (:func:`_curl`); the bounds allow for it.
``moves.py`` runs this search for every cell and every move that can reach it.
"""

from __future__ import annotations

import math

from numba import njit

from .kernel import INF, MISS, _entry, _golden, entry_gradient

_HALF = 0.5 * MISS
#: the bend bound from the ends, times this, holds over the interval
BEND_SAFETY = 2.0


@njit(cache=True, nogil=True, error_model="numpy")
def _slope(gc, ga, vcx, vcy, vcz, wax, way, waz):
    """dt/ds for the tip velocity vc and axis velocity wa (perpendicular to the axis)."""
    return (gc[0] * vcx + gc[1] * vcy + gc[2] * vcz) - (ga[0] * wax + ga[1] * way + ga[2] * waz)


@njit(cache=True, nogil=True, error_model="numpy")
def _axis_rate(nx, ny, nz, dax, day, daz):
    """Unit axis n / |n| and its rate for an axis n(s) with dn/ds = da (linear, renormalized)."""
    nn = math.sqrt(nx * nx + ny * ny + nz * nz)
    ax, ay, az = nx / nn, ny / nn, nz / nn
    k = ax * dax + ay * day + az * daz
    return ax, ay, az, (dax - k * ax) / nn, (day - k * ay) / nn, (daz - k * az) / nn


@njit(cache=True, nogil=True, error_model="numpy")
def _at(s, i, j, tip, axis, px, py, pz, dx, dy, dz, prm, g):
    """(entry, slope, 1 / cos) at move parameter s of move i -> j: the entry, its derivative
    along the move, and 1 / (normal . ray) at the entry point (0, 0 where the ray misses)."""
    vcx, vcy, vcz = tip[j, 0] - tip[i, 0], tip[j, 1] - tip[i, 1], tip[j, 2] - tip[i, 2]
    dax, day, daz = axis[j, 0] - axis[i, 0], axis[j, 1] - axis[i, 1], axis[j, 2] - axis[i, 2]
    cx, cy, cz = tip[i, 0] + s * vcx, tip[i, 1] + s * vcy, tip[i, 2] + s * vcz
    ax, ay, az, wax, way, waz = _axis_rate(axis[i, 0] + s * dax, axis[i, 1] + s * day,
                                           axis[i, 2] + s * daz, dax, day, daz)
    t, face = _entry(px, py, pz, dx, dy, dz, cx, cy, cz, ax, ay, az, prm, INF)
    if face == 0:
        return t, 0.0, 0.0
    g[0], g[1], g[2], g[3], g[4], g[5] = entry_gradient(t, face, px, py, pz, dx, dy, dz,
                                                        cx, cy, cz, ax, ay, az, prm)
    sl = _slope(g[:3], g[3:], vcx, vcy, vcz, wax, way, waz)
    return t, sl, _curl(g, ax, ay, az, wax, way, waz, vcx, vcy, vcz, sl)


@njit(cache=True, nogil=True, error_model="numpy")
def _curl(g, ax, ay, az, wax, way, waz, vcx, vcy, vcz, sl):
    """How fast the turning axis bends the entry away from convex, here: the cutter frame
    sees the ray move along a curve (d2y/ds2 = 2 w x v with w = a x da/ds the axis' angular
    rate, d2y/dsdt = w x d), so the non-convex part of f'' is at most
    2 (|n . (w x v)| + |w| |f'|) / |n . d| at an entry of normal n (gc = n / (n . d))."""
    wx, wy, wz = ay * waz - az * way, az * wax - ax * waz, ax * way - ay * wax
    cx, cy, cz = wy * vcz - wz * vcy, wz * vcx - wx * vcz, wx * vcy - wy * vcx
    gn = math.sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
    wn = math.sqrt(wx * wx + wy * wy + wz * wz)
    return abs(g[0] * cx + g[1] * cy + g[2] * cz) + wn * abs(sl) * gn


@njit(cache=True, nogil=True, error_model="numpy")
def _bound(a, b, fa, sa, fb, sb, kap):
    """Lower bound of f on [a, b] from the ends: f + kap/2 (s - a)(s - b) is convex there,
    so its tangents at the ends bound it (and f) from below. An end that misses (f above
    MISS / 2) gives no tangent: the hit stretch is an interval that ends before it."""
    w = b - a
    hit_a, hit_b = fa < _HALF, fb < _HALF
    ga, gb = sa - 0.5 * kap * w, sb + 0.5 * kap * w
    if hit_a and hit_b:
        if ga >= 0.0:
            return fa
        if gb <= 0.0:
            return fb
        return fa + ga * ((fb - fa + gb * (a - b)) / (ga - gb))
    if hit_a:
        return fa + min(ga, 0.0) * w
    if hit_b:
        return fb - max(gb, 0.0) * w
    return INF


@njit(cache=True, nogil=True, error_model="numpy")
def _bend(ka, kb):
    """kap of :func:`_bound` on an interval from :func:`_curl` at its ends."""
    return BEND_SAFETY * 2.0 * max(ka, kb)


@njit(cache=True, nogil=True, error_model="numpy")
def _noted(f, s, f_low, s_low, best, s_best):
    """(f_low, s_low, best, s_best) after an entry f at s: the search's lowest entry and the
    cell's best."""
    if f < f_low:
        f_low, s_low = f, s
    if f < best:
        best, s_best = f, s
    return f_low, s_low, best, s_best


@njit(cache=True, nogil=True, error_model="numpy")
def _move_min(i, j, tip, axis, px, py, pz, dx, dy, dz, prm, fa, sa, na, fb, sb, nb, best,
              tol, bend_tol, near_miss, n_golden, g, stk, stats, s0, lo, hi, c0=-1.0,
              ends=True):
    """(best, s, s_low, c): the deepest entry over move i -> j (s in [0, 1]) if it is below
    ``best`` (else best, -1) and where it is; s_low where this search's lowest entry lay
    (-1 if it evaluated none) and c the curvature of f there (the slopes' secant of its last
    two points; -1 if unknown), for the next cell's search. fa, sa, na / fb, sb, nb: entry,
    slope and 1 / cos at the ends (see the module doc); s0 in (0, 1): where to try first
    (the neighbouring cells' deepest pose); c0: the curvature there, for the first Newton
    step; [lo, hi]: the stretch outside which the move cannot cut below best, the only one
    searched (fa ... nb then hold placeholders for an end outside it). ``ends`` False: the
    caller took no end entries (lo = 0, hi = 1, s0 inside): the search starts at s0, each
    side bounded by the tangent there alone as beside an end that misses, and takes the ends
    only if the ray misses at s0.

    Where the points go: regula falsi on f' (or the tangents' crossing) inside a bracket,
    else halves; near the last point evaluated, a Newton step with the curvature of the
    last two (or c0); and where the convex bound already holds and only the bend allowance
    keeps an interval open, the point that closes the part next to its lower end in one
    step (the allowance's dip kap x^2 / 4 within ``bend_tol``, or the tangent still
    rising), instead of halving towards it. The points change the work, not the bounds; an
    interval reaching an end whose entry was not taken takes its bend allowance from its
    other end alone, as one reaching an end that misses always has.

    Branch and bound over sub-intervals of the move, each bounded by :func:`_bound` with
    kap, a bound of how far the turning axis bends f away from convex (the cutter frame
    sees the ray move along a curve: d2y/ds2 = 2 da/ds x v, d2y/dsdt = da/ds x d, hence
    |f''| of the non-convex part <= 2 |da/ds| (|v| + |f'|) / cos), with a factor 2 to spare."""
    s_best = -1.0
    if i == j:
        return best, s_best, -1.0, -1.0
    f_low, s_low = INF, -1.0  # the lowest entry this search evaluated, below best or not
    vx, vy, vz = tip[j, 0] - tip[i, 0], tip[j, 1] - tip[i, 1], tip[j, 2] - tip[i, 2]
    vlen = math.sqrt(vx * vx + vy * vy + vz * vz)
    s_l = sl_l = s_p = sl_p = 0.0  # the loop's last two points and their slopes
    hit_l = hit_p = False
    evals = 0
    n = 0
    if not ends:
        # the ends' entries not taken (fa ... nb placeholders; lo = 0, hi = 1, s0 inside):
        # start at s0, each side bounded by the tangent there alone, as beside an end that
        # misses; if s0 misses, take the ends after all
        f, sl, nu = _at(s0, i, j, tip, axis, px, py, pz, dx, dy, dz, prm, g)
        stats[2] += 1
        evals = 1
        if f < _HALF:
            f_low, s_low, best, s_best = _noted(f, s0, f_low, s_low, best, s_best)
            if sl < 0.0:  # f falls towards hi: that side first (pushed last)
                stk[0, :] = (lo, s0, INF, 0.0, 0.0, f, sl, nu, 0.0)
                stk[1, :] = (s0, hi, f, sl, nu, INF, 0.0, 0.0, 0.0)
            else:
                stk[0, :] = (s0, hi, f, sl, nu, INF, 0.0, 0.0, 0.0)
                stk[1, :] = (lo, s0, INF, 0.0, 0.0, f, sl, nu, 0.0)
            n = 2
            s_l, sl_l, hit_l = s0, sl, True
    if n == 0:  # not started from s0 above: from the stretch's ends
        # only [lo, hi] can cut below best (the spans' geometric bounds): its ends (the
        # whole move's too when the caller took none and s0 missed)
        if lo > 0.0 or not ends:
            fa, sa, na = _at(lo, i, j, tip, axis, px, py, pz, dx, dy, dz, prm, g)
            stats[2] += 1
            f_low, s_low, best, s_best = _noted(fa, lo, f_low, s_low, best, s_best)
        if hi < 1.0 or not ends:
            fb, sb, nb = _at(hi, i, j, tip, axis, px, py, pz, dx, dy, dz, prm, g)
            stats[2] += 1
            f_low, s_low, best, s_best = _noted(fb, hi, f_low, s_low, best, s_best)
        if fa >= _HALF and fb >= _HALF:
            # both ends miss: try where the tip passes closest to the cell (in XY)
            vv = vx * vx + vy * vy
            sc = 0.5 * (lo + hi) if vv <= 0.0 else min(max(
                ((px - tip[i, 0]) * vx + (py - tip[i, 1]) * vy) / vv, lo), hi)
            f, sl, nu = _at(sc, i, j, tip, axis, px, py, pz, dx, dy, dz, prm, g)
            if f >= _HALF:
                if f - MISS > near_miss:
                    return best, s_best, s_low, -1.0
                stats[3] += 1
                return min(best, _golden(i + lo, i + hi, i, i + 1, tip, axis, px, py, pz, dx,
                                         dy, dz, prm, n_golden)), s_best, s_low, -1.0
            f_low, s_low, best, s_best = _noted(f, sc, f_low, s_low, best, s_best)
            stk[0, :] = (lo, sc, fa, sa, nu, f, sl, nu, 0.0)
            stk[1, :] = (sc, hi, f, sl, nu, fb, sb, nu, 0.0)
            n = 2
        else:
            stk[0, :] = (lo, hi, fa, sa, na, fb, sb, nb, 0.0)
            n = 1
    while n > 0:
        n -= 1
        a, b, fa, sa, na, fb, sb, nb, kept = stk[n]
        w = b - a
        if w * vlen < 1e-6 or evals >= 60:
            continue
        # done where neither f can dip more than tol below best if it is convex, nor more
        # than bend_tol as bent by the turning axis
        l0 = _bound(a, b, fa, sa, fb, sb, 0.0)
        if l0 >= best - tol and _bound(a, b, fa, sa, fb, sb, _bend(na, nb)) >= best - bend_tol:
            continue
        if fa < _HALF and fb < _HALF and sa < 0.0 < sb:
            # regula falsi on f'; an end kept twice in a row counts half (Illinois)
            ea = sa * 0.5 ** max(kept - 1.0, 0.0)
            eb = sb * 0.5 ** max(-kept - 1.0, 0.0)
            s = a - ea * w / (eb - ea)
            st = (fb - fa + sa * a - sb * b) / (sa - sb)  # where the end tangents cross
            if abs(s - st) > 0.2 * w:
                # f is far from a parabola (a kink where the entry passes from the flat
                # bottom to the corner, a steep wall where the ray grazes the cutter):
                # regula falsi would creep, the tangents' crossing finds a kink
                s = 0.5 * (s + st)
            s = min(max(s, a + 0.01 * w), b - 0.01 * w)
        else:
            s = 0.5 * (a + b)
            kept = 0.0
        if l0 >= best - tol and (fa < _HALF or fb < _HALF):
            # convex, f cannot dip below best - tol here: only the bend allowance keeps the
            # interval open. Split it where the part next to its lower end closes in one step
            # by that end's allowance (the tangent still rising, or the dip kap x^2 / 4
            # within bend_tol), not by halves or by regula falsi's 1 % steps
            low_a = fa <= fb
            rise, kap, f_end = (sa, _bend(na, na), fa) if low_a else (-sb, _bend(nb, nb), fb)
            if kap > 0.0:
                x = 0.9 * max(2.0 * rise / kap,
                              2.0 * math.sqrt(max(f_end - best + bend_tol, 0.0) / kap))
                if 0.01 * w < x < 0.5 * w:
                    s = a + x if low_a else b - x
        elif hit_l:
            # near the last point f is nearly a parabola: a Newton step on f', with the
            # curvature of the last two points (the neighbouring cell's after the first)
            cur = (sl_l - sl_p) / (s_l - s_p) if hit_p and s_l != s_p else c0
            if cur > 0.0:
                sn = s_l - sl_l / cur
                # inside, or (refining the end just found) closer to that end than 1 %
                if a + 0.01 * w < sn < b - 0.01 * w or (
                        a + 1e-9 < sn < b - 1e-9 and (s_l == a or s_l == b)
                        and abs(sn - s_l) < 0.01 * w):
                    s = sn
        if evals == 0 and a < s0 < b:
            s = s0
        f, sl, nu = _at(s, i, j, tip, axis, px, py, pz, dx, dy, dz, prm, g)
        s_p, sl_p, hit_p = s_l, sl_l, hit_l
        s_l, sl_l, hit_l = s, sl, f < _HALF
        evals += 1
        stats[2] += 1
        f_low, s_low, best, s_best = _noted(f, s, f_low, s_low, best, s_best)
        # the side towards which f falls is searched first (pushed last); ``kept`` counts
        # how often in a row its end a (> 0) or b (< 0) was kept
        if sl < 0.0:
            stk[n, :] = (a, s, fa, sa, na, f, sl, nu, 0.0)
            stk[n + 1, :] = (s, b, f, sl, nu, fb, sb, nb, min(kept, 0.0) - 1.0)
        else:
            stk[n, :] = (s, b, f, sl, nu, fb, sb, nb, 0.0)
            stk[n + 1, :] = (a, s, fa, sa, na, f, sl, nu, max(kept, 0.0) + 1.0)
        n += 2
    c_out = (sl_l - sl_p) / (s_l - s_p) if hit_l and hit_p and s_l != s_p else -1.0
    return best, s_best, s_low, c_out
