"""Zoning as a decision of the toolpath problem: the pymoo problem GA and VEGA optimize.

Genes (``variables``): the cutter (a choice from the tool database) and the zoning gene of
the registered method (``methods/``, its ``gene``): the number of K-means clusters ``zones``
(Herraz) or, with ``method: amas``, Djebali's k_LZ.
Delta L, h_c, the mesh and the surface come from the config. The objective is the machining
length of Djebali Eq. 4 (mm): each zone machined along its optimized direction with the
step-over that keeps the scallop under h_c, plus (|Z| - 1) Delta L. The step-over is then
not a gene: at a given h_c the largest admissible one is always best for the length.

A plan depends only on the decoded genes, so plans are memoized (the decoded space of
``zones`` x tools is small); ``criteria(X)`` gives the raw numbers (zones, cutting length,
penalty, total).
"""

from __future__ import annotations

import numpy as np
from pymoo.core.problem import Problem
from pymoo.core.variable import Choice, Integer, Real

from ...checks import number
from ...geometry.spec import parse_surface
from ...tools import parse_tools
from .features import check_mesh, mesh_features
from .methods import get_method
from .plan import ZoningPlan, plan_from_labels, zone_labels
from .samples import sample_surface
from .stepover import ScallopTarget

__all__ = ["ZonedToolpathProblem"]

CHOI_TOOLS = [
    {"id": 1, "type": "ball", "diameter": 6.35},
    {"id": 2, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.0},
    {"id": 3, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.27},
    {"id": 4, "type": "flat", "diameter": 6.35},
]


class ZonedToolpathProblem(Problem):
    """Tool and zoning chosen together; minimize the Eq. 4 length (see the module doc).

    Plain-data params: ``surface`` (default choi), ``tools`` (default: Choi's R 3.175 ball,
    toroidal r 1 and 1.27, flat), ``h_c`` (0.254), ``delta_l`` (40), ``mesh`` ([70, 70]),
    ``method`` (a registered method with a gene: kmeans | amas), ``zones`` range for kmeans
    ([1, 8]), ``k_lz`` range for amas ([0.02, 0.6]), another method's gene range under its
    gene name in ``gene_ranges``, ``settings`` (the method's fixed settings), ``k_cmd`` (1,
    for a method with that setting), ``seed`` (AMAS tie-breaks), ``stepover_model``.
    """

    def __init__(self, surface="choi", tools=None, h_c=0.254, delta_l=40.0, mesh=(70, 70),
                 method="kmeans", zones=(1, 8), k_lz=(0.02, 0.6), k_cmd=1.0, seed=0,
                 stepover_model="profile", base_dir=None, settings=None, gene_ranges=None):
        self.surface = parse_surface(surface, "surface", base_dir)
        self.tool_db = parse_tools(tools if tools is not None else CHOI_TOOLS, "tools")
        self.h_c = number(h_c, "h_c", positive=True)
        self.delta_l = number(delta_l, "delta_l")
        if self.delta_l < 0:
            raise ValueError(f"delta_l: must be >= 0 mm, got {delta_l!r}")
        self.zoning = get_method(method)
        if self.zoning.gene is None:
            raise ValueError(f"method: {method!r} has no setting to optimize as a gene")
        if stepover_model not in ("profile", "circle"):
            raise ValueError(f"stepover_model: expected profile or circle, got {stepover_model!r}")
        self.method, self.model = self.zoning.name, stepover_model
        self.k_cmd, self.seed = number(k_cmd, "k_cmd"), int(seed)
        fixed = dict(settings or {})
        if "k_cmd" in self.zoning.Settings.model_fields:
            fixed.setdefault("k_cmd", self.k_cmd)
        self.settings = self.zoning.settings(fixed).model_dump()
        self.features = mesh_features(self.surface, *check_mesh(*mesh))
        self.samples = sample_surface(self.surface)
        ids = [int(t) for t in self.tool_db.ids]
        spec = self.zoning.gene
        ranges = {"zones": zones, "k_lz": k_lz, **(gene_ranges or {})}
        lo, hi = self.zoning.gene_range(ranges.get(spec.name, spec.bounds), self.features)
        gene = Integer(bounds=(int(lo), int(hi))) if spec.integer else Real(bounds=(lo, hi))
        self.gene = spec.name
        self.variables = {"tool": Choice(options=ids), self.gene: gene}
        self._plans: dict = {}
        self._labels: dict = {}
        super().__init__(n_var=2, n_obj=1, xl=np.array([0.0, lo]),
                         xu=np.array([len(ids) - 1.0, hi]), vtype=float, vars=self.variables)

    def target(self, tool_index: int) -> ScallopTarget:
        """The database's cutter at ``tool_index`` with this problem's scallop limit h_c."""
        return ScallopTarget(self.tool_db.cutter(tool_index), self.h_c)

    def _decode(self, value: float):
        """The zoning gene's value as the method's setting (an int for an integer gene)."""
        return int(round(value)) if self.zoning.gene.integer else round(float(value), 9)

    def labels(self, value: float) -> np.ndarray:
        """Zone labels on the mesh for one value of the zoning gene (memoized)."""
        value = self._decode(value)
        if value not in self._labels:
            settings = {**self.settings, self.zoning.gene.setting: value}
            labels, _ = zone_labels(self.features, self.zoning, seed=self.seed, **settings)
            self._labels[value] = labels
        return self._labels[value]

    def zoning_plan(self, tool_index: int, value: float) -> ZoningPlan:
        """The whole plan (zones, directions, planes) of one decoded gene pair."""
        labels = self.labels(value)
        zones, seconds = plan_from_labels(self.samples, self.features, labels,
                                          self.target(tool_index), self.model)
        return ZoningPlan(self.method, labels, zones, self.delta_l, {"directions": seconds},
                          features=self.features)

    @property
    def simulation_tolerance(self) -> float:
        """The tolerance band of a simulated cut's deviation map: h_c (mm)."""
        return self.h_c

    def cl_path(self, params, step: float = 1.0, placement: str = "drop",
                tolerance: float | None = 0.01):
        """(CLPath, mesh labels) of one plan given by name (``tool`` = the tool id, and
        ``zones`` or ``k_lz``): every zone's passes as CL points of the vertical cutter,
        moves within ``tolerance`` mm of the CL curve (``zone_cl_path``)."""
        from .cl_points import zone_cl_path

        missing = [k for k in ("tool", self.gene) if k not in params]
        if missing:
            raise ValueError(f"params.{missing[0]}: missing")
        index = self.tool_db.index_of(params["tool"])
        plan = self.zoning_plan(index, number(params[self.gene], f"params.{self.gene}"))
        return (zone_cl_path(self.surface, plan, self.tool_db.cutter(index), step=step,
                             placement=placement, tolerance=tolerance), plan.labels)

    def artifacts(self, x) -> dict[str, bytes]:
        """Result files of one plan ``x: (2,)`` (a phenotype row: the tool as its index, the
        zoning gene): the zone map with each zone's passes and the borders, the CC points on
        the surface coloured by zone, and the APT CL program of :meth:`cl_path` (what
        ``evoplan simulate --run`` cuts) with a ``$$ ZONE z PASS k`` comment opening each
        section and a retract and approach between sections."""
        import textwrap

        from ...figures import cc_pattern_png
        from ...export.apt_write import apt_toolpath
        from ...export.toolpath import Tool, Toolpath
        from .figures import zone_map_png

        x = np.asarray(x, float).reshape(-1)
        tool = self.tool_db.tools[int(round(x[0]))]
        value = self._decode(x[1])
        plan = self.zoning_plan(int(round(x[0])), value)
        path, _ = self.cl_path({"tool": tool.id, self.gene: value})
        settings = (f"tool {tool.id} ({tool.label()}), {self.gene} {value:g}, {self.method}: "
                    f"{len(plan.zones)} zones, h_c {self.h_c:g} mm, Eq. 4 total "
                    f"{plan.total_length:.1f} mm")
        starts = np.flatnonzero(np.r_[True, np.diff(path.section) != 0])
        names = {int(path.section[i]): f"ZONE {path.zone[i]} PASS {path.pass_index[i]}"
                 for i in starts}
        tp = Toolpath.from_sections("finish", Tool(tool.id, tool.diameter, tool.corner_radius),
                                    path.tip, path.axis, path.section, feed=path.feed_rate,
                                    comments=textwrap.wrap(settings, 66), section_names=names)
        return {"zone_map.png": zone_map_png(self.surface, plan, self.samples, title=settings),
                "cc_pattern.png": cc_pattern_png(self.surface, path.info["cc"], path.pass_index,
                                                 title=settings, color=path.zone,
                                                 color_label="zone", categories=len(plan.zones)),
                "toolpath.apt": apt_toolpath(tp, part="EVOPLAN ZONED TOOLPATH").encode()}

    def plan(self, tool_index: int, value: float) -> dict[str, float]:
        """Raw numbers of one decoded gene pair (memoized)."""
        value = self._decode(value)
        key = (int(tool_index), value)
        if key not in self._plans:
            labels = self.labels(value)
            zones, _ = plan_from_labels(self.samples, self.features, labels,
                                        self.target(tool_index), self.model)
            cutting = float(sum(z.length for z in zones))
            penalty = (len(zones) - 1) * self.delta_l
            self._plans[key] = {"zones": float(len(zones)), "cutting_length": cutting,
                                "penalty": penalty, "total_length": cutting + penalty}
        return self._plans[key]

    def criteria(self, X) -> dict[str, np.ndarray]:
        if isinstance(X, dict) or (np.ndim(X) == 1 and len(X) and isinstance(X[0], dict)):
            X = [[self.tool_db.index_of(r["tool"]), r[self.gene]]  # pymoo mixed-variable rows
                 for r in ([X] if isinstance(X, dict) else X)]
        X = np.atleast_2d(np.asarray(X, float))
        rows = [self.plan(int(round(x[0])), x[1]) for x in X]
        return {k: np.array([r[k] for r in rows]) for k in rows[0]}

    def _evaluate(self, X, out, *args, **kwargs):
        out["F"] = self.criteria(X)["total_length"][:, None]
