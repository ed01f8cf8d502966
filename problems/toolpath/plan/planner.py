"""The planner: decisions in, toolpath plans (``PlanBatch``) out, for a whole population.

One pipeline for every configuration (the folders' order):

1. **Zones** (``zones.py``): ``single`` (the whole part), or a zoning method of the
   registry (``zoning/methods``: kmeans, amas) with its gene; zone labels on the
   parametric mesh are memoized per gene value.
2. **Feed direction per zone**: the configured ``feed_angle``, or optimized per zone
   (Herraz Eq. 3 on the zone's samples: ``zoning/direction.py``), memoized per
   (zoning, tool).
3. **Passes** (``sections.py``): vertical planes parallel to the zone's feed, spaced by a
   fixed step-over (% of D, measured in XY) or by the scallop target h_c, adaptively per
   pass (``zoning/passes.py``); each plane is cut into the sections where its band (the
   strip to its neighbouring planes) holds zone material, so neighbouring zones' passes
   meet across their border.
4. **CC points** (``points.py``): the maximum step, then the chord tolerance.
5. **Orientation and placement** (``orientation.py``): 3-axis (drop-cutter) or 5-axis
   (lead/tilt).
6. **Order**: zones in plan order, passes in zig-zag inside a zone, sections along their
   travel: a ``PlanBatch`` in machining order; sections that end on the part's edge run
   on past it (``overrun.py``).

Everything is batched: the individuals that share a zone geometry (the same direction) are
planned together with no Python loop per individual, pass or point.
"""

from __future__ import annotations

import numpy as np

from ..geometry.rows import ranges
from ..geometry.surface import Surface, unit_normal
from ..tools import ToolDatabase
from ..clpath import CLPath
from .batch import PlanBatch
from .orientation import get_machine, travel_tangent
from .overrun import edge_overrun as add_overrun
from .planes import PassGeometry
from .points import sample_sections
from .sections import Sections, full_plane_sections, zone_sections
from .zones import ZoneLayouts
from .zoning.chord import refine_chords, refine_drop_moves

__all__ = ["Planner", "SPACINGS"]

SPACINGS = ("stepover", "scallop")


class Planner:
    """Plans of a surface, a tool database and a strategy; see the module docstring.

    ``machine``: ``5axis`` | ``3axis``; ``placement``: 3-axis ``drop`` | ``cc``;
    ``zoning``: None (a single zone) or a ``zones.ZoningSpec``; ``spacing``: ``stepover``
    (gene, % of D) | ``scallop`` (h_c, adaptive); ``h_c`` (mm): the scallop target of the
    adaptive spacing and of the zone-direction search; ``tolerance``: the chord tolerance
    (mm); ``feed_angle``: degrees from +X, or None (optimized per zone);
    ``max_rounds``: chord refinement rounds; ``edge_overrun``: sections that end on the
    part's edge run on past it (``overrun.py``; False: they stop at their last CC point, as
    the former evaluator's passes did, and leave the edge rows and wedges high).
    """

    def __init__(self, surface: Surface, tools: ToolDatabase, *, machine: str = "5axis",
                 placement: str | None = None, zoning=None, spacing: str = "stepover",
                 h_c: float | None = None, tolerance: float = 0.01,
                 feed_angle: float | None = 0.0, max_rounds: int = 6,
                 edge_overrun: bool = True):
        if spacing not in SPACINGS:
            raise ValueError(f"spacing: expected one of {', '.join(SPACINGS)}, got {spacing!r}")
        if spacing == "scallop" and h_c is None:
            raise ValueError("h_c: the scallop spacing needs a scallop height h_c (mm)")
        self.surface, self.tools = surface, tools
        self.machine = get_machine(machine, placement)
        if spacing == "scallop" and self.machine.genes:
            raise ValueError(f"spacing: the scallop spacing models a vertical cutter (3axis); "
                             f"a {machine} plan is spaced by stepover")
        self.spacing, self.h_c = spacing, (None if h_c is None else float(h_c))
        self.tolerance, self.max_rounds = float(tolerance), int(max_rounds)
        self.feed_angle = None if feed_angle is None else float(feed_angle)
        self.edge_overrun = bool(edge_overrun) and self.machine.overrun
        self.layouts = ZoneLayouts(surface, tools, zoning, self.h_c, self.feed_angle)
        self._geoms: dict[float, PassGeometry] = {}

    # ---------------------------------------------------------------------------------
    @property
    def gene_names(self) -> tuple[str, ...]:
        """The decisions this configuration reads, in chromosome order."""
        names = ["tool"] + (["stepover"] if self.spacing == "stepover" else [])
        names += list(self.machine.genes) + ["step"]
        if self.layouts.gene is not None:
            names.append(self.layouts.gene)
        return tuple(names)

    @property
    def zoned(self) -> bool:
        """Whether plans go through zone layouts (False: one zone fed along the configured
        direction at a fixed step-over, every plane across the whole footprint)."""
        return not (self.layouts.gene is None and self.layouts.single
                    and self.spacing == "stepover")

    def layout(self, genes: dict):
        """The zone layout (``zones.ZoneLayout``) of the first decision set of ``genes``, or
        None when plans need none (:attr:`zoned`)."""
        if not self.zoned:
            return None
        gene = self.layouts.gene
        value = np.atleast_1d(genes[gene])[0] if gene else None
        return self.layouts.get(value, int(np.atleast_1d(genes["tool"])[0]))

    def geometry(self, alpha: float) -> PassGeometry:
        """Pass-plane tables for the feed direction alpha (radians), memoized."""
        key = round(float(np.degrees(alpha)) % 360.0, 9)
        if key not in self._geoms:
            self._geoms[key] = PassGeometry(self.surface, key)
        return self._geoms[key]

    def plan(self, genes: dict, place: bool = True) -> PlanBatch:
        """Plans of n decision sets: ``genes`` maps every name of :attr:`gene_names` to an
        (n,) array (``tool`` the INDEX into the database). ``place``: also the CL points
        (``tip``); the analytic criteria do not need them, and a 3-axis drop-cutter
        placement is the costliest step of a plan, so an evaluation skips it."""
        missing = [g for g in self.gene_names if g not in genes]
        if missing:
            raise ValueError(f"genes: missing {', '.join(missing)}")
        tool = np.asarray(genes["tool"]).astype(np.int64)
        n = len(tool)
        step = np.broadcast_to(np.asarray(genes["step"], float), (n,))
        if self.spacing == "stepover":
            delta = np.asarray(genes["stepover"], float) / 100.0 * 2.0 * self.tools.R[tool]
        else:
            delta = np.full(n, np.nan)
        parts: list[Sections] = []
        zones = np.ones(n, np.int64)
        if not self.zoned:
            geom = self.geometry(np.radians(self.feed_angle))
            parts.append(full_plane_sections(geom, np.arange(n), delta, step))
        else:
            values = (np.asarray(genes[self.layouts.gene], float) if self.layouts.gene
                      else np.zeros(n))
            for (value, t), rows in _groups(values, tool, self.layouts):
                layout = self.layouts.get(value, t)
                zones[rows] = layout.count
                for z in range(layout.count):
                    geom = self.geometry(layout.alpha[z])
                    parts.append(zone_sections(geom, layout, z, rows, delta[rows], step[rows],
                                               self.spacing))
        return self._assemble(n, zones, parts, tool, genes, place)

    def cl_path(self, genes: dict, feed_rate: float = 1000.0, chord_rounds: int = 8) -> CLPath:
        """The toolpath of ONE decision set (``genes``: a value or a (1,) array per name) as
        the machine runs it. A 3-axis plan's moves are split until each stays within the
        chord tolerance of the placement's CL curve: the drop-cutter tip falls away at edges
        and crests and swings round corners, and a straight move there would cut into the
        part (``zoning/chord.py``: ``refine_drop_moves``, checked at the move's own XY; a
        tangent placement: ``refine_chords``); ``info`` reports it and the CC points."""
        one = {k: np.atleast_1d(np.asarray(v))[:1] for k, v in genes.items()}
        batch = self.plan(one, place=True)
        tool = self.tools.tools[int(one["tool"][0])]
        path = batch.cl_path(0, tool.diameter, tool.corner_radius, feed_rate)
        if self.machine.name != "3axis":
            return path
        pts = {"uv": path.info["uv"], "cc": path.info["cc"], "normal": path.info["normal"],
               "tip": path.tip, "section": path.section, "pass_index": path.pass_index,
               "zone": path.zone, "on_part": path.info["on_part"],
               "inserted": np.zeros(len(path), bool)}
        cutter = tool.cutter
        if self.machine.drop:  # the drop-cutter placement: every move at its own XY
            pts, stats = refine_drop_moves(pts, cutter, self.surface, self.tolerance,
                                           chord_rounds)
        else:  # the tangent placement: against the tangent tip at the moves' CC points
            def place(c, surface, cc, normal):
                return self.machine.tips(c, surface, cc, normal, None)

            pts, stats = refine_chords(self.surface, cutter, place, pts, self.tolerance,
                                       chord_rounds)
        info = {"cc": pts["cc"], "uv": pts["uv"], "normal": pts["normal"],
                "on_part": pts["on_part"], "inserted": pts["inserted"], **stats}
        return CLPath(pts["tip"], np.array([0.0, 0.0, 1.0]), tool.diameter,
                      tool.corner_radius, section=pts["section"],
                      pass_index=pts["pass_index"], zone=pts["zone"], feed_rate=feed_rate,
                      info=info)

    # ---------------------------------------------------------------------------------
    def _assemble(self, n, zones, parts, tool, genes, place) -> PlanBatch:
        """Sample every part's sections, order them for machining, orient the tool."""
        parts = [s for s in parts if len(s.d)]
        if not parts:
            raise ValueError("plan: no section holds a CC point (empty plan)")
        sampled = [sample_sections(s.geom, s.d, s.ta, s.tb, s.step, self.tolerance,
                                   self.max_rounds) for s in parts]
        sec = {k: np.concatenate([getattr(s, k) for s in parts])
               for k in ("ind", "zone", "pass_k", "d", "ta", "tb", "spacing", "side", "run_lo",
                         "run_hi")}
        sec["alpha"] = np.concatenate([np.full(len(s.d), s.alpha) for s in parts])
        sec_off = np.cumsum([0] + [len(s.d) for s in parts])[:-1]
        pt_off = np.cumsum([0] + [len(sp.u) for sp in sampled])[:-1]
        start = np.concatenate([sp.sec_start + o for sp, o in zip(sampled, pt_off)])
        count = np.concatenate([sp.sec_count for sp in sampled])
        pts = {k: np.concatenate([getattr(sp, k) for sp in sampled])
               for k in ("u", "v", "p", "chord", "seg_err", "seg_len")}
        seg_sec = np.concatenate([sp.seg_sec + o for sp, o in zip(sampled, sec_off)])
        reverse = _pass_rank(sec["ind"], sec["zone"], sec["pass_k"]) % 2 == 1
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
        u, v, p, chord = (pts[k][src] for k in ("u", "v", "p", "chord"))
        normal = unit_normal(self.surface.jet(u, v, order=1), self.surface.normal_sign)
        tangent = travel_tangent(normal, sec["alpha"][pt_sec], reverse[pt_sec])
        ind_pt = sec["ind"][pt_sec]
        axis = self.machine.axes(normal, tangent, {g: np.asarray(genes[g], float)[ind_pt]
                                                   for g in self.machine.genes})
        seg = {"sec": inv[seg_sec][seg_order], "err": pts["seg_err"][seg_order],
               "len": pts["seg_len"][seg_order], "cc": np.ones(len(seg_order), bool)}
        pt = {"u": u, "v": v, "p": p, "chord": chord, "normal": normal, "tangent": tangent,
              "axis": axis}
        on_part, shift = np.ones(len(u), bool), np.zeros_like(p)
        if self.edge_overrun:
            lo_end, hi_end = sec["ta"] <= 1e-9, sec["tb"] >= 1 - 1e-9
            ahead = np.zeros(len(u))
            for t in np.unique(tool[ind_pt]):
                sel = tool[ind_pt] == t
                off = self.tools.cutter(t).cc_to_tip(p[sel], normal[sel], axis[sel]) - p[sel]
                ahead[sel] = np.sum(off[:, :2] * tangent[sel, :2], axis=1) / np.maximum(
                    np.linalg.norm(tangent[sel, :2], axis=1), 1e-300)
            wedge = 1.0 if self.machine.wedge else 0.0  # Machine.wedge
            pt, new_start, count, on_part, shift, (x_sec, x_len) = add_overrun(
                pt, new_start, count, np.where(reverse, hi_end, lo_end),
                np.where(reverse, lo_end, hi_end),
                wedge * np.where(reverse, sec["run_hi"], sec["run_lo"]),
                wedge * np.where(reverse, sec["run_lo"], sec["run_hi"]), ahead)
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
            for t in np.unique(tool[ind_pt]):
                sel = tool[ind_pt] == t
                tip[sel] = self.machine.tips(self.tools.cutter(t), self.surface,
                                             pt["p"][sel] - shift[sel], pt["normal"][sel],
                                             pt["axis"][sel], shift[sel])
        return PlanBatch(
            n=n, zones=zones, sec_ind=sec["ind"], sec_zone=sec["zone"], sec_pass=sec["pass_k"],
            sec_d=sec["d"], sec_alpha=sec["alpha"], sec_reverse=reverse,
            sec_spacing=sec["spacing"], sec_side=sec["side"], sec_start=new_start,
            sec_count=count, pt_sec=pt_sec, tip=tip, on_part=on_part, seg_sec=seg["sec"],
            seg_err=seg["err"], seg_len=seg["len"], seg_cc=seg["cc"], **pt)


def _pass_rank(ind, zone, pass_k):
    """Rank of each section's plane among the non-empty planes of its (individual, zone):
    the zig-zag alternates over the planes that are really cut."""
    o = np.lexsort((pass_k, zone, ind))
    g_new = np.r_[True, (ind[o][1:] != ind[o][:-1]) | (zone[o][1:] != zone[o][:-1])]
    p_new = g_new | np.r_[True, pass_k[o][1:] != pass_k[o][:-1]]
    cum = np.cumsum(p_new)
    rank = np.empty(len(o), np.int64)
    rank[o] = cum - np.maximum.accumulate(np.where(g_new, cum, 0))
    return rank


def _groups(values, tool, layouts):
    """Individuals grouped by (zoning gene value, tool): [((value, tool), rows)]."""
    keys = np.stack([layouts.keys(values), np.asarray(tool, float)])
    uniq, inverse = np.unique(keys, axis=1, return_inverse=True)
    return [((layouts.key(v), int(t)), np.flatnonzero(inverse.ravel() == g))
            for g, (v, t) in enumerate(uniq.T)]
