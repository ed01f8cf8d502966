"""3-axis drop-cutter against an exact parametric surface.

A vertical cutter with its tip at (x, y, t) occupies, over a point at radial distance rho
from its axis, the heights above t + height(rho). It does not penetrate the surface patch
where every surface point q with rho_q <= R has z_q <= t + height(rho_q); the drop-cutter
tip is the lowest such t:

    t(x, y) = max over q in the patch, |xy_q - xy| <= R, of  z_q - height(rho_q)

(the classical drop-cutter of the CAM literature, here against the exact surface rather
than a triangulation). f(u, v) = z - height(rho) is maximised over the part D of the unit
square whose XY lies in the cutter's disk. Its maximum lies at one of:

A. a stationary point of f inside D, on a patch edge, or at a patch corner: projected
   Newton in (u, v) (bounds as an active set, the Hessian shifted to be definite,
   a monotone backtracking line search), seeded at the best grid points of the disk (the
   best overall and the best of each quadrant within a slack of it: ``drop_seeds.py``, one
   compiled pass over the queries);
B. the highest point of z on the rim circle |xy - c| = R (the flat-end's rim contact):
   samples about one grid spacing apart on the circle, through the inverse map
   XY -> (u, v), then a golden-section search around the best;
C. a crossing of the rim circle with a patch edge: bisection along the edge.

B and C are needed only by profiles of finite slope at the rim (the flat-end, or a cone):
a torus or ball rises vertically there, so moving inwards always lowers it more than any
finite surface slope raises the surface, and its rim is never the contact.

Every candidate is a feasible point, so the result is a lower bound of the true maximum
that reaches it when the seeds sit in the right basins; the dense grid seeds (spacing
R / 10 by default) make that so for parts whose features are larger than the grid.
Queries whose disk holds no grid point (it grazes the patch) start A from the edge point
nearest the axis; -inf when nothing is touched.
"""

from __future__ import annotations

import numpy as np

from .drop_rim import edge_candidates, group_argmax, rim_candidates
from .drop_seeds import drop_seeds
from .surface_grid import surface_grid

__all__ = ["drop_cutter"]


def _f(cutter, surface, uv, c, order=0):
    jet = surface.jet(uv[:, 0], uv[:, 1], order=order)
    d = jet.p[:, :2] - c
    g, g1, g2 = cutter.height_jet(0.5 * np.einsum("ij,ij->i", d, d))
    return jet.p[:, 2] - g, jet, d, g1, g2


def _newton(cutter, surface, uv, c, iterations):
    """Candidates A: projected Newton ascent of f from uv (m, 2) for cutter centres c."""
    uv = uv.copy()
    big = cutter.radius
    active = np.ones(len(uv), bool)
    for _ in range(iterations):
        i = np.flatnonzero(active)
        if len(i) == 0:
            break
        f, jet, d, g1, g2 = _f(cutter, surface, uv[i], c[i], order=2)
        xu, xv = jet.su[:, :2], jet.sv[:, :2]
        su = np.einsum("ij,ij->i", d, xu)
        sv = np.einsum("ij,ij->i", d, xv)
        gu = jet.su[:, 2] - g1 * su
        gv = jet.sv[:, 2] - g1 * sv
        # M = -Hessian of f (f = z - g(s), s = |d|^2 / 2)
        m11 = -(jet.suu[:, 2] - g2 * su * su - g1 * (np.einsum("ij,ij->i", xu, xu)
                                                     + np.einsum("ij,ij->i", d, jet.suu[:, :2])))
        m12 = -(jet.suv[:, 2] - g2 * su * sv - g1 * (np.einsum("ij,ij->i", xu, xv)
                                                     + np.einsum("ij,ij->i", d, jet.suv[:, :2])))
        m22 = -(jet.svv[:, 2] - g2 * sv * sv - g1 * (np.einsum("ij,ij->i", xv, xv)
                                                     + np.einsum("ij,ij->i", d, jet.svv[:, :2])))
        u, v = uv[i, 0], uv[i, 1]
        fu = ((u <= 0) & (gu < 0)) | ((u >= 1) & (gu > 0))
        fv = ((v <= 0) & (gv < 0)) | ((v >= 1) & (gv > 0))
        gu, gv = np.where(fu, 0.0, gu), np.where(fv, 0.0, gv)
        m12 = np.where(fu | fv, 0.0, m12)
        m11, m22 = np.where(fu, 1.0, m11), np.where(fv, 1.0, m22)
        bad = ~(np.isfinite(m11) & np.isfinite(m12) & np.isfinite(m22)
                & np.isfinite(gu) & np.isfinite(gv))  # on the rim of a torus: stop there
        m11, m12, m22, gu, gv = (np.where(bad, 0.0, x) for x in (m11, m12, m22, gu, gv))
        scale = np.abs(m11) + np.abs(m22) + np.abs(m12) + 1e-12
        lam = 0.5 * (m11 + m22) - np.sqrt(0.25 * (m11 - m22) ** 2 + m12 * m12)
        shift = np.where(lam <= 1e-9 * scale, 1e-3 * scale - lam, 0.0)
        m11, m22 = m11 + shift, m22 + shift
        det = m11 * m22 - m12 * m12
        du = (m22 * gu - m12 * gv) / det
        dv = (m11 * gv - m12 * gu) / det
        dx = du[:, None] * xu + dv[:, None] * xv
        # at most R / 2 in XY, and (to first order) not past the rim: |d + cap dx| <= R
        qa = np.maximum(np.einsum("ij,ij->i", dx, dx), 1e-300)
        qb = 2 * np.einsum("ij,ij->i", d, dx)
        qc = np.minimum(np.einsum("ij,ij->i", d, d) - big * big * (1 - 1e-12), 0.0)
        to_rim = (-qb + np.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
        cap = np.minimum(np.minimum(1.0, 0.5 * big / np.sqrt(qa)), to_rim)
        step = np.stack([du, dv], 1) * cap[:, None]
        # monotone backtracking: accept the first halving that does not decrease f
        todo = np.arange(len(i))
        alpha = 1.0
        for _ in range(45):
            trial = np.clip(uv[i[todo]] + alpha * step[todo], 0.0, 1.0)
            ft = _f(cutter, surface, trial, c[i[todo]])[0]
            ok = ft >= f[todo]
            moved = np.abs(trial - uv[i[todo]]).max(axis=1)
            uv[i[todo[ok]]] = trial[ok]
            active[i[todo[ok]]] = (moved[ok] > 1e-15) & (ft[ok] > f[todo[ok]])
            todo = todo[~ok]
            if len(todo) == 0:
                break
            alpha *= 0.5
        active[i[todo]] = False
    return uv, _f(cutter, surface, uv, c)[0]


def drop_cutter(cutter, surface, xy, return_contact: bool = False, spacing: float | None = None,
                iterations: int = 40, chunk: int = 2048):
    """Tip z (k,) of the vertical ``cutter`` dropped on ``surface`` at XY (k, 2) (module doc).

    ``spacing``: the seed grid's XY spacing (default R / 10, within [0.05, 0.5] mm).
    ``return_contact``: also the contact parameters (k, 2) (nan where nothing is touched).
    """
    xy = np.asarray(xy, float).reshape(-1, 2)
    big = cutter.radius
    spacing = float(np.clip(big / 10, 0.05, 0.5)) if spacing is None else float(spacing)
    grid = surface_grid(surface, spacing)
    g_rim, slope_rim, _ = (float(x[0]) for x in cutter.height_jet(np.array([0.5 * big * big])))
    # a profile that rises vertically at the rim (torus, ball) never touches with the rim:
    # moving inwards lowers it faster than any finite surface slope (B and C are skipped)
    rim_contacts = np.isfinite(slope_rim)
    tips = np.full(len(xy), -np.inf)
    contact = np.full((len(xy), 2), np.nan)
    for start in range(0, len(xy), chunk):
        c = xy[start:start + chunk]
        k = len(c)
        seeds = drop_seeds(cutter, grid, c)
        cand_val, cand_uv = [np.full(k, -np.inf)], [np.full((k, 2), np.nan)]
        qa, sa = np.nonzero(seeds >= 0)
        key = seeds[qa, sa]
        first = np.unique(qa * (len(grid.u) + 1) + key, return_index=True)[1]
        qa, key = qa[first], key[first]
        uv0 = np.stack([grid.u[key], grid.v[key]], 1)
        lonely = np.flatnonzero(seeds[:, 0] < 0)  # no grid point in the disk
        if rim_contacts:
            uv_b, v_b = rim_candidates(cutter, surface, grid, c, g_rim)
            uv_c, v_c, uv_s, v_s = edge_candidates(cutter, surface, grid, c, g_rim)
            cand_val += [v_b, v_c]
            cand_uv += [uv_b, uv_c]
            uv_e, v_e = uv_s[lonely], v_s[lonely]
        else:
            uv_e, v_e = edge_candidates(cutter, surface, grid, c[lonely], g_rim)[2:]
        # a disk that only grazes the patch between grid points: Newton from the edge
        # point nearest the axis
        ok = np.isfinite(v_e)
        qa, uv0 = np.concatenate([qa, lonely[ok]]), np.concatenate([uv0, uv_e[ok]])
        if len(qa):
            uv, val = _newton(cutter, surface, uv0, c[qa], iterations)
            arg = group_argmax(qa, val, k)
            has = arg >= 0
            v_a, uv_a = np.full(k, -np.inf), np.full((k, 2), np.nan)
            v_a[has], uv_a[has] = val[arg[has]], uv[arg[has]]
            cand_val.append(v_a)
            cand_uv.append(uv_a)
        vals = np.stack(cand_val, 1)
        best = np.argmax(vals, axis=1)
        rows = np.arange(k)
        tips[start:start + k] = vals[rows, best]
        contact[start:start + k] = np.stack(cand_uv, 1)[rows, best]
    contact[~np.isfinite(tips)] = np.nan
    return (tips, contact) if return_contact else tips
