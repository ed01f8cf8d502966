"""The stages every strategy shares once its sections hold CC points in machining order:
tool orientation, the edge run-on, the placement (CL points), the ``PlanBatch``.

A strategy (``strategies/``) hands over its sections (per section: individual, zone, pass,
the plane fields ``d`` / ``alpha`` / ``spacing`` / ``side`` / ``reverse`` where it has
planes, whether each end lies on the part's edge and how far the band extends past it) and
its points in machining order (``u``, ``v``, ``p``, ``chord``, the unit travel ``tangent``
and, for passes that are not planes, the per-point cross-feed ``cross``, ``gap`` and
``gap_side`` the analytic scallop reads); :func:`finish` does the rest, identically for all.
"""

from __future__ import annotations

import numpy as np

from ..geometry.rows import present, ranges
from ..geometry.surface import normal_curvature
from ..geometry.vectors import row_norms, take_rows
from .batch import PlanBatch
from .overrun import edge_overrun as add_overrun

__all__ = ["finish"]

_POINT_EXTRA = ("cross", "gap", "gap_side")


def finish(planner, n, zones, sec, reverse, start, count, pts, seg, tool, genes, place,
           at_head, at_tail) -> PlanBatch:
    """The PlanBatch of sections ``sec`` (dict of (S,) arrays: ind, zone, pass_k, d, alpha,
    spacing, side, run_lo, run_hi; in machining order), ``reverse`` (S,), their points
    ``start``/``count`` and ``pts`` (u, v, p, chord, normal, tangent; optional cross, gap,
    gap_side), moves ``seg`` (sec, err, len, cc), ``at_head`` / ``at_tail`` (S,): the
    section's first / last point lies on the footprint's edge (its travel runs on past it)."""
    pt_sec, _ = ranges(count)
    ind_pt = sec["ind"][pt_sec]
    machine = planner.machine
    axis = machine.axes(pts["normal"], pts["tangent"], {g: genes[g] for g in machine.genes},
                        ind_pt)
    pt = {k: pts[k] for k in ("u", "v", "p", "chord", "normal", "tangent") + _POINT_EXTRA
          if k in pts}
    pt["axis"] = axis
    p = pt["p"]
    on_part, shift = np.ones(len(p), bool), np.zeros_like(p)
    if planner.edge_overrun:
        # the tool's offset from its contact, at the sections' end points (all the run-on
        # reads): every other point keeps 0
        ahead, rho = np.zeros(len(p)), np.zeros(len(p))
        ends = np.unique(np.r_[start, start + count - 1])
        ends_tool = tool[ind_pt[ends]]
        for t in np.unique(ends_tool):
            sel = ends[ends_tool == t]
            p_sel = take_rows(p, sel)
            off = planner.tools.cutter(t).cc_to_tip(p_sel, take_rows(pt["normal"], sel),
                                                    take_rows(axis, sel)) - p_sel
            tan = take_rows(pt["tangent"], sel)
            ahead[sel] = np.sum(off[:, :2] * tan[:, :2], axis=1) / np.maximum(
                row_norms(tan[:, :2]), 1e-300)
            rho[sel] = row_norms(off[:, :2])
        wedge = 1.0 if machine.wedge else 0.0  # Machine.wedge
        pt, start, count, on_part, shift, (x_sec, x_len) = add_overrun(
            pt, start, count, at_head, at_tail,
            wedge * np.where(reverse, sec["run_hi"], sec["run_lo"]),
            wedge * np.where(reverse, sec["run_lo"], sec["run_hi"]), ahead,
            reach=wedge * rho)  # the contact's distance from the axis (overrun.py)
        seg = {"sec": np.r_[seg["sec"], x_sec], "err": np.r_[seg["err"], 0.0 * x_len],
               "len": np.r_[seg["len"], x_len],
               "cc": np.r_[seg["cc"], np.zeros(len(x_sec), bool)]}
        o = np.argsort(seg["sec"], kind="stable")
        seg = {k: a[o] for k, a in seg.items()}
        pt_sec, _ = ranges(count)
        ind_pt = sec["ind"][pt_sec]
    tip = None
    if place:
        tip = np.empty_like(pt["p"])
        bend = _bend(planner.surface, pt, on_part) if machine.bends else None
        for t in present(tool[ind_pt]):
            sel = tool[ind_pt] == t
            tip[sel] = machine.tips(planner.tools.cutter(t), planner.surface,
                                    pt["p"][sel] - shift[sel], pt["normal"][sel],
                                    pt["axis"][sel], shift[sel], bend if bend is None else bend[sel])
    extra = {k: pt.pop(k) for k in _POINT_EXTRA if k in pt}
    return PlanBatch(
        n=n, zones=zones, sec_ind=sec["ind"], sec_zone=sec["zone"], sec_pass=sec["pass_k"],
        sec_d=sec["d"], sec_alpha=sec["alpha"], sec_reverse=reverse,
        sec_spacing=sec["spacing"], sec_side=sec["side"], sec_start=start,
        sec_count=count, pt_sec=pt_sec, tip=tip, on_part=on_part, seg_sec=seg["sec"],
        seg_err=seg["err"], seg_len=seg["len"], seg_cc=seg["cc"], **pt,
        pt_cross=extra.get("cross"), pt_gap=extra.get("gap"),
        pt_gap_side=extra.get("gap_side"))


def _bend(surface, pt, on_part) -> np.ndarray:
    """The surface's normal curvature along the travel (1/mm, > 0 concave seen from the
    tool) at the CC point each run-on row repeats (its u, v, normal and tangent are those
    of the section's end point); 0 on the part."""
    bend = np.zeros(len(on_part))
    off = np.flatnonzero(~on_part)
    if off.size:
        jet = surface.jet(pt["u"][off], pt["v"][off], order=2)
        bend[off] = normal_curvature(jet, pt["tangent"][off], normal=pt["normal"][off])
    return bend
