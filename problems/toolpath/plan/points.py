"""CC points along the sections of pass planes: the maximum step, then the chord tolerance.

A section is a stretch [tau_a, tau_b] of one plane d (``planes.PassGeometry``; a whole
pass of a single-zone plan is [0, 1]). Its CC points (Fountas et al., "Experimental
validation": the maximum discretization step and the cut tolerance):

1. spaced uniformly in arc length with ceil(L / step) segments, so no chord exceeds the
   maximum discretization step, both ends included;
2. every segment whose chord error e exceeds the tolerance is split into
   m = ceil(sqrt(e / tol)) equal parts in the feed coordinate (the sagitta scales with the
   square of the length), and the new segments are checked again, until all meet the
   tolerance (at most ``max_rounds`` rounds).

The chord error of a segment is the true distance of the surface curve from the chord
(``geometry.chord.chord_deviation`` at the curve's mid-point, not Fountas Eq. 3 as
printed). Every section of a batch is handled at once: sections laid end to end, points
located by one bilinear seed and a Newton step, refinement on flat arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.chord import chord_deviation
from ..geometry.rows import interp_rows_numpy, ranges
from ..geometry.vectors import row_norms, take_rows
from .planes import PassGeometry, _vector
from .seed_kernel import section_points

__all__ = ["SectionPoints", "sample_sections", "section_points_numpy"]


@dataclass
class SectionPoints:
    """Points of S sections, each along +f (tau ascending), flattened.

    Points (N): ``u``, ``v``, ``p`` (N, 3), ``chord`` the larger chord error of the point's
    two segments. Segments (N - S): ``seg_sec``, ``seg_err``, ``seg_len``.
    ``sec_start``/``sec_count``.
    """

    sec_start: np.ndarray
    sec_count: np.ndarray
    u: np.ndarray
    v: np.ndarray
    p: np.ndarray
    chord: np.ndarray
    seg_sec: np.ndarray
    seg_err: np.ndarray
    seg_len: np.ndarray


def _arc_at(arc, tau_grid, tau):
    """Arc length along each row of ``arc`` (S, n_tau) at tau (S,)."""
    tf = np.clip(tau, 0.0, 1.0) * (len(tau_grid) - 1)
    t0 = np.clip(np.floor(tf).astype(int), 0, len(tau_grid) - 2)
    w = tf - t0
    rows = np.arange(len(tau))
    return arc[rows, t0] * (1 - w) + arc[rows, t0 + 1] * w


def section_points_numpy(geom: PassGeometry, d, ta, tb, step):
    """``seed_kernel.section_points`` in numpy (the reference the compiled pass is tested
    against): (pt_sec, tau, segment starts) of the sections' first points, ceil(L / step)
    segments each uniformly in arc length."""
    d, ta, tb = (np.asarray(a, float) for a in (d, ta, tb))
    step = np.broadcast_to(np.asarray(step, float), d.shape)
    arc = geom.arc_rows(d)
    a0, a1 = _arc_at(arc, geom.tau_grid, ta), _arc_at(arc, geom.tau_grid, tb)
    length = np.maximum(a1 - a0, 0.0)
    nseg = np.maximum(np.ceil(length / step - 1e-9).astype(int), 1)
    pt_sec, q = ranges(nseg + 1)
    target = a0[pt_sec] + q / nseg[pt_sec] * length[pt_sec]
    # row by row: a plan's points never depend on the other plans of its batch
    tau = interp_rows_numpy(arc, geom.tau_grid, target, pt_sec)
    tau = np.where(q == 0, ta[pt_sec], np.where(q == nseg[pt_sec], tb[pt_sec], tau))
    first = np.ones(len(tau), bool)
    first[1:] = pt_sec[1:] != pt_sec[:-1]
    return pt_sec, tau, np.flatnonzero(~np.r_[first[1:], True])


def sample_sections(geom: PassGeometry, d, ta, tb, step, tol: float,
                    max_rounds: int = 6) -> SectionPoints:
    """CC points of S sections: plane offsets d (S,), feed stretches [ta, tb] (S,) of the
    normalized feed coordinate, maximum step (S,) mm, cut tolerance tol (mm)."""
    d, ta, tb = (_vector(a) for a in (d, ta, tb))
    step = _vector(step, d.shape)
    n_sec = len(d)
    pt_sec, tau, a = section_points(geom.d_grid, geom.arc, geom.tau_grid, d, ta, tb, step)
    u, v, p = geom.locate(d[pt_sec], tau)
    b = a + 1
    seg = {"sec": take_rows(pt_sec, a), "ta": take_rows(tau, a), "tb": take_rows(tau, b),
           "pa": take_rows(p, a), "pb": take_rows(p, b), "ua": take_rows(u, a),
           "va": take_rows(v, a), "ub": take_rows(u, b), "vb": take_rows(v, b)}
    # the segments stay in machining order (section, then tau): a split segment's parts
    # take its place, so only the parts made in the last round are checked
    f, fresh, err = seg, np.arange(len(a)), np.empty(len(a))
    for rnd in range(max_rounds + 1):
        _, _, pm = geom.locate(d[f["sec"]], 0.5 * (f["ta"] + f["tb"]))
        e = chord_deviation(f["pa"], pm, f["pb"])
        err[fresh] = e
        split = np.flatnonzero(e > tol)
        if rnd == max_rounds or not split.size:
            break
        m = np.minimum(np.ceil(np.sqrt(e[split] / tol) - 1e-12), 64).astype(int)
        f = _split(geom, d, {k: take_rows(x, split) for k, x in f.items()}, m)
        seg, err, fresh = _replace(seg, err, fresh[split], m, f)
    s = seg | {"err": err}
    # points: segment starts, plus the end of each section's last segment
    segs_per_sec = np.bincount(s["sec"], minlength=n_sec)
    n_seg = len(s["sec"])
    n_pts = n_seg + n_sec
    start_idx = np.arange(n_seg) + s["sec"]
    end_idx = np.cumsum(segs_per_sec) + np.arange(n_sec)
    last_seg = np.cumsum(segs_per_sec) - 1
    out = {}
    for name, src_a, src_b, shape in (("u", "ua", "ub", ()), ("v", "va", "vb", ()),
                                      ("p", "pa", "pb", (3,))):
        arr = np.empty((n_pts,) + shape)
        arr[start_idx] = s[src_a]
        arr[end_idx] = s[src_b][last_seg]
        out[name] = arr
    chord = np.zeros(n_pts)
    chord[start_idx] = s["err"]
    chord[start_idx + 1] = np.maximum(chord[start_idx + 1], s["err"])
    count = segs_per_sec + 1
    return SectionPoints(
        sec_start=np.cumsum(count) - count, sec_count=count, u=out["u"], v=out["v"],
        p=out["p"], chord=chord, seg_sec=s["sec"], seg_err=s["err"],
        seg_len=row_norms(s["pb"] - s["pa"]))


def _replace(seg, err, which, m, sub):
    """The segments (dict of arrays, in order) with segment ``which[i]`` replaced in place
    by its m[i] parts ``sub`` (in order, grouped by segment): (segments, errors (the parts'
    left to fill), the parts' positions)."""
    parts = np.ones(len(err), int)
    parts[which] = m
    start = np.cumsum(parts) - parts
    n_new = int(parts.sum())
    keep = np.ones(len(err), bool)
    keep[which] = False
    kept, kept_at = np.flatnonzero(keep), start[keep]
    owner, j = ranges(m)
    sub_at = start[which][owner] + j
    out = {}
    for k, x in seg.items():
        arr = np.empty((n_new,) + x.shape[1:], x.dtype)
        arr[kept_at] = take_rows(x, kept)
        arr[sub_at] = sub[k]
        out[k] = arr
    new_err = np.empty(n_new)
    new_err[kept_at] = take_rows(err, kept)
    return out, new_err, sub_at


def _split(geom, d, seg, m):
    """Split segments into m (k,) equal parts in tau; returns the sub-segment arrays."""
    owner, j = ranges(m - 1)
    j = j + 1
    dt = seg["tb"] - seg["ta"]
    t_in = seg["ta"][owner] + dt[owner] * j / m[owner]
    u_in, v_in, p_in = geom.locate(d[seg["sec"][owner]], t_in)
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
    sec = np.repeat(seg["sec"], m)
    return dict(sec=sec, ta=out_t[i0], tb=out_t[i1], pa=out_p[i0], pb=out_p[i1],
                ua=out_u[i0], va=out_v[i0], ub=out_u[i1], vb=out_v[i1])
