"""Zig-zag parallel-plane strategy: the CC pattern of a whole batch of parameter sets.

Strategy (Fountas et al., "Experimental validation": multi-axis zig-zag sweeping, feed along
X, cut tolerance 0.01 mm):

- Passes are the sections of the surface by vertical planes parallel to the feed direction
  (angle ``feed_angle`` from +X, default 0). Let f be the horizontal feed unit vector and
  c = z x f the cross-feed one; a pass is {p on S : c.p = d}.
- **Step-over is measured in XY between the planes**, as CAM systems do: d_k = d_min + k
  delta with delta = step-over % x D, the last pass clamped on the far edge (d_max), so the
  last spacing may be shorter. On a slope the CC points of adjacent passes are further apart
  on the surface (delta / (b.c), with b the cross-feed tangent); the scallop uses that
  surface distance.
- Along a pass the CC points are first spaced uniformly in arc length with
  ceil(L / step) segments (so no chord exceeds the maximum discretization step). Then every
  segment whose chord error e exceeds the tolerance is split into
  m = ceil(sqrt(e / tol)) equal parts in the feed coordinate (the sagitta scales with the
  square of the length), and the new segments are checked again, until all meet the
  tolerance (at most ``max_rounds`` rounds).
- Pass 0 travels along +f, pass 1 along -f, and so on.

Precomputation (gene independent, :class:`PassGeometry`): the footprint's extent along each
plane, the inverse map (d, tau) -> (u, v) on a grid (tau in [0, 1] the normalized feed
coordinate along a pass), and the cumulative arc length along the passes. A batch then needs
no Python loop per individual, pass or point: passes of all individuals are laid end to end,
the points located by one bilinear seed + Newton solve on the planes, and the refinement
works on flat arrays.

Assumptions: the surface is a graph over its XY footprint (no vertical walls or overhangs)
and each plane meets the footprint in one interval (e.g. a convex footprint).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..geometry.chord import chord_deviation
from ..geometry.surface import Surface

__all__ = ["PassGeometry", "PatternBatch", "cc_pattern_batch"]


class PassGeometry:
    """Gene-independent tables of the pass planes over a surface for one feed direction.

    surface: the part; feed_angle: degrees from +X; n_d, n_tau: table sizes across and
    along the passes.
    """

    def __init__(self, surface: Surface, feed_angle: float = 0.0, n_d: int = 129,
                 n_tau: int = 65, n_boundary: int = 1024):
        self.surface = surface
        al = np.radians(feed_angle)
        self.f = np.array([np.cos(al), np.sin(al)])
        self.c = np.array([-np.sin(al), np.cos(al)])
        t = np.linspace(0.0, 1.0, n_boundary)
        one, zero = np.ones_like(t), np.zeros_like(t)
        bu = np.concatenate([t, one, 1 - t, zero])
        bv = np.concatenate([zero, t, one, 1 - t])
        bp = surface.jet(bu, bv, order=0).p
        bd, bs = bp[:, :2] @ self.c, bp[:, :2] @ self.f
        self.d_min, self.d_max = float(bd.min()), float(bd.max())
        self.width = self.d_max - self.d_min
        if not self.width > 0:
            raise ValueError("surface: the footprint has no width across the feed direction")
        eps = 1e-9 * self.width
        self.d_grid = np.linspace(self.d_min + eps, self.d_max - eps, n_d)
        self.tau_grid = np.linspace(0.0, 1.0, n_tau)
        # extent of each plane in the footprint: crossings of the closed boundary polyline
        da, db = bd, np.roll(bd, -1)
        sa, sb = bs, np.roll(bs, -1)
        dj = self.d_grid[:, None]
        hit = (da - dj) * (db - dj) <= 0
        with np.errstate(divide="ignore", invalid="ignore"):
            frac = np.clip(np.where(db != da, (dj - da) / (db - da), 0.0), 0.0, 1.0)
        sx = sa + frac * (sb - sa)
        self.s_lo = np.where(hit, sx, np.inf).min(axis=1)
        self.s_hi = np.where(hit, sx, -np.inf).max(axis=1)
        # inverse map on the (d, tau) grid: nearest dense sample, then Newton
        dd = np.repeat(self.d_grid, n_tau)
        ss = (self.s_lo[:, None] + self.tau_grid[None, :] * (self.s_hi - self.s_lo)[:, None]).ravel()
        g = np.linspace(0.0, 1.0, 161)
        gu, gv = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
        gp = surface.jet(gu, gv, order=0).p
        tree = cKDTree(np.stack([gp[:, :2] @ self.c, gp[:, :2] @ self.f], axis=1))
        _, idx = tree.query(np.stack([dd, ss], axis=1))
        u, v = self._newton(dd, ss, gu[idx], gv[idx], iters=30)
        self.U = u.reshape(n_d, n_tau)
        self.V = v.reshape(n_d, n_tau)
        p = surface.jet(u, v, order=0).p.reshape(n_d, n_tau, 3)
        seg = np.linalg.norm(np.diff(p, axis=1), axis=-1)
        self.arc = np.concatenate([np.zeros((n_d, 1)), np.cumsum(seg, axis=1)], axis=1)

    # ---------------------------------------------------------------------------------
    def _newton(self, d, s, u, v, iters: int, with_points: bool = False):
        """Solve c.S(u, v) = d, f.S(u, v) = s (the XY position) by Newton, u, v in [0, 1].

        With ``with_points`` also returns the points, linearized from the last jet
        (p + su du + sv dv: error ~ curvature x step^2, ~1e-9 mm from a table seed).
        """
        c, f = self.c, self.f
        for _ in range(iters):
            j = self.surface.jet(u, v, order=1)
            r1 = j.p[:, :2] @ c - d
            r2 = j.p[:, :2] @ f - s
            a11, a12 = j.su[:, :2] @ c, j.sv[:, :2] @ c
            a21, a22 = j.su[:, :2] @ f, j.sv[:, :2] @ f
            det = a11 * a22 - a12 * a21
            det = np.where(np.abs(det) > 1e-300, det, 1e-300)
            un = np.clip(u - (a22 * r1 - a12 * r2) / det, 0.0, 1.0)
            vn = np.clip(v - (a11 * r2 - a21 * r1) / det, 0.0, 1.0)
            du, dv, u, v = un - u, vn - v, un, vn
        if not with_points:
            return u, v
        if iters == 0:
            return u, v, self.surface.jet(u, v, order=0).p
        return u, v, j.p + j.su * du[:, None] + j.sv * dv[:, None]

    def _index(self, d):
        jf = (d - self.d_grid[0]) / (self.d_grid[-1] - self.d_grid[0]) * (len(self.d_grid) - 1)
        j0 = np.clip(np.floor(jf).astype(int), 0, len(self.d_grid) - 2)
        return j0, np.clip(jf - j0, 0.0, 1.0)

    def pass_extent(self, d):
        """(s_lo, s_hi) of planes d: (n,) each (linear in the d table)."""
        j0, fj = self._index(d)
        lo = self.s_lo[j0] * (1 - fj) + self.s_lo[j0 + 1] * fj
        hi = self.s_hi[j0] * (1 - fj) + self.s_hi[j0 + 1] * fj
        return lo, hi

    def arc_rows(self, d):
        """Cumulative arc length along planes d at tau_grid: (n, n_tau)."""
        j0, fj = self._index(d)
        return self.arc[j0] * (1 - fj)[:, None] + self.arc[j0 + 1] * fj[:, None]

    def locate(self, d, tau, iters: int = 1):
        """(u, v, points) of the pass points at planes d, normalized feed coordinates tau.

        Bilinear seed from the table (~1e-3 mm off on Fountas' surface), then ``iters``
        Newton steps: one step is within ~1e-8 mm, two reach round-off (tested).
        """
        j0, fj = self._index(d)
        tf = np.clip(tau, 0.0, 1.0) * (len(self.tau_grid) - 1)
        t0 = np.clip(np.floor(tf).astype(int), 0, len(self.tau_grid) - 2)
        ft = tf - t0
        w00, w01 = (1 - fj) * (1 - ft), (1 - fj) * ft
        w10, w11 = fj * (1 - ft), fj * ft
        u = (self.U[j0, t0] * w00 + self.U[j0, t0 + 1] * w01 + self.U[j0 + 1, t0] * w10
             + self.U[j0 + 1, t0 + 1] * w11)
        v = (self.V[j0, t0] * w00 + self.V[j0, t0 + 1] * w01 + self.V[j0 + 1, t0] * w10
             + self.V[j0 + 1, t0 + 1] * w11)
        lo, hi = self.pass_extent(d)
        return self._newton(d, lo + tau * (hi - lo), u, v, iters, with_points=True)


@dataclass
class PatternBatch:
    """CC patterns of a batch of parameter sets, flattened.

    Passes (P of them): ``pass_ind`` individual, ``pass_k`` index within its toolpath,
    ``pass_d`` plane position, ``pass_start``/``pass_count`` its CC points (sorted along +f,
    i.e. tau ascending; odd passes are machined in reverse order), ``pass_spacing`` the XY
    distance to the next pass (to the previous for the last pass; 0 for a single pass).
    Points (N): ``pt_pass``, ``tau``, ``u``, ``v``, ``p`` (N, 3), ``chord`` the larger chord
    error of the two segments at the point. Segments (N - P): ``seg_pass``, ``seg_err``,
    ``seg_len``, ``seg_start`` (index of the first point).
    """

    n: int
    pass_ind: np.ndarray
    pass_k: np.ndarray
    pass_d: np.ndarray
    pass_start: np.ndarray
    pass_count: np.ndarray
    pass_spacing: np.ndarray
    pt_pass: np.ndarray
    tau: np.ndarray
    u: np.ndarray
    v: np.ndarray
    p: np.ndarray
    chord: np.ndarray
    seg_pass: np.ndarray
    seg_err: np.ndarray
    seg_len: np.ndarray
    seg_start: np.ndarray


def _segments_error(geom, surface, seg_d, ta, tb, pa, pb):
    _, _, pm = geom.locate(seg_d, 0.5 * (ta + tb))
    return chord_deviation(pa, pm, pb)


def _ranges(counts):
    """For counts (k,): (owner (sum,), position within owner (sum,))."""
    owner = np.repeat(np.arange(len(counts)), counts)
    starts = np.cumsum(counts) - counts
    return owner, np.arange(owner.size) - starts[owner]


def cc_pattern_batch(geom: PassGeometry, delta, step, tol: float,
                     max_rounds: int = 6) -> PatternBatch:
    """CC patterns for n parameter sets: delta (n,) XY step-over (mm), step (n,) maximum
    discretization step (mm), tol the cut tolerance (mm). See the module docstring."""
    surface = geom.surface
    delta = np.asarray(delta, float)
    step = np.asarray(step, float)
    n = len(delta)
    # passes
    n_int = np.maximum(np.ceil(geom.width / delta - 1e-9).astype(int), 1)
    pass_ind, pass_k = _ranges(n_int + 1)
    pass_d = geom.d_min + np.minimum(pass_k * delta[pass_ind], geom.width)
    last = pass_k == n_int[pass_ind]
    nxt = np.minimum(np.arange(len(pass_d)) + 1, len(pass_d) - 1)
    prv = np.maximum(np.arange(len(pass_d)) - 1, 0)
    pass_spacing = np.where(last, pass_d - pass_d[prv], pass_d[nxt] - pass_d)
    # initial sampling, uniform in arc length
    arc = geom.arc_rows(pass_d)
    length = arc[:, -1]
    nseg = np.maximum(np.ceil(length / step[pass_ind] - 1e-9).astype(int), 1)
    pt_pass, q = _ranges(nseg + 1)
    target = q / nseg[pt_pass] * length[pt_pass]
    off = np.arange(len(pass_d)) * (float(length.max()) + 1.0)
    tau = np.interp(target + off[pt_pass], (arc + off[:, None]).ravel(),
                    np.tile(geom.tau_grid, len(pass_d)))
    tau = np.where(q == 0, 0.0, np.where(q == nseg[pt_pass], 1.0, tau))
    u, v, p = geom.locate(pass_d[pt_pass], tau)
    first = np.ones(len(tau), bool)
    first[1:] = pt_pass[1:] != pt_pass[:-1]
    a = np.flatnonzero(~np.r_[first[1:], True])  # segment starts: every point but a pass end
    b = a + 1
    seg = dict(pas=pt_pass[a], ta=tau[a], tb=tau[b], pa=p[a], pb=p[b],
               ua=u[a], va=v[a], ub=u[b], vb=v[b])
    keep = []
    for rnd in range(max_rounds + 1):
        err = _segments_error(geom, surface, pass_d[seg["pas"]], seg["ta"], seg["tb"],
                              seg["pa"], seg["pb"])
        split = err > tol
        if rnd == max_rounds or not split.any():
            keep.append({**seg, "err": err})
            break
        keep.append({k: x[~split] for k, x in seg.items()} | {"err": err[~split]})
        seg = _split(geom, surface, pass_d, {k: x[split] for k, x in seg.items()},
                     np.minimum(np.ceil(np.sqrt(err[split] / tol) - 1e-12), 64).astype(int))
    s = {k: np.concatenate([blk[k] for blk in keep]) for k in keep[0]}
    order = np.argsort(s["pas"] + s["ta"], kind="stable")
    s = {k: x[order] for k, x in s.items()}
    # points: segment starts, plus the end of each pass's last segment
    n_pass = len(pass_d)
    segs_per_pass = np.bincount(s["pas"], minlength=n_pass)
    n_pts = len(order) + n_pass
    start_idx = np.arange(len(order)) + s["pas"]
    end_idx = np.cumsum(segs_per_pass) + np.arange(n_pass)
    last_seg = np.cumsum(segs_per_pass) - 1
    out = {}
    for name, src_a, src_b, shape in (("tau", "ta", "tb", ()), ("u", "ua", "ub", ()),
                                      ("v", "va", "vb", ()), ("p", "pa", "pb", (3,))):
        arr = np.empty((n_pts,) + shape)
        arr[start_idx] = s[src_a]
        arr[end_idx] = s[src_b][last_seg]
        out[name] = arr
    chord = np.zeros(n_pts)
    chord[start_idx] = s["err"]
    chord[start_idx + 1] = np.maximum(chord[start_idx + 1], s["err"])
    pass_count = segs_per_pass + 1
    return PatternBatch(
        n=n, pass_ind=pass_ind, pass_k=pass_k, pass_d=pass_d,
        pass_start=np.cumsum(pass_count) - pass_count, pass_count=pass_count,
        pass_spacing=pass_spacing, pt_pass=np.repeat(np.arange(n_pass), pass_count),
        tau=out["tau"], u=out["u"], v=out["v"], p=out["p"], chord=chord,
        seg_pass=s["pas"], seg_err=s["err"],
        seg_len=np.linalg.norm(s["pb"] - s["pa"], axis=-1), seg_start=start_idx)


def _split(geom, surface, pass_d, seg, m):
    """Split segments into m (k,) equal parts in tau; returns the sub-segment arrays."""
    owner, j = _ranges(m - 1)
    j = j + 1
    dt = seg["tb"] - seg["ta"]
    t_in = seg["ta"][owner] + dt[owner] * j / m[owner]
    u_in, v_in, p_in = geom.locate(pass_d[seg["pas"][owner]], t_in)
    # boundary list per split segment: [a, interior..., b]
    blk = m + 1
    bstart = np.cumsum(blk) - blk
    nb = int(blk.sum())
    out_t, out_u, out_v = np.empty(nb), np.empty(nb), np.empty(nb)
    out_p = np.empty((nb, 3))
    for arr, ka, kb, inner in ((out_t, "ta", "tb", t_in), (out_u, "ua", "ub", u_in),
                               (out_v, "va", "vb", v_in), (out_p, "pa", "pb", p_in)):
        arr[bstart] = seg[ka]
        arr[bstart + m] = seg[kb]
        arr[bstart[owner] + j] = inner
    starts = np.ones(nb, bool)
    starts[bstart + m] = False
    i0 = np.flatnonzero(starts)
    i1 = i0 + 1
    pas = np.repeat(seg["pas"], m)
    return dict(pas=pas, ta=out_t[i0], tb=out_t[i1], pa=out_p[i0], pb=out_p[i1],
                ua=out_u[i0], va=out_v[i0], ub=out_u[i1], vb=out_v[i1])
