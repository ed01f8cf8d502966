"""Pass planes over a surface for one feed direction: the gene-independent tables.

Passes are the sections of the surface by vertical planes parallel to the feed direction
(angle ``feed_angle`` from +X). With f the horizontal feed unit vector and c = z x f the
cross-feed one, a plane is {p on S : c.p = d}; along it, tau in [0, 1] is the normalized
feed coordinate between the plane's entry into and exit from the footprint.

:class:`PassGeometry` tabulates, once per surface and direction, the footprint's extent
along each plane, the inverse map (d, tau) -> (u, v) on a grid and the cumulative arc length
along the planes, so that a batch of plans locates its points with one bilinear seed and a
Newton step, with no Python loop per plan, pass or point.

Assumption: the surface is a graph over its XY footprint (no vertical walls or overhangs).
A plane may meet a trimmed or non-convex footprint several times: tau then runs from its
first entry to its last exit, and :meth:`PassGeometry.material` gives the stretches between
that are material (each one a section of the plan).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..geometry.crossings import edges_of, line_intervals
from ..geometry.footprint import footprint_of
from ..geometry.surface import Surface
from .seed_kernel import extent, newton_step, seed_feed, seed_uv

__all__ = ["PassGeometry"]

#: degrees: a footprint's boundary turning by more than this at a vertex is a corner
CORNER_DEG = 10.0


def _with_corners(grid, loops, c, tol):
    """The offsets ``grid`` (sorted) with the offsets c . p of the footprint's corners (the
    loops' vertices where the boundary turns by more than ``CORNER_DEG``) added, those
    within ``tol`` of a node left out. A plane's extent along the feed is linear in its
    offset between two corners' offsets (the boundary is straight or smooth there) but
    has a kink at each one: a table on a uniform grid interpolates across the kink, and a
    plane near a corner gets the extent of a plane a grid step away (measured: the last
    plane of a zone fed at 179.5 deg on Choi's square, 0.5 mm from the edge, got 42.2 of
    its 50.8 mm)."""
    extra = []
    for lp in loops:
        a = np.asarray(lp, float)
        a = a[np.r_[True, np.any(np.abs(np.diff(a, axis=0)) > 1e-12, axis=1)]]
        if len(a) > 1 and np.allclose(a[0], a[-1]):
            a = a[:-1]  # the loop closed on its first point; repeated points dropped
        e_in = a - np.roll(a, 1, axis=0)
        e_out = np.roll(a, -1, axis=0) - a
        cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
        turn = np.abs(np.arctan2(cross, np.sum(e_in * e_out, axis=1)))
        extra.append(a[turn > np.radians(CORNER_DEG)] @ c)
    extra = np.concatenate(extra) if extra else np.zeros(0)
    extra = extra[(extra > grid[0] + tol) & (extra < grid[-1] - tol)]
    near = np.abs(extra[:, None] - grid[None, :]).min(axis=1, initial=np.inf) <= tol
    out = np.unique(np.concatenate([grid, extra[~near]]))
    keep = np.r_[True, np.diff(out) > tol]
    return out[keep]


def _vector(x, shape=None) -> np.ndarray:
    """x as a C-contiguous, writable float64 array (broadcast to ``shape``): the one type the
    compiled passes take."""
    x = np.asarray(x, float)
    if shape is not None and x.shape != shape:
        x = np.broadcast_to(x, shape)
    return x if x.flags.c_contiguous and x.flags.writeable else np.array(x, float)


def newton_step_numpy(d, s, u, v, pc, pf, a11, a12, a21, a22):
    """``seed_kernel.newton_step`` in numpy (the reference the compiled pass is tested
    against): the new (u, v) and the steps (du, dv)."""
    r1, r2 = pc - d, pf - s
    det = a11 * a22 - a12 * a21
    det = np.where(np.abs(det) > 1e-300, det, 1e-300)
    un = np.clip(u - (a22 * r1 - a12 * r2) / det, 0.0, 1.0)
    vn = np.clip(v - (a11 * r2 - a21 * r1) / det, 0.0, 1.0)
    return un, vn, un - u, vn - v


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
        fp = footprint_of(surface)
        if fp.whole:
            t = np.linspace(0.0, 1.0, n_boundary)
            one, zero = np.ones_like(t), np.zeros_like(t)
            bu = np.concatenate([t, one, 1 - t, zero])
            bv = np.concatenate([zero, t, one, 1 - t])
            loops = [surface.jet(bu, bv, order=0).p[:, :2]]
        else:  # a trimmed footprint: its outer loop and holes
            loops = fp.xy_loops(surface, 1.0 / n_boundary)
        #: the footprint's loops as (s, d) (None: the whole square, one stretch a plane)
        self.loops_sd = None if fp.whole else [lp @ np.stack([self.f, self.c], 1) for lp in loops]
        (a, b) = edges_of(loops)
        bd, bs = a @ self.c, a @ self.f
        self.d_min, self.d_max = float(bd.min()), float(bd.max())
        self.width = self.d_max - self.d_min
        if not self.width > 0:
            raise ValueError("surface: the footprint has no width across the feed direction")
        eps = 1e-9 * self.width
        self.d_grid = _with_corners(np.linspace(self.d_min + eps, self.d_max - eps, n_d),
                                    loops, self.c, 1e-6 * self.width)
        n_d = len(self.d_grid)
        self.tau_grid = np.linspace(0.0, 1.0, n_tau)
        # extent of each plane in the footprint: crossings of the closed boundary polyline
        da, db = bd, b @ self.c
        sa, sb = bs, b @ self.f
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
        """Solve c.S(u, v) = d, f.S(u, v) = s (the XY position) by Newton, u, v in [0, 1],
        at most ``iters`` steps (fewer once every step is below 1e-13 in u and v).

        With ``with_points`` also returns the points, linearized from the last jet
        (p + su du + sv dv: error ~ curvature x step^2, ~1e-9 mm from a table seed).
        """
        c, f = self.c, self.f
        u, v = _vector(u), _vector(v)
        d, s = _vector(d, u.shape), _vector(s, u.shape)
        for it in range(iters):
            j = self.surface.jet(u, v, order=1)
            u, v, du, dv = newton_step(  # one compiled pass after numpy's projections
                d, s, u, v, j.p[:, :2] @ c, j.p[:, :2] @ f, j.su[:, :2] @ c, j.sv[:, :2] @ c,
                j.su[:, :2] @ f, j.sv[:, :2] @ f)
            if it + 1 < iters and max(np.abs(du).max(initial=0.0),
                                      np.abs(dv).max(initial=0.0)) < 1e-13:
                break  # converged (quadratically, from a close seed: ~5 steps for the table)
        if not with_points:
            return u, v
        return u, v, j.p + j.su * du[:, None] + j.sv * dv[:, None]

    def _index(self, d):
        g = self.d_grid
        j0 = np.clip(np.searchsorted(g, d, side="right") - 1, 0, len(g) - 2)
        return j0, np.clip((d - g[j0]) / (g[j0 + 1] - g[j0]), 0.0, 1.0)

    def pass_extent(self, d):
        """(s_lo, s_hi) of planes d: (n,) each (linear in the d table). One compiled pass
        (``seed_kernel.extent``): the numbers of :meth:`pass_extent_numpy`, bit for bit."""
        d = np.asarray(d, float)
        lo, hi = extent(self.d_grid, self.s_lo, self.s_hi, np.ascontiguousarray(d.ravel()))
        return lo.reshape(d.shape), hi.reshape(d.shape)

    def pass_extent_numpy(self, d):
        """:meth:`pass_extent` in numpy (the reference the compiled pass is tested against)."""
        j0, fj = self._index(d)
        lo = self.s_lo[j0] * (1 - fj) + self.s_lo[j0 + 1] * fj
        hi = self.s_hi[j0] * (1 - fj) + self.s_hi[j0 + 1] * fj
        return lo, hi

    def material(self, d):
        """The stretches of planes d (n,) inside the footprint: (plane index, tau_a, tau_b,
        first, last) in order along each plane (``first`` / ``last``: the plane's first and
        last stretch). The whole square gives every plane [0, 1]; a trimmed footprint the
        crossings of the plane with its loops (``crossings.line_intervals``), exact, in the
        tau of :meth:`pass_extent` (so a stretch may reach a little past [0, 1], where the
        extent table's linear interpolation falls short of the true boundary)."""
        d = np.asarray(d, float)
        if self.loops_sd is None:
            one = np.ones(len(d), bool)
            return np.arange(len(d)), np.zeros(len(d)), np.ones(len(d)), one, one
        eps = 1e-9 * self.width  # a plane on the extreme offset grazes the boundary
        q = np.clip(d, self.d_min + eps, self.d_max - eps)
        line, sa, sb, first, last = line_intervals(self.loops_sd, q)
        lo, hi = self.pass_extent(d[line])
        span = np.where(hi > lo, hi - lo, 1.0)
        return line, (sa - lo) / span, (sb - lo) / span, first, last

    def arc_rows(self, d):
        """Cumulative arc length along planes d at tau_grid: (n, n_tau)."""
        j0, fj = self._index(d)
        return self.arc[j0] * (1 - fj)[:, None] + self.arc[j0 + 1] * fj[:, None]

    def seed(self, d, tau):
        """(u, v) of plane points (d, tau) by bilinear interpolation of the table alone
        (~1e-3 mm off on Fountas' surface: enough to tell which mesh cell holds a point).
        One compiled pass (``seed_kernel.seed_uv``): the numbers of :meth:`seed_numpy`, bit
        for bit."""
        d = np.ascontiguousarray(np.broadcast_to(np.asarray(d, float), np.shape(tau)).ravel())
        tau = np.ascontiguousarray(np.asarray(tau, float).ravel())
        return seed_uv(self.d_grid, self.U, self.V, d, tau)

    def seed_numpy(self, d, tau):
        """:meth:`seed` in numpy (the reference the compiled pass is tested against)."""
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
        return u, v

    def locate(self, d, tau, iters: int = 1):
        """(u, v, points) of the pass points at planes d, normalized feed coordinates tau.

        Bilinear seed from the table (:meth:`seed`), then ``iters`` Newton steps: one step
        is within ~1e-8 mm, two reach round-off (tested).
        """
        d, tau = np.asarray(d, float), np.asarray(tau, float)
        if d.shape == tau.shape and d.ndim == 1:  # one compiled pass: seed and feed coordinate
            d, tau = _vector(d), _vector(tau)
            u, v, s = seed_feed(self.d_grid, self.U, self.V, self.s_lo, self.s_hi, d, tau)
        else:
            u, v = self.seed(d, tau)
            lo, hi = self.pass_extent(d)
            s = lo + tau * (hi - lo)
        return self._newton(d, s, u, v, max(iters, 1), with_points=True)
