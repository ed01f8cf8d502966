"""CL points of a zoning plan for a vertical (3-axis) cutter: the plan as the machine runs it.

A zone's passes are vertical planes {c . (x, y) = s_k} parallel to its feed direction
alpha, with f = (cos a, sin a) and c = (-sin a, cos a) (``passes.py``). This module cuts
each plane with the surface and keeps the stretches of the section that lie on the zone's
cells of the (u, v) mesh (``plan.labels``); each stretch is one section of the toolpath
(the tool retracts between stretches and between zones).

- **Section.** The points of plane k are xy(t) = s_k c + t f; their (u, v) come from the
  inverse map of the surface seen as a graph over XY (``cutters.surface_grid.uv_at_xy``).
  A point holds zone material when it lies on the footprint and its mesh cell belongs to
  the zone. Membership is sampled along t at most ``resolution`` apart and each stretch's
  ends are located by bisection to 1e-6 mm.
- **CC points.** Along each stretch, equally spaced in t at most ``step`` mm apart (both
  ends included); a CC point that falls on another zone's cell (a corner clipped between
  two membership samples) is dropped and splits the stretch.
- **Order.** Zones in plan order; inside a zone the planes by increasing offset, in
  zig-zag: the travel direction along f alternates from one non-empty pass to the next;
  the stretches of a pass follow its travel direction.
- **Placement** (``PLACEMENTS``): ``"cc"``: the tip that makes the cutter tangent to the
  surface at the CC point (``Cutter.cc_to_tip``; what the analytic model assumes, not
  gouge-free); ``"drop"``: the drop-cutter tip at the CC point's XY (``Cutter.drop_cutter``:
  gouge-free).
- **Chord tolerance** (``chord.py``). The machine joins consecutive CL points of a section
  by straight moves; where the placement's CL curve bends (the drop-cutter tip falling
  away near a part edge or a crest) a move leaves it, and below a convex stretch it cuts
  into the part between two gouge-free points (the cut simulation measured up to 0.055 mm
  on Choi's surface with a 1 mm step). Moves further than ``tolerance`` from the curve
  (checked at their quarter and mid points) are split at their mid-point, all at once, for
  at most ``rounds`` rounds; ``step`` stays the largest spacing.

Difference from ``passes.py``: there a pass is credited with every bin of t where its band
(the samples nearer to its plane than to the others) holds zone material; here a pass runs
where its own plane does, so a sliver of zone between two planes that neither plane
crosses is not cut by this zone's passes. ``info`` reports both lengths per zone.
"""

from __future__ import annotations

import numpy as np

from ...clpath import CLPath
from ...cutters.surface_grid import surface_grid, uv_at_xy
from ...geometry.surface import unit_normal
from .chord import refine_chords

__all__ = ["PLACEMENTS", "zone_cl_path"]


def _place_cc(cutter, surface, cc, normal):
    return cutter.cc_to_tip(cc, normal, (0.0, 0.0, 1.0))


def _place_drop(cutter, surface, cc, normal):
    return np.column_stack([cc[:, :2], cutter.drop_cutter(surface, cc[:, :2])])


PLACEMENTS = {"cc": _place_cc, "drop": _place_drop}


class _Zone:
    """Membership of plane points in one zone: on the footprint and on the zone's cells."""

    def __init__(self, surface, grid, labels, zone):
        self.surface, self.grid, self.labels, self.zone = surface, grid, labels, zone

    def uv(self, xy):
        near = self.grid.tree.query(xy)[1]
        return uv_at_xy(self.surface, xy, np.column_stack([self.grid.u[near], self.grid.v[near]]))

    def holds(self, xy):
        uv, ok = self.uv(xy)
        n, m = self.labels.shape
        i = np.minimum((uv[:, 0] * n).astype(np.int64), n - 1)
        j = np.minimum((uv[:, 1] * m).astype(np.int64), m - 1)
        return ok & (self.labels[i, j] == self.zone), uv


def _stretches(member: _Zone, planes, f, c, t_lo, t_hi, resolution):
    """(plane index, t_start, t_end) of every stretch of zone material on the planes."""
    nt = max(2, int(np.ceil((t_hi - t_lo) / resolution)) + 1)
    t = np.linspace(t_lo, t_hi, nt)
    k = len(planes)
    xy = (planes[:, None, None] * c + t[None, :, None] * f).reshape(-1, 2)
    inside = member.holds(xy)[0].reshape(k, nt)
    pad = np.pad(inside, ((0, 0), (1, 1)))
    starts = np.argwhere(~pad[:, :-2] & pad[:, 1:-1])  # (plane, first in-zone sample)
    ends = np.argwhere(pad[:, 1:-1] & ~pad[:, 2:])  # (plane, last in-zone sample)

    def refine(plane, t_in, t_out):  # bisection on membership, t_in inside
        for _ in range(max(1, int(np.ceil(np.log2(resolution / 1e-6))))):
            mid = 0.5 * (t_in + t_out)
            ok = member.holds(planes[plane, None] * c + mid[:, None] * f)[0]
            t_in, t_out = np.where(ok, mid, t_in), np.where(ok, t_out, mid)
        return t_in

    p = starts[:, 0]
    a = refine(p, t[starts[:, 1]], t[np.maximum(starts[:, 1] - 1, 0)])
    b = refine(ends[:, 0], t[ends[:, 1]], t[np.minimum(ends[:, 1] + 1, nt - 1)])
    return p, a, b


def zone_cl_path(surface, plan, cutter, step: float = 1.0, placement: str = "drop",
                 resolution: float | None = None, tolerance: float | None = 0.01,
                 rounds: int = 8) -> CLPath:
    """CL points of ``plan`` (a ``ZoningPlan``) for the vertical ``cutter`` (see module doc).

    ``step``: the largest distance between CC points along the feed coordinate (mm);
    ``placement``: a key of ``PLACEMENTS``; ``resolution``: membership sampling along the
    planes (default min(step, grid spacing) / 2). ``info`` holds the CC points ``cc``,
    their ``uv`` and ``normal``, the ``placement``, ``step``, and per zone the section
    length cut (``section_length``, on the surface) and the plan's claimed length
    (``claimed_length``). ``tolerance``: the chord tolerance of the CL moves (mm; None: no
    refinement), ``rounds`` its round limit; ``info`` reports ``chord_tolerance``,
    ``chord_added`` (points inserted), ``chord_rounds`` and ``chord_deviation`` (the largest
    remaining deviation at the check points).
    """
    if placement not in PLACEMENTS:
        raise ValueError(f"placement: expected one of {', '.join(PLACEMENTS)}, got {placement!r}")
    step = float(step)
    if not (np.isfinite(step) and step > 0):
        raise ValueError(f"step: must be a number > 0 mm, got {step!r}")
    if tolerance is not None and not (np.isfinite(tolerance) and tolerance > 0):
        raise ValueError(f"tolerance: must be a number > 0 mm or None, got {tolerance!r}")
    grid = surface_grid(surface, 0.25)
    resolution = 0.5 * min(step, grid.spacing) if resolution is None else float(resolution)
    n, m = plan.labels.shape
    node_cell = (np.minimum((grid.u * n).astype(np.int64), n - 1) * m
                 + np.minimum((grid.v * m).astype(np.int64), m - 1))
    node_zone = plan.labels.ravel()[node_cell]
    cc_uv, sec, pas, zon = [], [], [], []
    n_sec = n_pass = 0
    claimed = []
    for zp in plan.zones:
        alpha, planes = zp.passes.alpha, np.asarray(zp.passes.s, float)
        f = np.array([np.cos(alpha), np.sin(alpha)])
        c = np.array([-np.sin(alpha), np.cos(alpha)])
        claimed.append(zp.length)
        nodes = grid.xy[node_zone == zp.zone]
        if len(planes) == 0 or len(nodes) == 0:
            continue
        t_nodes = nodes @ f
        pad = 2 * grid.spacing
        member = _Zone(surface, grid, plan.labels, zp.zone)
        p, a, b = _stretches(member, planes, f, c, t_nodes.min() - pad, t_nodes.max() + pad,
                             resolution)
        forward = True
        for k in np.unique(p):
            sel = np.flatnonzero((p == k) & (b - a > 1e-9))
            if len(sel) == 0:
                continue
            order = np.argsort(a[sel] if forward else -a[sel])
            for i in sel[order]:
                cnt = max(2, int(np.ceil((b[i] - a[i]) / step)) + 1)
                t = np.linspace(a[i], b[i], cnt)[:: 1 if forward else -1]
                ok, uv = member.holds(planes[k] * c + t[:, None] * f)
                new_sec = n_sec + np.cumsum(~ok)  # a dropped point splits the stretch
                cc_uv.append(uv[ok])
                sec.append(new_sec[ok])
                n_sec = int(new_sec[-1]) + 1
                pas.append(np.full(int(ok.sum()), n_pass))
                zon.append(np.full(int(ok.sum()), zp.zone))
            n_pass += 1
            forward = not forward
    if not cc_uv:
        raise ValueError("plan: no zone holds a CC point (empty plan)")
    uv = np.concatenate(cc_uv)
    jet = surface.jet(uv[:, 0], uv[:, 1], order=1)
    cc, normal = jet.p, unit_normal(jet, surface.normal_sign)
    _, section = np.unique(np.concatenate(sec), return_inverse=True)  # consecutive ids
    pts = {"uv": uv, "cc": cc, "normal": normal, "section": section,
           "pass_index": np.concatenate(pas), "zone": np.concatenate(zon),
           "tip": PLACEMENTS[placement](cutter, surface, cc, normal)}
    chord = {"chord_tolerance": None}
    if tolerance is not None:
        pts, chord = refine_chords(surface, cutter, PLACEMENTS[placement], pts, tolerance,
                                   rounds)
    cc, section, zone = pts["cc"], pts["section"], pts["zone"]
    same = section[1:] == section[:-1]
    seg = np.linalg.norm(np.diff(cc, axis=0), axis=1) * same
    cut = [float(seg[zone[1:] == zp.zone].sum()) for zp in plan.zones]
    info = {"placement": placement, "step": step, "cc": cc, "uv": pts["uv"],
            "normal": pts["normal"], "section_length": cut, "claimed_length": claimed, **chord}
    return CLPath(pts["tip"], np.array([0.0, 0.0, 1.0]), cutter.diameter,
                  cutter.corner_radius, section=section, pass_index=pts["pass_index"],
                  zone=zone, info=info)
