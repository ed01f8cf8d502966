"""The analytic criteria of a batch of plans: one pass over a ``PlanBatch``, no simulation.

:func:`analytic_criteria` computes every criterion of the ``analytic`` family of
``criteria/table.py`` for the n plans of a :class:`~problems.toolpath.plan.batch.PlanBatch`,
vectorized over all their points, moves and sections (a Python loop only over the distinct
tools):

- **Scallop and gouge** per point on the part, at the middle of the gap between the point's
  section and the neighbouring plane it faces (``sec_side``; none for a zone of one plane):
  the gap's width on the surface is w = sec_spacing / (b.c), b the unit cross-feed tangent
  (the surface tangent in the vertical plane through c = (-sin alpha, cos alpha, 0)), and
  kappa the normal curvature along b (> 0 concave).

  - 5-axis (genes ``lead``/``tilt``): the projected-profile model of ``criteria/scallop.py``
    (:func:`~problems.toolpath.criteria.scallop.gap_heights` on each plan's
    ``Cutter.swept_profile`` tables). The gap lies on the tool's +b side when the section
    travels along +f and faces the next plane, or travels along -f and faces the previous one.
  - 3-axis (no lead/tilt): the vertical cutter's exact swept profile, the model the
    planner spaces 3-axis passes with, inverted for the cusp height
    (``criteria/scallop_3axis.py``); gouge from the circle model with the exact effective
    radius (``Cutter.effective_radius``, a.t = t_z, a.n = n_z: Djebali Eq. 1 in the travel
    frame). ``r_eff`` is then the smallest over the plan's points.

  Heights are capped at the finishing ``allowance``; a negative height is a gouge.
- **Pose gouge** per point (5-axis): the depth the leaned or tilted cutter, placed tangent
  at the point, cuts below the surface's osculating quadric anywhere under its end
  (``criteria/heel.py``). The gap model above looks only at mid-gap; a flat or toroidal
  bottom leaned by the lead reaches up to a diameter behind the contact and beside the
  pass, and where the surface is concave there it rises into the tool (a flat end on a
  surface concave along the feed: max over x of kappa_f x^2 / 2 - x tan lead, the heel).
  ``gouge`` per point is the larger of the gap's gouge and the pose gouge. Not added for
  3-axis plans: the drop-cutter placement is gouge-free, and the tangent ``cc`` placement
  keeps the circle model's gouge above.
- **Machining error** per point (Fountas Fig. 1): chord error (larger of the point's two
  moves) + scallop + gouge (the larger of the gap's and the pose's); max and mean over the
  points on the part.
- **Lengths**: cutting = sum of ``seg_len``; between consecutive sections of one plan the
  move from the last CC point of one to the first of the next is a link (same zone) or an
  inter-zone move; path = cutting + link + inter-zone; time = path / feed rate (min).
- **Djebali Eq. 4**: eq4_total = cutting length + (zones - 1) delta_l (the runs past the
  part's edge included); counted as the papers count, ``length_on_part_mm`` = the moves
  between CC points on the part and ``length_papers_mm`` = that + (zones - 1) delta_l.

``objective`` (Fountas Eq. 9) is not computed here: it needs the weights and the
normalization bounds (``criteria/objective.py``).
"""

from __future__ import annotations

import numpy as np

from ..geometry.surface import normal_curvature, unit_normal
from ..geometry.vectors import row_norms, take_rows
from .heel import pose_gouge
from .kinematic_time import kinematic_time
from .scallop import gap_heights
from .scallop_3axis import gap_heights_3axis
from .table import names

__all__ = ["analytic_criteria", "point_heights", "plan_lengths", "eq4_total", "ANALYTIC"]

#: the names :func:`analytic_criteria` returns, in table order
ANALYTIC = names(family="analytic")


def _tool_index(genes, tools, n) -> np.ndarray:
    ti = np.clip(np.rint(np.asarray(genes["tool"], float)).astype(int), 0, len(tools) - 1)
    return np.broadcast_to(ti, (n,))


def _five_axis(genes, machine) -> bool:
    if machine is None:
        return "lead" in genes and "tilt" in genes
    if machine not in ("5axis", "3axis"):
        raise ValueError(f"machine: expected 5axis or 3axis, got {machine!r}")
    return machine == "5axis"


def swept_profiles(tools, ti, lead, tilt):
    """Profile tables (x, z, reach) of every plan (rows 2i, 2i + 1 for plan i): each tool's
    cutter gives its plans' tables (``Cutter.swept_profile``, radians); a shorter table is
    padded with its last point (the profile is vertical beyond its reach)."""
    parts = []
    for t in np.unique(ti):
        rows = np.flatnonzero(ti == t)
        parts.append((rows, tools.cutter(t).swept_profile(lead[rows], tilt[rows])))
    m = max(p[1][0].shape[1] for p in parts)
    x, z, reach = np.empty((2 * len(ti), m)), np.empty((2 * len(ti), m)), np.empty(2 * len(ti))
    for rows, (xt, zt, rt) in parts:
        at = np.stack([2 * rows, 2 * rows + 1], axis=1).ravel()
        pad = ((0, 0), (0, m - xt.shape[1]))
        x[at], z[at], reach[at] = np.pad(xt, pad, mode="edge"), np.pad(zt, pad, mode="edge"), rt
    return x, z, reach


def _per_tool(tools, ti, fn) -> np.ndarray:
    """fn(cutter, rows) -> values of those rows, for each distinct tool of ti."""
    out = np.empty(len(ti))
    for t in np.unique(ti):
        rows = np.flatnonzero(ti == t)
        out[rows] = fn(tools.cutter(t), rows)
    return out


def point_heights(batch, surface, tools, genes, *, allowance, machine=None) -> dict:
    """Per point (N,): ``h`` the signed material height in the gap (mm, < 0 gouge),
    ``pose_gouge`` the gouge under the cutter's end (mm, >= 0; 0 for 3-axis), ``kappa``, ``w``,
    ``normal``, and ``r_eff`` (3-axis: per point; 5-axis: per plan's lead/tilt). See the
    module docstring for the model."""
    n = batch.n
    ti = _tool_index(genes, tools, n)
    sec = batch.pt_sec
    ind = batch.sec_ind[sec]
    jet = surface.jet(batch.u, batch.v, order=2)
    nrm = unit_normal(jet, surface.normal_sign)
    curves = batch.pt_cross is not None  # passes that are not planes carry their cross-feed
    if curves:
        c3 = batch.pt_cross
    else:
        alpha = batch.sec_alpha  # per section, then taken per point (the same numbers)
        c3 = take_rows(np.column_stack([-np.sin(alpha), np.cos(alpha), np.zeros_like(alpha)]),
                       sec)
    bvec = c3 - np.einsum("ij,ij->i", nrm, c3)[:, None] * nrm
    bc = row_norms(bvec)  # = b.c, b the unit cross-feed tangent
    kappa = normal_curvature(jet, bvec / bc[:, None], surface.normal_sign, nrm)
    w = (batch.pt_gap if curves else batch.sec_spacing[sec]) / bc
    side = batch.pt_gap_side if curves else batch.sec_side[sec]
    if _five_axis(genes, machine):
        lead = np.broadcast_to(np.radians(np.asarray(genes["lead"], float)), (n,))
        tilt = np.broadcast_to(np.radians(np.asarray(genes["tilt"], float)), (n,))
        sigma = 1 if curves else np.where(batch.sec_reverse[sec], -1, 1)
        h = gap_heights(swept_profiles(tools, ti, lead, tilt), ind, sigma * side, w, kappa,
                        allowance)
        r_eff = _per_tool(tools, ti, lambda c, rows: c.effective_radius_lead_tilt(
            lead[rows], tilt[rows]))[ind]
        pose = pose_gouge(tools.cutters, ti[ind], batch.p, nrm, batch.tangent, batch.axis, jet)
    else:
        tan, pt_tool = batch.tangent, ti[ind]
        r_eff = _per_tool(tools, pt_tool, lambda c, rows: c.effective_radius(
            tan[rows, 2], nrm[rows, 2]))
        h = _per_tool(tools, pt_tool, lambda c, rows: gap_heights_3axis(
            c, w[rows], tan[rows], nrm[rows], kappa[rows], allowance))
        pose = np.zeros(len(h))
    h = np.where(side != 0, h, 0.0)
    return dict(h=h, pose_gouge=pose, kappa=kappa, w=w, normal=nrm, r_eff=r_eff)


def _group_max(x, owner, n) -> np.ndarray:
    """Largest x per owner (owner sorted ascending), 0 for an owner with none."""
    out = np.zeros(n)
    counts = np.bincount(owner, minlength=n)
    has = counts > 0
    if has.any():
        out[has] = np.maximum.reduceat(x, (np.cumsum(counts) - counts)[has])
    return out


def _group_mean(x, owner, n) -> np.ndarray:
    counts = np.bincount(owner, minlength=n)
    return np.bincount(owner, x, n) / np.maximum(counts, 1)


def _group_min(x, owner, n) -> np.ndarray:
    """Smallest x per owner (owner sorted ascending), inf for an owner with none."""
    has = np.bincount(owner, minlength=n) > 0
    return np.where(has, -_group_max(-x, owner, n), np.inf)


def plan_lengths(batch) -> dict[str, np.ndarray]:
    """Per plan (n,): cutting, link and inter-zone lengths (mm) from the plan's points."""
    n = batch.n
    cutting = np.bincount(batch.sec_ind[batch.seg_sec], batch.seg_len, n)
    s = np.flatnonzero(batch.sec_ind[1:] == batch.sec_ind[:-1])  # section s -> s + 1
    end = take_rows(batch.p, batch.sec_start[s] + batch.sec_count[s] - 1)
    dist = row_norms(take_rows(batch.p, batch.sec_start[s + 1]) - end)
    same = batch.sec_zone[s + 1] == batch.sec_zone[s]
    own = batch.sec_ind[s]
    return {"cutting_length": cutting,
            "link_length": np.bincount(own, np.where(same, dist, 0.0), n),
            "interzone_length": np.bincount(own, np.where(same, 0.0, dist), n)}


def eq4_total(cutting_length, zones, delta_l: float):
    """Djebali Eq. 4: the cutting length plus (zones - 1) delta_l, the inter-zone penalty."""
    return cutting_length + (zones - 1.0) * float(delta_l)


def _plan_counts(batch) -> dict[str, np.ndarray]:
    n, si = batch.n, batch.sec_ind
    new_pass = np.ones(len(si), bool)
    new_pass[1:] = ((si[1:] != si[:-1]) | (batch.sec_zone[1:] != batch.sec_zone[:-1])
                    | (batch.sec_pass[1:] != batch.sec_pass[:-1]))
    return {"cc_count": np.bincount(batch.pt_ind[batch.on_part], minlength=n).astype(float),
            "n_passes": np.bincount(si[new_pass], minlength=n).astype(float),
            "n_sections": np.bincount(si, minlength=n).astype(float),
            "zones": np.asarray(batch.zones, float).reshape(n)}


def analytic_criteria(batch, surface, tools, genes: dict, *, allowance: float,
                      feed_rate: float, delta_l: float, machine: str | None = None,
                      dynamics=None) -> dict[str, np.ndarray]:
    """Every analytic criterion (``ANALYTIC``, table order), each (n,), of the n plans of
    ``batch`` (a ``PlanBatch``) on ``surface``.

    tools: the ``ToolDatabase``; genes: per plan (n,) arrays, ``tool`` the tool INDEX and, for
    a 5-axis plan, ``lead`` and ``tilt`` (degrees); other genes are ignored. allowance:
    finishing stock (mm, the cap of a scallop); feed_rate (mm/min, for a tool without a library
    feed); delta_l: Djebali's
    Delta L per extra zone (mm). dynamics: the machine's limits (``kinematic_time.Dynamics``,
    None: the defaults) for ``machining_time``. machine: ``5axis`` | ``3axis``; None: 5-axis when the genes
    hold lead and tilt. Points off the part (``on_part`` False) count in the lengths only.
    """
    n = batch.n
    if n == 0:
        return {name: np.zeros(0) for name in ANALYTIC}
    ti = _tool_index(genes, tools, n)
    pt = point_heights(batch, surface, tools, genes, allowance=allowance, machine=machine)
    on = np.asarray(batch.on_part, bool)
    ind = batch.pt_ind[on]
    h = pt["h"][on]
    scallop, gouge = np.maximum(h, 0.0), np.maximum(np.maximum(-h, 0.0), pt["pose_gouge"][on])
    err = batch.chord[on] + scallop + gouge
    chords = (np.ones(len(batch.seg_err), bool) if batch.seg_cc is None
              else np.asarray(batch.seg_cc, bool))  # the moves past an edge are no chords
    seg_ind = batch.sec_ind[batch.seg_sec][chords]
    crit = _plan_counts(batch)
    crit |= {
        "chord_error_mean": _group_mean(batch.seg_err[chords], seg_ind, n),
        "chord_error_max": _group_max(batch.seg_err[chords], seg_ind, n),
        "r_eff": _group_min(pt["r_eff"][on], ind, n),
        "scallop_max": _group_max(scallop, ind, n),
        "scallop_mean": _group_mean(scallop, ind, n),
        "gouge_max": _group_max(gouge, ind, n),
        "machining_error": _group_max(err, ind, n),
        "machining_error_mean": _group_mean(err, ind, n),
    }
    sharp = np.array([c.sharp_rim for c in tools.cutters], bool)[ti]
    crit["undercut_max"] = np.where(sharp, crit["scallop_max"], 0.0)
    crit |= plan_lengths(batch)
    crit["path_length"] = crit["cutting_length"] + crit["link_length"] + crit["interzone_length"]
    # both times at the plan's programmed feed, the one its APT and NC programs carry
    feed = tools.feeds(feed_rate)[ti]
    crit["machining_time_nominal"] = crit["path_length"] / feed
    crit["machining_time"] = kinematic_time(batch, feed, dynamics)
    crit["eq4_total"] = eq4_total(crit["cutting_length"], crit["zones"], delta_l)
    crit["length_on_part_mm"] = np.bincount(seg_ind, batch.seg_len[chords], n)
    crit["length_papers_mm"] = eq4_total(crit["length_on_part_mm"], crit["zones"], delta_l)
    return {name: crit[name] for name in ANALYTIC}
