"""CC points along passes that are not planes (iso-scallop offsets, iso-parametric curves):
dense (u, v) polylines in, sections in machining order out (``finish.py`` does the rest).

A strategy gives, per (individual, zone), its passes as pieces: a dense (u, v) polyline
(points a fraction of a mm apart on the surface, already in the travel direction of the
zig-zag), and per dense point the horizontal unit vector ``cross`` towards the pass the
scallop is measured against and the XY distance ``gap`` to it (0: none). On each piece,
as on a plane section (``points.py``, Fountas et al. "Experimental validation"):

1. CC points uniformly in arc length with ceil(L / step) segments (both ends kept);
2. every segment whose chord error (the curve's distance from the chord at its mid-arc
   point, ``geometry.chord.chord_deviation``) exceeds the tolerance is split into
   ceil(sqrt(e / tol)) equal arc parts, again until all meet it (``max_rounds``).

The curve between dense points is the surface image of the straight (u, v) segment; the
travel tangent at a CC point is the central difference of its neighbours, in the tangent
plane.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..geometry.chord import chord_deviation
from ..geometry.rows import ranges
from ..geometry.surface import unit_normal
from .finish import finish

__all__ = ["Piece", "plan_pieces"]


@dataclass
class Piece:
    """One section: ``uv`` (M, 2) in travel order, ``cross`` (M, 3), ``gap`` (M,), its
    ``zone``, ``pass_k`` and the zone's ``alpha``; ``edge`` (head, tail): whether its ends lie
    on the footprint's edge (the travel runs on past them)."""

    uv: np.ndarray
    cross: np.ndarray
    gap: np.ndarray
    zone: int
    pass_k: int
    alpha: float = 0.0
    edge: tuple = field(default=(False, False))


def _on_edge(uv, eps=1e-7) -> bool:
    return bool(np.any((uv <= eps) | (uv >= 1 - eps)))


def plan_pieces(planner, n, zones, pieces_of, tool, genes, step, place):
    """The PlanBatch of n plans whose pieces are ``pieces_of[i]`` (a list of
    :class:`Piece` in machining order) for individual i, max step ``step`` (n,)."""
    surface, tol = planner.surface, planner.tolerance
    pcs = [(i, pc) for i in range(n) for pc in pieces_of[i] if len(pc.uv) >= 2]
    if not pcs:
        raise ValueError("plan: no section holds a CC point (empty plan)")
    S = len(pcs)
    m = np.array([len(pc.uv) for _, pc in pcs])
    owner, _ = ranges(m)
    uv = np.concatenate([pc.uv for _, pc in pcs])
    cross = np.concatenate([pc.cross for _, pc in pcs])
    gap = np.concatenate([pc.gap for _, pc in pcs])
    P = surface.jet(uv[:, 0], uv[:, 1], order=0).p
    d = np.linalg.norm(np.diff(P, axis=0), axis=1)
    d[owner[1:] != owner[:-1]] = 1.0  # a unit jump between pieces keeps the arc monotone
    arc = np.r_[0.0, np.cumsum(d)]
    first = np.cumsum(m) - m
    a0, a1 = arc[first], arc[first + m - 1]
    length = a1 - a0
    sec_step = np.asarray(step, float)[[i for i, _ in pcs]]
    nseg = np.maximum(np.ceil(length / sec_step - 1e-9).astype(int), 1)

    def at(s):
        return np.interp(s, arc, uv[:, 0]), np.interp(s, arc, uv[:, 1])

    pt_sec, q = ranges(nseg + 1)
    s_pts = a0[pt_sec] + q / nseg[pt_sec] * length[pt_sec]
    is_first = np.r_[True, pt_sec[1:] != pt_sec[:-1]]
    ia = np.flatnonzero(~np.r_[is_first[1:], True])
    seg = {"sec": pt_sec[ia], "sa": s_pts[ia], "sb": s_pts[ia + 1]}
    keep = []
    for rnd in range(planner.max_rounds + 1):
        ua, va = at(seg["sa"])
        ub, vb = at(seg["sb"])
        um, vm = at(0.5 * (seg["sa"] + seg["sb"]))
        pa, pm, pb = (surface.jet(x, y, order=0).p for x, y in ((ua, va), (um, vm), (ub, vb)))
        err = chord_deviation(pa, pm, pb)
        split = err > tol
        if rnd == planner.max_rounds or not split.any():
            keep.append({**seg, "err": err, "len": np.linalg.norm(pb - pa, axis=1)})
            break
        keep.append({k: x[~split] for k, x in seg.items()}
                    | {"err": err[~split], "len": np.linalg.norm(pb - pa, axis=1)[~split]})
        mm = np.minimum(np.ceil(np.sqrt(err[split] / tol) - 1e-12), 64).astype(int)
        o, j = ranges(mm)
        sa, sb = seg["sa"][split][o], seg["sb"][split][o]
        seg = {"sec": seg["sec"][split][o], "sa": sa + (sb - sa) * j / mm[o],
               "sb": sa + (sb - sa) * (j + 1) / mm[o]}
    sg = {k: np.concatenate([b[k] for b in keep]) for k in keep[0]}
    o = np.lexsort((sg["sa"], sg["sec"]))
    sg = {k: x[o] for k, x in sg.items()}
    per = np.bincount(sg["sec"], minlength=S)
    count = per + 1
    start = np.cumsum(count) - count
    pt_sec, j = ranges(count)
    s_all = np.empty(int(count.sum()))
    s_all[start[sg["sec"]] + (np.arange(len(o)) - (np.cumsum(per) - per)[sg["sec"]])] = sg["sa"]
    s_all[start + per] = a1
    u, v = at(s_all)
    jet = surface.jet(u, v, order=1)
    normal = unit_normal(jet, surface.normal_sign)
    p = jet.p
    chord = np.zeros(len(u))
    gi = start[sg["sec"]] + (np.arange(len(o)) - (np.cumsum(per) - per)[sg["sec"]])
    chord[gi] = sg["err"]
    chord[gi + 1] = np.maximum(chord[gi + 1], sg["err"])
    # travel tangent: central differences inside each section, in the tangent plane
    nxt = np.minimum(np.arange(len(u)) + 1, start[pt_sec] + count[pt_sec] - 1)
    prv = np.maximum(np.arange(len(u)) - 1, start[pt_sec])
    t = p[nxt] - p[prv]
    t -= np.einsum("ij,ij->i", t, normal)[:, None] * normal
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
    # a section whose points coincide (a contour's spine that is a point) has no travel of
    # its own: it is taken along its zone's feed direction, so that a 5-axis tool leans as
    # on the zone's other passes (with no tangent the axis fell back to the normal, and the
    # flat-bottomed torus gouged Fountas' concave part 0.178 mm at the spine)
    alpha = np.array([pc.alpha for _, pc in pcs], float)
    still = np.linalg.norm(t, axis=1) < 0.5
    if still.any():
        a = alpha[pt_sec[still]]
        f = np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])
        f -= np.einsum("ij,ij->i", f, normal[still])[:, None] * normal[still]
        t[still] = f / np.linalg.norm(f, axis=1, keepdims=True)
    c = np.column_stack([np.interp(s_all, arc, cross[:, k]) for k in range(3)])
    c[:, 2] = 0.0
    none = np.linalg.norm(c, axis=1) < 1e-9  # no neighbouring pass: across the travel
    c[none] = np.column_stack([-t[none, 1], t[none, 0], np.zeros(int(none.sum()))])
    c /= np.maximum(np.linalg.norm(c, axis=1, keepdims=True), 1e-300)
    g = np.interp(s_all, arc, gap)
    side = np.sign(-t[:, 1] * c[:, 0] + t[:, 0] * c[:, 1]) * (g > 0)
    sec = {"ind": np.array([i for i, _ in pcs]), "zone": np.array([pc.zone for _, pc in pcs]),
           "pass_k": np.array([pc.pass_k for _, pc in pcs]), "d": np.full(S, np.nan),
           "alpha": alpha,
           "spacing": np.bincount(pt_sec, g, S) / count,
           "side": np.ones(S, np.int64), "run_lo": np.zeros(S), "run_hi": np.zeros(S)}
    pts = {"u": u, "v": v, "p": p, "chord": chord, "normal": normal, "tangent": t,
           "cross": c, "gap": g, "gap_side": side}
    segd = {"sec": sg["sec"], "err": sg["err"], "len": sg["len"], "cc": np.ones(len(o), bool)}
    head = np.array([pc.edge[0] for _, pc in pcs], bool)
    tail = np.array([pc.edge[1] for _, pc in pcs], bool)
    return finish(planner, n, zones, sec, np.zeros(S, bool), start, count, pts, segd, tool,
                  genes, place, head, tail)
