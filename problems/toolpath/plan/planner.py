"""The planner: decisions in, toolpath plans (``PlanBatch``) out, for a whole population.

One pipeline for every configuration (the folders' order):

1. **Zones** (``zones.py``): ``single`` (the whole part), or a zoning method of the
   registry (``zoning/methods``: kmeans, amas) with its gene; zone labels on the
   parametric mesh are memoized per gene value.
2. **Feed direction per zone**: the configured ``feed_angle``, or optimized per zone
   (Herraz Eq. 3 on the zone's samples: ``zoning/direction.py``), memoized per
   (zoning, tool).
3. **Passes**: the strategy's (``strategies/``, one module and one registry entry each:
   ``parallel`` planes, ``isoscallop`` offsets, ``contour`` loops, ``isoparametric``
   curves); the planner
   holds no pass logic. Each strategy puts CC points on its passes (the maximum step, then
   the chord tolerance) and orders them for machining (zones in plan order, passes in
   zig-zag inside a zone, sections along their travel).
4. **Orientation, run-on, placement** (``finish.py``, the same for every strategy):
   3-axis (drop-cutter) or 5-axis (lead/tilt) (``orientation.py``); sections that end on
   the part's edge run on past it (``overrun.py``); a ``PlanBatch`` in machining order.

Everything is batched: the individuals that share a zone geometry (the same direction) are
planned together with no Python loop per individual, pass or point.
"""

from __future__ import annotations

import numpy as np

from ..geometry.surface import Surface
from ..tools import ToolDatabase
from ..clpath import CLPath
from .batch import PlanBatch, merge_batches
from .orientation import get_machine
from .planes import PassGeometry
from .strategies import get_strategy
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
    the former evaluator's passes did, and leave the edge rows and wedges high);
    ``border_passes``: a trimmed footprint's edges that the passes leave high are cut by
    border passes (``border.py``).
    """

    def __init__(self, surface: Surface, tools: ToolDatabase, *, machine: str = "5axis",
                 placement: str | None = None, zoning=None, spacing: str = "stepover",
                 h_c: float | None = None, tolerance: float = 0.01,
                 feed_angle: float | None = 0.0, max_rounds: int = 6,
                 edge_overrun: bool = True, strategy=None, border_passes: bool = True):
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
        self.border_passes = bool(border_passes)
        self.layouts = ZoneLayouts(surface, tools, zoning, self.h_c, self.feed_angle)
        # a list of strategies: the categorical gene ``strategy`` chooses among them
        self.choices = ([get_strategy(x, f"strategy[{i}]") for i, x in enumerate(strategy)]
                        if isinstance(strategy, (list, tuple)) else None)
        if self.choices is not None and not self.choices:
            raise ValueError("strategy: an empty list of strategies to choose from")
        self.strategy = self.choices[0] if self.choices else get_strategy(strategy)
        for st in self.choices or [self.strategy]:
            st.check(self)

    # ---------------------------------------------------------------------------------
    @property
    def gene_names(self) -> tuple[str, ...]:
        """The decisions this configuration reads, in chromosome order."""
        own = dict.fromkeys(g for st in (self.choices or [self.strategy])
                            for g in st.gene_names(self))
        names = [g for g in ("tool", "stepover") if g in own] + list(self.machine.genes)
        names += ["step"] + (["strategy"] if self.choices else [])
        if self.layouts.gene is not None:
            names.append(self.layouts.gene)
        return tuple(names)

    @property
    def zoned(self) -> bool:
        """Whether plans go through zone layouts (False: one zone fed along the configured
        direction at a fixed step-over, every plane across the whole footprint)."""
        return not (self.whole_planes and self.strategy.name == "parallel"
                    and not self.choices)

    @property
    def whole_planes(self) -> bool:
        """Whether parallel planes need no zone layout: one zone, the configured direction, a
        fixed step-over (every plane across the whole footprint)."""
        return (self.layouts.gene is None and self.layouts.single
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
        """Pass-plane tables for the feed direction alpha (radians), memoized (with the
        zone layouts, which build those of their zones' directions)."""
        return self.layouts.geometry(alpha)

    def decisions(self, genes: dict):
        """(tool index (n,), n, step (n,), XY step-over delta (n,) mm, nan without one)."""
        missing = [g for g in self.gene_names if g not in genes]
        if missing:
            raise ValueError(f"genes: missing {', '.join(missing)}")
        tool = np.asarray(genes["tool"]).astype(np.int64)
        n = len(tool)
        step = np.broadcast_to(np.asarray(genes["step"], float), (n,))
        if "stepover" in self.gene_names:
            delta = np.asarray(genes["stepover"], float) / 100.0 * 2.0 * self.tools.R[tool]
        else:
            delta = np.full(n, np.nan)
        return tool, n, step, delta

    def plan(self, genes: dict, place: bool = True) -> PlanBatch:
        """Plans of n decision sets: ``genes`` maps every name of :attr:`gene_names` to an
        (n,) array (``tool`` the INDEX into the database). ``place``: also the CL points
        (``tip``); the analytic criteria do not need them, and a 3-axis drop-cutter
        placement is the costliest step of a plan, so an evaluation skips it. The passes
        are the strategy's (``strategies/``); with a ``strategy`` gene (an index into the
        planner's list of strategies) each strategy plans its individuals and the plans
        form one batch."""
        if not self.choices:
            return self._bordered(self.strategy.plan(self, genes, place), genes, place)
        missing = [g for g in self.gene_names if g not in genes]
        if missing:
            raise ValueError(f"genes: missing {', '.join(missing)}")
        k = np.clip(np.rint(np.asarray(genes["strategy"], float)), 0,
                    len(self.choices) - 1).astype(np.int64)
        parts = []
        for s in np.unique(k):
            rows = np.flatnonzero(k == s)
            sub = {g: np.broadcast_to(np.asarray(v), (len(k),))[rows] for g, v in genes.items()}
            parts.append((rows, self.choices[s].plan(self, sub, place)))
        batch = parts[0][1] if len(parts) == 1 and len(parts[0][0]) == len(k) else \
            merge_batches(len(k), parts)
        return self._bordered(batch, genes, place)

    def _bordered(self, batch: PlanBatch, genes: dict, place: bool) -> PlanBatch:
        """The border passes a trimmed footprint's plans need (``border.py``)."""
        if not self.border_passes:
            return batch
        from .border import with_border

        return with_border(self, batch, genes, place)

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
        path = batch.cl_path(0, tool.cutter, feed_rate)
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
        return CLPath(pts["tip"], np.array([0.0, 0.0, 1.0]), cutter, section=pts["section"],
                      pass_index=pts["pass_index"], zone=pts["zone"], feed_rate=feed_rate,
                      info=info)
