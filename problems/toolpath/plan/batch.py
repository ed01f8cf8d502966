"""``PlanBatch``: the toolpath plans of a batch of decision sets, flattened, in machining order.

What every planning stage produces and every criterion reads. For n decision sets (one per
individual of a population) the plans are laid end to end, with no Python object per
point, pass or zone:

- **Sections** (S): a section is one stretch of one pass plane inside one zone, cut as one
  feed motion (the tool retracts before the next section). Sections are stored in
  machining order: individual, then zone in plan order, then pass, then along the travel.
  Per section: ``sec_ind`` individual, ``sec_zone`` zone (0 .. zones - 1), ``sec_pass``
  the plane index in its zone (several sections share it when a plane leaves and
  re-enters the zone), ``sec_d`` the plane offset along the zone's cross-feed c (mm),
  ``sec_alpha`` the zone's feed direction (radians from +X; f = (cos, sin), c = z x f),
  ``sec_reverse`` True when the section is travelled along -f (zig-zag), ``sec_spacing``
  the XY distance to the neighbouring plane whose gap the analytic scallop measures and
  ``sec_side`` which one (+1 the next plane, along +c; -1 the previous one: the zone's last
  plane; 0 a zone of one plane), ``sec_start`` / ``sec_count`` its points.
- **Points** (N), in machining order (a section's points along its travel): ``pt_sec``
  the section, ``u``, ``v`` surface parameters, ``p`` the CC point, ``normal`` the unit
  surface normal on the tool side, ``tangent`` the unit travel direction on the surface,
  ``axis`` the unit tool axis, ``tip`` the CL point (the APT tool tip; None when the
  planner was asked not to place the tool: the analytic criteria do not need it), ``chord`` the
  larger chord error of the point's two moves (mm), ``on_part`` False for a CL point that
  holds no CC point (a tool position past the footprint's edge that cuts the edge wedge;
  its ``p``/``normal`` are those of the nearest CC point on the part).
- **Moves** (N - S): the feed moves between consecutive points of a section: ``seg_sec``,
  ``seg_err`` the chord error (the largest distance of the surface curve from the chord,
  mm), ``seg_len`` the chord length between the CC points (mm), ``seg_cc`` True for a
  chord between two CC points (False for a move past the part's edge, which has no chord
  error to speak of; None: every move is a chord).
- **Cross-feed of passes that are not planes** (``isoscallop``, ``contour``,
  ``isoparametric``; None for planes, whose cross-feed is the section's): per point
  ``pt_cross`` (N, 3) the horizontal unit vector towards the neighbouring pass whose gap
  the analytic scallop measures, ``pt_gap`` (N,) the XY distance to it along ``pt_cross``
  (mm), ``pt_gap_side`` (N,) +1 / -1 the side of the travel it lies on (the sign of
  (z x t) . cross; 0: no neighbouring pass).
- **Per individual** (n): ``zones`` the number of zones of its plan.

A plan's claimed lengths are computed from these points (``seg_len``): what is claimed is
what is cut.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..clpath import CLPath

__all__ = ["PlanBatch"]


@dataclass
class PlanBatch:
    """Plans of n decision sets; see the module docstring for every field."""

    n: int
    zones: np.ndarray
    sec_ind: np.ndarray
    sec_zone: np.ndarray
    sec_pass: np.ndarray
    sec_d: np.ndarray
    sec_alpha: np.ndarray
    sec_reverse: np.ndarray
    sec_spacing: np.ndarray
    sec_side: np.ndarray
    sec_start: np.ndarray
    sec_count: np.ndarray
    pt_sec: np.ndarray
    u: np.ndarray
    v: np.ndarray
    p: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    axis: np.ndarray
    tip: np.ndarray | None
    chord: np.ndarray
    on_part: np.ndarray
    seg_sec: np.ndarray
    seg_err: np.ndarray
    seg_len: np.ndarray
    seg_cc: np.ndarray | None = None
    pt_cross: np.ndarray | None = None
    pt_gap: np.ndarray | None = None
    pt_gap_side: np.ndarray | None = None

    @property
    def pt_ind(self) -> np.ndarray:
        """(N,) the individual of every point."""
        return self.sec_ind[self.pt_sec]

    @property
    def seg_ind(self) -> np.ndarray:
        """(N - S,) the individual of every move."""
        return self.sec_ind[self.seg_sec]

    def points_of(self, i: int) -> np.ndarray:
        """Indices of individual i's points, in machining order."""
        secs = np.flatnonzero(self.sec_ind == i)
        if len(secs) == 0:
            return np.zeros(0, np.int64)
        return np.arange(self.sec_start[secs[0]],
                         self.sec_start[secs[-1]] + self.sec_count[secs[-1]])

    def cl_path(self, i: int, cutter, feed_rate: float = 1000.0) -> CLPath:
        """Individual i's toolpath as the machine runs it: its CL points, one section per
        feed motion, passes numbered across zones, zone labels, the ``cutter`` (a
        ``cutters.Cutter``); ``info`` holds the CC points
        (``cc``), their ``uv``, ``normal`` and ``on_part``."""
        if self.tip is None:
            raise ValueError("plan: the tool was not placed (plan with place=True)")
        idx = self.points_of(i)
        sec = self.pt_sec[idx]
        zone = self.sec_zone[sec]
        # passes numbered across zones in machining order
        key = zone.astype(np.int64) * (int(self.sec_pass.max(initial=0)) + 1) + self.sec_pass[sec]
        _, pass_index = np.unique(key, return_inverse=True)
        info = {"cc": self.p[idx], "uv": np.column_stack([self.u[idx], self.v[idx]]),
                "normal": self.normal[idx], "on_part": self.on_part[idx]}
        return CLPath(self.tip[idx], self.axis[idx], cutter,
                      section=sec - sec.min(initial=0), pass_index=pass_index, zone=zone,
                      feed_rate=feed_rate, info=info)


def merge_batches(n: int, parts) -> PlanBatch:
    """One PlanBatch of n plans from ``parts``: [(rows, batch)], each batch planning the
    individuals ``rows`` (its individual i is rows[i]); sections reordered by individual
    (each part keeps its own order), so the plans of several strategies form one batch.
    Plane parts get the per-point cross-feed fields from their sections when any part has
    them (``pt_cross``: the plane's c; ``pt_gap``: its spacing; ``pt_gap_side``: the side of
    the travel the gap lies on)."""
    curves = any(b.pt_cross is not None for _, b in parts)
    sec_keys = ("sec_zone", "sec_pass", "sec_d", "sec_alpha", "sec_reverse", "sec_spacing",
                "sec_side")
    pt_keys = ("u", "v", "p", "normal", "tangent", "axis", "chord", "on_part")
    cat = {k: [] for k in sec_keys + pt_keys + ("sec_ind", "sec_start", "sec_count", "tip",
                                                "seg_sec", "seg_err", "seg_len", "seg_cc",
                                                "pt_cross", "pt_gap", "pt_gap_side")}
    zones = np.ones(n, np.int64)
    s_off = p_off = 0
    for rows, b in parts:
        rows = np.asarray(rows)
        zones[rows] = b.zones
        cat["sec_ind"].append(rows[b.sec_ind])
        for k in sec_keys + pt_keys:
            cat[k].append(getattr(b, k))
        cat["sec_start"].append(b.sec_start + p_off)
        cat["sec_count"].append(b.sec_count)
        cat["tip"].append(b.tip)
        cat["seg_sec"].append(b.seg_sec + s_off)
        cat["seg_err"].append(b.seg_err)
        cat["seg_len"].append(b.seg_len)
        cat["seg_cc"].append(np.ones(len(b.seg_len), bool) if b.seg_cc is None else b.seg_cc)
        if curves:
            if b.pt_cross is not None:
                cross, gap, side = b.pt_cross, b.pt_gap, b.pt_gap_side
            else:
                a = b.sec_alpha[b.pt_sec]
                cross = np.column_stack([-np.sin(a), np.cos(a), np.zeros_like(a)])
                gap = b.sec_spacing[b.pt_sec]
                side = np.where(b.sec_reverse, -1, 1)[b.pt_sec] * b.sec_side[b.pt_sec]
            cat["pt_cross"].append(cross)
            cat["pt_gap"].append(gap)
            cat["pt_gap_side"].append(side)
        s_off += len(b.sec_ind)
        p_off += len(b.u)
    c = {k: (np.concatenate(v) if v and all(x is not None for x in v) else None)
         for k, v in cat.items()}
    order = np.argsort(c["sec_ind"], kind="stable")
    inv = np.empty_like(order)
    inv[order] = np.arange(len(order))
    count = c["sec_count"][order]
    start = np.cumsum(count) - count
    pt_sec = np.repeat(np.arange(len(order)), count)
    src = c["sec_start"][order][pt_sec] + (np.arange(len(pt_sec)) - start[pt_sec])
    seg_sec = inv[c["seg_sec"]]
    so = np.argsort(seg_sec, kind="stable")
    pt = {k: c[k][src] for k in pt_keys}
    extra = {k: (None if c[k] is None else c[k][src]) for k in ("pt_cross", "pt_gap",
                                                                 "pt_gap_side")}
    return PlanBatch(
        n=n, zones=zones, sec_ind=c["sec_ind"][order],
        **{k: c[k][order] for k in sec_keys}, sec_start=start, sec_count=count,
        pt_sec=pt_sec, tip=None if c["tip"] is None else c["tip"][src],
        seg_sec=seg_sec[so], seg_err=c["seg_err"][so], seg_len=c["seg_len"][so],
        seg_cc=c["seg_cc"][so], **pt, **extra)
