"""Compiled passes of the pass-plane tables (``planes.PassGeometry``): the planes' extents,
the bilinear seed of plane points and the zone-band membership of ``sections._stretches``.

Each does, point by point, exactly the floating-point operations of its numpy reference
(``PassGeometry.pass_extent_numpy``, ``PassGeometry.seed_numpy`` and
``sections._band_inside_numpy``), in the same order, so
their numbers agree bit for bit (tested); they only skip the temporaries: the band test of
a zoned evaluation built a (planes x feed samples) array per sub-plane offset, each point
seeded from the tables with ten of them.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..geometry.rows import _interp_rows

__all__ = ["extent", "seed_uv", "seed_feed", "newton_step", "section_points", "band_runs_max", "band_runs", "band_inside", "zone_cells"]


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _d_cell(g, d):
    """``PassGeometry._index`` of one offset: (j0, fj)."""
    ng = len(g)
    if d != d:  # NaN sorts last (np.searchsorted)
        j = ng
    else:  # np.searchsorted(g, d, side="right"): the count of nodes <= d
        a, b = 0, ng
        while a < b:
            mid = (a + b) // 2
            if g[mid] <= d:
                a = mid + 1
            else:
                b = mid
        j = a
    j0 = min(max(j - 1, 0), ng - 2)
    fj = (d - g[j0]) / (g[j0 + 1] - g[j0])
    if fj < 0.0:
        fj = 0.0
    elif fj > 1.0:
        fj = 1.0
    return j0, fj


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _tau_cell(tau, nt):
    """The tau cell of ``PassGeometry.seed_numpy`` of one point: (t0, ft)."""
    if tau < 0.0:
        tau = 0.0
    elif tau > 1.0:
        tau = 1.0
    tf = tau * (nt - 1)
    if tf != tf:
        t0 = 0  # numpy's NaN -> int64 is the smallest int64, clipped to 0
    else:
        t0 = min(max(np.int64(np.floor(tf)), 0), nt - 2)
    return t0, tf - t0


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _bilinear(U, V, j0, fj, t0, ft):
    """``PassGeometry.seed_numpy`` of one point of table cell (j0, t0): (u, v)."""
    w00, w01 = (1 - fj) * (1 - ft), (1 - fj) * ft
    w10, w11 = fj * (1 - ft), fj * ft
    u = (U[j0, t0] * w00 + U[j0, t0 + 1] * w01 + U[j0 + 1, t0] * w10
         + U[j0 + 1, t0 + 1] * w11)
    v = (V[j0, t0] * w00 + V[j0, t0 + 1] * w01 + V[j0 + 1, t0] * w10
         + V[j0 + 1, t0 + 1] * w11)
    return u, v


@njit(cache=True, nogil=True, error_model="numpy")
def extent(g, s_lo, s_hi, d):
    """(s_lo, s_hi) of planes d (q,): linear in the offset table."""
    q = len(d)
    lo, hi = np.empty(q), np.empty(q)
    for i in range(q):
        j0, fj = _d_cell(g, d[i])
        lo[i] = s_lo[j0] * (1 - fj) + s_lo[j0 + 1] * fj
        hi[i] = s_hi[j0] * (1 - fj) + s_hi[j0 + 1] * fj
    return lo, hi


@njit(cache=True, nogil=True, error_model="numpy")
def seed_uv(g, U, V, d, tau):
    """(u, v) of plane points (d, tau), each (q,): the table's bilinear seed."""
    q, nt = len(d), U.shape[1]
    u, v = np.empty(q), np.empty(q)
    for i in range(q):
        j0, fj = _d_cell(g, d[i])
        t0, ft = _tau_cell(tau[i], nt)
        u[i], v[i] = _bilinear(U, V, j0, fj, t0, ft)
    return u, v


@njit(cache=True, nogil=True, error_model="numpy")
def seed_feed(g, U, V, s_lo, s_hi, d, tau):
    """``PassGeometry.locate``'s start for plane points (d, tau), each (q,): the seed (u, v)
    of :func:`seed_uv` and the feed coordinate s = lo + tau (hi - lo) of the plane's
    extent (:func:`extent`)."""
    q, nt = len(d), U.shape[1]
    u, v, s = np.empty(q), np.empty(q), np.empty(q)
    for i in range(q):
        j0, fj = _d_cell(g, d[i])
        t0, ft = _tau_cell(tau[i], nt)
        u[i], v[i] = _bilinear(U, V, j0, fj, t0, ft)
        lo = s_lo[j0] * (1 - fj) + s_lo[j0 + 1] * fj
        hi = s_hi[j0] * (1 - fj) + s_hi[j0 + 1] * fj
        s[i] = lo + tau[i] * (hi - lo)
    return u, v, s


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _unit_clip(x):
    """np.clip(x, 0.0, 1.0) (NaN stays NaN)."""
    if x < 0.0:
        return 0.0
    if x > 1.0:
        return 1.0
    return x


@njit(cache=True, nogil=True, error_model="numpy")
def newton_step(d, s, u, v, pc, pf, a11, a12, a21, a22):
    """One step of ``PassGeometry._newton`` from the jet's projections (the residuals' c.p,
    f.p and the Jacobian a11 = c.su, a12 = c.sv, a21 = f.su, a22 = f.sv, each (q,), taken
    by numpy as before): the new (u, v) and the steps (du, dv)."""
    q = len(d)
    un, vn, du, dv = np.empty(q), np.empty(q), np.empty(q), np.empty(q)
    for i in range(q):
        r1 = pc[i] - d[i]
        r2 = pf[i] - s[i]
        det = a11[i] * a22[i] - a12[i] * a21[i]
        if not np.abs(det) > 1e-300:
            det = 1e-300
        un[i] = _unit_clip(u[i] - (a22[i] * r1 - a12[i] * r2) / det)
        vn[i] = _unit_clip(v[i] - (a11[i] * r2 - a21[i] * r1) / det)
        du[i], dv[i] = un[i] - u[i], vn[i] - v[i]
    return un, vn, du, dv


@njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _maximum(a, b):
    """np.maximum of two floats (NaN propagates; b where they are equal)."""
    return a if (a > b or a != a) else b


@njit(cache=True, nogil=True, error_model="numpy")
def section_points(g, arc, tau_grid, d, ta, tb, step):
    """The first CC points of ``points.sample_sections``: sections (d, [ta, tb], step),
    each (S,), uniformly in arc length along their planes (``PassGeometry.arc_rows``, its
    ``_arc_at``), ceil(L / step) segments each: (pt_sec, tau) (N,) and the segment starts
    (every point but a section's last). The numbers of ``points.section_points_numpy``."""
    n_sec, nt = len(d), arc.shape[1]
    rows = np.empty((n_sec, nt))
    nseg = np.empty(n_sec, np.int64)
    a0, length = np.empty(n_sec), np.empty(n_sec)
    for i in range(n_sec):
        j0, fj = _d_cell(g, d[i])
        for k in range(nt):
            rows[i, k] = arc[j0, k] * (1 - fj) + arc[j0 + 1, k] * fj
        ends = np.empty(2)
        for e in range(2):
            t0, w = _tau_cell(ta[i] if e == 0 else tb[i], nt)
            ends[e] = rows[i, t0] * (1 - w) + rows[i, t0 + 1] * w
        a0[i] = ends[0]
        length[i] = _maximum(ends[1] - ends[0], 0.0)
        x = np.ceil(length[i] / step[i] - 1e-9)
        # astype(int) then np.maximum(., 1): NaN, inf and beyond int64 give INT64_MIN
        nseg[i] = max(np.int64(x), 1) if abs(x) < 9.2e18 else 1
    n = 0
    for i in range(n_sec):
        n += nseg[i] + 1
    pt_sec, q = np.empty(n, np.int64), np.empty(n, np.int64)
    target = np.empty(n)
    at = 0
    for i in range(n_sec):
        for j in range(nseg[i] + 1):
            pt_sec[at], q[at] = i, j
            target[at] = a0[i] + j / nseg[i] * length[i]
            at += 1
    tau = _interp_rows(rows, tau_grid.reshape(1, -1), target, pt_sec, True)
    starts = np.empty(n - n_sec, np.int64)
    at, b = 0, 0
    for i in range(n_sec):
        for j in range(nseg[i] + 1):
            if j == 0:
                tau[at] = ta[i]
            elif j == nseg[i]:
                tau[at] = tb[i]
            if j < nseg[i]:
                starts[b] = at
                b += 1
            at += 1
    return pt_sec, tau, starts


@njit(cache=True, nogil=True, error_model="numpy")
def band_runs_max(g, s_lo, s_hi, d, up, down, fracs):
    """``sections.edge_runs`` of planes d (q,): the largest run of the footprint past each
    plane's ends over the sub-plane offsets f up, -f down (f in ``fracs``, in that order)."""
    q = len(d)
    run_lo, run_hi = np.empty(q), np.empty(q)
    for i in range(q):
        j0, fj = _d_cell(g, d[i])
        lo = s_lo[j0] * (1 - fj) + s_lo[j0 + 1] * fj
        hi = s_hi[j0] * (1 - fj) + s_hi[j0 + 1] * fj
        rl, rh = 0.0, 0.0
        for f in fracs:
            for side in range(2):
                off = f * up[i] if side == 0 else (-f) * down[i]
                j1, f1 = _d_cell(g, d[i] + off)
                lo2 = s_lo[j1] * (1 - f1) + s_lo[j1 + 1] * f1
                hi2 = s_hi[j1] * (1 - f1) + s_hi[j1 + 1] * f1
                rl, rh = _maximum(rl, lo - lo2), _maximum(rh, hi2 - hi)
        run_lo[i], run_hi[i] = rl, rh
    return run_lo, run_hi


@njit(cache=True, nogil=True, error_model="numpy")
def band_runs(inside, tau, half, run_lo, run_hi):
    """The runs of ``inside`` (P, nt) along each plane as sections of a whole (untrimmed)
    footprint (``sections._stretches`` then ``_on_material``): (plane, tau_a, tau_b,
    edge_lo, edge_hi, run_lo, run_hi) per run, the ends widened by ``half`` and clipped to
    [0, 1], an end on the edge with its plane's run (``run_lo`` / ``run_hi`` (P,))."""
    P, nt = inside.shape
    n = 0
    for i in range(P):
        for t in range(nt):
            if inside[i, t] and (t == 0 or not inside[i, t - 1]):
                n += 1
    plane, ta, tb = np.empty(n, np.int64), np.empty(n), np.empty(n)
    at = 0
    for i in range(P):
        for t in range(nt):
            if not inside[i, t]:
                continue
            if t == 0 or not inside[i, t - 1]:
                plane[at], ta[at] = i, _unit_clip(tau[t] - half)
            if t == nt - 1 or not inside[i, t + 1]:
                tb[at] = _unit_clip(tau[t] + half)
                at += 1
    lo, hi = np.empty(n), np.empty(n)  # cut to the plane's one stretch [0, 1]
    m = 0
    for r in range(n):
        lo[r] = _maximum(ta[r], 0.0)
        hi[r] = tb[r] if (tb[r] < 1.0 or tb[r] != tb[r]) else 1.0  # np.minimum
        m += hi[r] > lo[r]
    out_p, out_a, out_b = np.empty(m, np.int64), np.empty(m), np.empty(m)
    e_lo, e_hi = np.empty(m, np.bool_), np.empty(m, np.bool_)
    r_lo, r_hi = np.empty(m), np.empty(m)
    k = 0
    for r in range(n):
        if hi[r] > lo[r]:
            out_p[k], out_a[k], out_b[k] = plane[r], lo[r], hi[r]
            e_lo[k], e_hi[k] = 0.0 >= ta[r] - 1e-9, 1.0 <= tb[r] + 1e-9
            r_lo[k] = run_lo[plane[r]] if e_lo[k] else 0.0
            r_hi[k] = run_hi[plane[r]] if e_hi[k] else 0.0
            k += 1
    return out_p, out_a, out_b, e_lo, e_hi, r_lo, r_hi


@njit(cache=True, nogil=True, error_model="numpy")
def band_inside(g, U, V, labels, z, s, d2, lo2, span, maybe):
    """(P, nt) whether the band of each plane holds zone z at each feed sample: s (P, nt)
    the samples' feed coordinates; per sub-plane offset o and plane i the offset d2[o, i],
    its extent's start lo2[o, i] and span[o, i]; a sample is inside when on some sub-plane
    it lies within the extent (1e-9) and its seed's mesh cell carries label z. ``maybe``
    (table cells): False where no seed of the cell can fall in a cell of zone z
    (:func:`zone_cells`), those samples are not seeded."""
    P, nt = s.shape
    n, m = labels.shape
    ntab = U.shape[1]
    inside = np.zeros((P, nt), np.bool_)
    for o in range(d2.shape[0]):
        for i in range(P):
            j0, fj = _d_cell(g, d2[o, i])
            lo, sp = lo2[o, i], span[o, i]
            for t in range(nt):
                if inside[i, t]:
                    continue  # already inside: another sub-plane cannot change it
                t2 = (s[i, t] - lo) / sp
                if not ((t2 >= -1e-9) & (t2 <= 1 + 1e-9)):
                    continue
                t0, ft = _tau_cell(t2, ntab)
                if not maybe[j0, t0] and fj == fj:
                    continue
                u, v = _bilinear(U, V, j0, fj, t0, ft)
                a = min(max(np.int64(u * n) if u == u else 0, 0), n - 1)
                b = min(max(np.int64(v * m) if v == v else 0, 0), m - 1)
                if labels[a, b] == z:
                    inside[i, t] = True
    return inside


def zone_cells(U, V, labels, z, margin: float = 1e-9) -> np.ndarray:
    """(n_d - 1, n_tau - 1) bool: whether a seed in each table cell can fall in a mesh cell
    labelled z. A seed is a convex combination of its cell's four corners (weights in
    [0, 1]), so its u lies within the corners' range (``margin`` covers the round-off of
    the weights' sum) and its mesh row within that range's rows; likewise v. False: the
    box of mesh cells holds no cell of zone z (a summed-area count)."""
    n, m = labels.shape
    corners = [(U[:-1, :-1], U[:-1, 1:], U[1:, :-1], U[1:, 1:]),
               (V[:-1, :-1], V[:-1, 1:], V[1:, :-1], V[1:, 1:])]
    box = []
    for c, size in zip(corners, (n, m)):
        lo = np.minimum(np.minimum(c[0], c[1]), np.minimum(c[2], c[3])) - margin
        hi = np.maximum(np.maximum(c[0], c[1]), np.maximum(c[2], c[3])) + margin
        box.append((np.clip(np.trunc(lo * size), 0, size - 1).astype(np.int64),
                    np.clip(np.trunc(hi * size), 0, size - 1).astype(np.int64)))
    (a0, a1), (b0, b1) = box
    sat = np.zeros((n + 1, m + 1), np.int64)
    sat[1:, 1:] = np.cumsum(np.cumsum(labels == z, axis=0), axis=1)
    count = sat[a1 + 1, b1 + 1] - sat[a0, b1 + 1] - sat[a1 + 1, b0] + sat[a0, b0]
    return count > 0
