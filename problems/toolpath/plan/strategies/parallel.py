"""``parallel``: vertical planes parallel to each zone's feed direction, cut in zig-zag.

The planes are spaced by a fixed step-over (% of D, in XY) or adaptively at h_c (each plane
as far from the previous one as the worst point of its pass allows: Djebali Sec. 3.1,
Herraz Sec. 3); ``sections.py`` cuts them into sections (a single zone: every plane across
the footprint; zoned: wherever a plane's band holds zone material), ``points.py`` puts CC
points on them. Machining order: individual, zone, plane; a reversed plane's sections from
far to near.
"""

from __future__ import annotations

import numpy as np

from ...geometry.rows import ranges
from ...geometry.surface import unit_normal
from ...geometry.vectors import take_rows
from ..finish import finish
from ..orientation import travel_tangent
from ..points import sample_sections
from ..sections import Sections, full_plane_sections, zone_sections
from .base import Strategy

__all__ = ["Parallel", "pass_rank", "groups", "zone_groups"]


class Parallel(Strategy):
    name = "parallel"

    def plan(self, planner, genes, place):
        tool, n, step, delta = planner.decisions(genes)
        parts: list[Sections] = []
        zones = np.ones(n, np.int64)
        if planner.whole_planes:
            geom = planner.geometry(np.radians(planner.feed_angle))
            parts.append(full_plane_sections(geom, np.arange(n), delta, step))
        else:
            for layout, rows in zone_groups(planner, genes, tool):
                zones[rows] = layout.count
                for z in range(layout.count):
                    geom = planner.geometry(layout.alpha[z])
                    parts.append(zone_sections(geom, layout, z, rows, delta[rows], step[rows],
                                               planner.spacing))
        return _assemble(planner, n, zones, parts, tool, genes, place)


def zone_groups(planner, genes, tool):
    """[(layout, rows)]: the individuals grouped by zone layout (zoning gene value, tool)."""
    layouts = planner.layouts
    values = np.asarray(genes[layouts.gene], float) if layouts.gene else np.zeros(len(tool))
    return [(layouts.get(value, t), rows) for (value, t), rows in groups(values, tool, layouts)]


def _assemble(planner, n, zones, parts, tool, genes, place):
    """Sample every part's sections, order them for machining, hand them to ``finish``."""
    parts = [s for s in parts if len(s.d)]
    if not parts:
        raise ValueError("plan: no section holds a CC point (empty plan)")
    sampled = [sample_sections(s.geom, s.d, s.ta, s.tb, s.step, planner.tolerance,
                               planner.max_rounds) for s in parts]
    sec = {k: np.concatenate([getattr(s, k) for s in parts])
           for k in ("ind", "zone", "pass_k", "d", "ta", "tb", "spacing", "side", "run_lo",
                     "run_hi", "edge_lo", "edge_hi")}
    sec["alpha"] = np.concatenate([np.full(len(s.d), s.alpha) for s in parts])
    sec_off = np.cumsum([0] + [len(s.d) for s in parts])[:-1]
    pt_off = np.cumsum([0] + [len(sp.u) for sp in sampled])[:-1]
    start = np.concatenate([sp.sec_start + o for sp, o in zip(sampled, pt_off)])
    count = np.concatenate([sp.sec_count for sp in sampled])
    pts = {k: np.concatenate([getattr(sp, k) for sp in sampled])
           for k in ("u", "v", "p", "chord", "seg_err", "seg_len")}
    seg_sec = np.concatenate([sp.seg_sec + o for sp, o in zip(sampled, sec_off)])
    reverse = pass_rank(sec["ind"], sec["zone"], sec["pass_k"]) % 2 == 1
    # machining order: individual, zone, plane; a reversed plane's sections from far to near
    order = np.lexsort((np.where(reverse, -sec["ta"], sec["ta"]), sec["pass_k"],
                        sec["zone"], sec["ind"]))
    sec = {k: a[order] for k, a in sec.items()}
    reverse, count = reverse[order], count[order]
    new_start = np.cumsum(count) - count
    pt_sec, j = ranges(count)
    src = start[order][pt_sec] + np.where(reverse[pt_sec], count[pt_sec] - 1 - j, j)
    inv = np.empty(len(order), np.int64)
    inv[order] = np.arange(len(order))
    seg_order = np.argsort(inv[seg_sec], kind="stable")
    u, v, p, chord = (take_rows(pts[k], src) for k in ("u", "v", "p", "chord"))
    normal = unit_normal(planner.surface.jet(u, v, order=1), planner.surface.normal_sign)
    tangent = travel_tangent(normal, sec["alpha"], reverse, rows=pt_sec)
    seg = {"sec": inv[seg_sec][seg_order], "err": pts["seg_err"][seg_order],
           "len": pts["seg_len"][seg_order], "cc": np.ones(len(seg_order), bool)}
    pt = {"u": u, "v": v, "p": p, "chord": chord, "normal": normal, "tangent": tangent}
    lo_end, hi_end = sec["edge_lo"], sec["edge_hi"]  # ends on the footprint's edge
    return finish(planner, n, zones, sec, reverse, new_start, count, pt, seg, tool, genes,
                  place, np.where(reverse, hi_end, lo_end), np.where(reverse, lo_end, hi_end))


def pass_rank(ind, zone, pass_k):
    """Rank of each section's plane among the non-empty planes of its (individual, zone):
    the zig-zag alternates over the planes that are really cut."""
    o = np.lexsort((pass_k, zone, ind))
    g_new = np.r_[True, (ind[o][1:] != ind[o][:-1]) | (zone[o][1:] != zone[o][:-1])]
    p_new = g_new | np.r_[True, pass_k[o][1:] != pass_k[o][:-1]]
    cum = np.cumsum(p_new)
    rank = np.empty(len(o), np.int64)
    rank[o] = cum - np.maximum.accumulate(np.where(g_new, cum, 0))
    return rank


def groups(values, tool, layouts):
    """Individuals grouped by (zoning gene value, tool): [((value, tool), rows)]."""
    keys = np.stack([layouts.keys(values), np.asarray(tool, float)])
    uniq, inverse = np.unique(keys, axis=1, return_inverse=True)
    return [((layouts.key(v), int(t)), np.flatnonzero(inverse.ravel() == g))
            for g, (v, t) in enumerate(uniq.T)]
