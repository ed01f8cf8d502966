"""``ToolpathProblem``: the one toolpath engine as a batched pymoo problem.

A row of the chromosome is a set of decisions (``genes.py``): the tool, the step-over, the
lead and tilt, the discretization step and the zoning method's gene (K or k_LZ); which of
them exist is set by the strategy (``strategy.py``: machine, spacing, zoning) and any of
them may be fixed in the config. One evaluation of a population:

    X -> genes (tool as an index, fixed genes inserted) -> Planner.plan -> PlanBatch
      -> analytic criteria (criteria/analytic.py), or under ``criteria: simulated`` the
         scallop, gouge and machining error measured by the cut simulation per plan
      -> F: Fountas Eq. 9, the weighted sum of criteria normalized by FIXED bounds
         (criteria/objective.py; the bounds from a seeded design over the free genes),
         or with ``objectives`` the normalized criteria themselves (a Pareto front).

With the defaults (Fountas' surface, nine tools, 5-axis, one zone fed along X, step-over
spacing) the chromosome is Fountas' five genes, X (n, 5). Fountas prints the step range as
"[0.005-0.01]" and Table 2 as "x 10^-3 mm"; with those values a pass of ~96 mm would hold
~10^4 points, not the reported 289-337 CC points in total, so they are metres: 5-10 mm.
"""

from __future__ import annotations

import numpy as np
from pymoo.core.problem import Problem

from .criteria.analytic import ANALYTIC, analytic_criteria
from .criteria.objective import bounds_from_sample, normalize, parse_bounds, weighted_sum
from .criteria.table import names as criterion_names
from .genes import DEFAULT_RANGES, GENE_ORDER, PARAM_NAMES, GeneSpace
from .geometry.registry import parse_surface
from .plan.planner import Planner
from .spec import ToolpathSpec, tool_database
from .strategy import absent_genes

__all__ = ["ToolpathProblem", "ToolpathSpec", "PARAM_NAMES", "GENE_ORDER", "DEFAULT_RANGES"]


class ToolpathProblem(Problem):
    """Finishing of a free-form surface: plans of every decision set, judged by criteria.

    Built from a :class:`~.spec.ToolpathSpec` (``ToolpathProblem(spec)``), or from the plain
    data of a YAML ``params:`` mapping given as keywords (``ToolpathProblem(surface="choi",
    ...)`` = ``ToolpathProblem.from_params(...)``), which are validated into the spec first;
    ``docs/toolpath-spec.md`` lists every key. The part and tools: ``surface`` (default Fountas
    Eq. 14), ``tools`` (default the nine tools of ``tools.py``), ``base_dir`` for relative
    files. The strategy: ``machine`` 5axis | 3axis, ``placement`` (3-axis: drop | cc),
    ``zoning`` {method, mesh, merge, settings, seed}, ``spacing`` stepover | scallop, ``h_c``
    (mm; 0.254 with scallop spacing), ``delta_l`` (mm, Eq. 4), ``feed_angle`` (degrees from +X,
    or ``optimized``), ``tolerance`` (chord, mm), ``edge_overrun``, ``border_passes``, ``strategy``. The
    decisions: ``ranges`` {gene: [lo, hi]}, ``fixed`` {gene: value} (the tool by its id). The
    judgement: ``weights`` (criterion -> weight, default machining_error 0.5 + cc_count 0.5),
    ``objectives`` (a multi-objective F), ``normalization`` {criterion: [lo, hi]} (``[0, 1]``
    keeps a criterion's raw value), ``normalization_samples`` / ``seed`` of the fixed design
    (with every gene fixed there is no design: a criterion without given bounds enters Eq. 9
    raw), ``feed_rate`` mm/min (the feed of a tool without a library ``feed``), ``dynamics``
    (the machine's limits), ``allowance`` mm, ``criteria`` analytic | simulated (with
    ``simulation`` {grid_mm, rays, allowance, threads, screening}).
    Bad input raises a one-line ValueError starting with the key path.
    """

    def __init__(self, spec: ToolpathSpec | None = None, /, *, base_dir=None, **params):
        if spec is None:
            spec = ToolpathSpec.from_params(params, base_dir)
        elif not isinstance(spec, ToolpathSpec) or params or base_dir is not None:
            raise TypeError("ToolpathProblem(spec) takes a ToolpathSpec alone, or keyword params")
        self.spec = spec
        surf = parse_surface(spec.surface, "surface", spec.base_dir)
        self.tool_db = tool_database(spec.tools)
        self.machine = spec.machine
        self.planner = Planner(
            surf, self.tool_db, machine=spec.machine, placement=spec.placement,
            zoning=None if spec.zoning is None else spec.zoning.zoning_spec(spec.delta_l),
            spacing=spec.spacing, h_c=spec.scallop_height, tolerance=spec.tolerance,
            feed_angle=None if spec.feed_angle == "optimized" else spec.feed_angle,
            max_rounds=spec.max_rounds, edge_overrun=spec.edge_overrun, strategy=spec.strategy,
            border_passes=spec.border_passes)
        self.delta_l = spec.delta_l
        self.feed_rate = spec.feed_rate
        self.dynamics = spec.dynamics
        self.allowance = spec.allowance
        self.tolerance = self.planner.tolerance
        layouts = self.planner.layouts
        self.genes = GeneSpace(
            self.planner.gene_names, self.tool_db,
            None if spec.ranges is None else spec.ranges.given(),
            None if spec.fixed is None else spec.fixed.given(),
            absent=absent_genes(spec.machine, spec.spacing, layouts.method.name,
                                self.planner.strategy.name),
            zone_gene=layouts.method.gene, zone_range=self._zone_range,
            zone_value=self._zone_value,
            choices={"strategy": [st.name for st in self.planner.choices]}
            if self.planner.choices else None)
        self.weights = spec.weights_or_default
        self.objectives = None if spec.objectives is None else list(spec.objectives)
        self.simulated = None
        if spec.criteria == "simulated":
            from .criteria.simulated import SimulatedCriteria

            self.simulated = SimulatedCriteria(surf, spec.simulation)
        self.variables = self.genes.variables
        names = spec.judged
        given = parse_bounds(spec.normalization, names)
        missing = [k for k in names if k not in given]
        if missing and self.genes.n_var == 0:  # one plan, no design: its raw criteria
            given.update({k: (0.0, 1.0) for k in missing})
        elif missing:
            design = self.genes.design(int(spec.normalization_samples), int(spec.seed))
            given.update(bounds_from_sample(self._raw_criteria(design), missing))
        self.norm_bounds = {k: given[k] for k in names}
        super().__init__(n_var=self.genes.n_var,
                         n_obj=1 if self.objectives is None else len(self.objectives),
                         xl=self.genes.xl, xu=self.genes.xu, vtype=float, vars=self.variables)

    @classmethod
    def from_params(cls, base_dir=None, **params) -> "ToolpathProblem":
        """The problem of plain ``params`` (a run file's mapping), validated into the spec."""
        return cls(ToolpathSpec.from_params(params, base_dir))

    # -- configuration ------------------------------------------------------------------
    def _zone_range(self, value):
        layouts = self.planner.layouts
        try:
            return layouts.method.gene_range(value, layouts.features)
        except ValueError as e:
            raise ValueError(f"ranges.{e}") from None

    def _zone_value(self, value, key):
        method = self.planner.layouts.method
        try:
            method.settings({method.gene.setting: int(value) if method.gene.integer else value})
        except ValueError as e:
            raise ValueError(f"{key}: {str(e).split(': ', 1)[-1]}") from None

    @property
    def fixed(self) -> dict:
        """Fixed genes by name (the tool by its id): not variables of the chromosome."""
        return {k: int(self.tool_db.ids[int(v)]) if k == "tool" else v
                for k, v in self.genes.fixed.items()}

    @property
    def n_tools(self) -> int:
        return len(self.tool_db)

    @property
    def ranges(self) -> dict:
        """The free continuous genes' ranges."""
        return dict(self.genes.bounds)

    @property
    def surface(self):
        """The part's design surface."""
        return self.planner.surface

    @property
    def simulation_tolerance(self) -> float:
        """The tolerance band of a simulated cut's deviation map: h_c with a scallop target,
        else the cut tolerance (mm)."""
        return self.planner.h_c if self.planner.spacing == "scallop" else self.tolerance

    # -- rows -----------------------------------------------------------------------------
    def check(self, X) -> np.ndarray:
        """X as (n, n_var) float; ValueError ``params.<name>: ...`` for a value out of range."""
        return self.genes.check(X)

    def row(self, params) -> np.ndarray:
        """One decision set by name (the tool by its id) -> X row (1, n_var)."""
        return self.genes.row(params)

    def plan(self, X, place: bool = True):
        """(PlanBatch, genes) of the rows X (``place``: with the CL points)."""
        genes = self.genes.decode(self.check(X))
        return self.planner.plan(genes, place=place), genes

    # -- criteria -------------------------------------------------------------------------
    def _raw_criteria(self, X) -> dict[str, np.ndarray]:
        """The analytic criteria of X, with the simulated ones in place of the analytic
        scallop, gouge and machining error under ``criteria: simulated``. The last single
        plan's criteria are kept: its objective and its report (``evaluate``, a run with
        every gene fixed) cost one evaluation, not two."""
        X = self.check(X)
        if len(X) == 0:
            return {k: np.zeros(0) for k in ANALYTIC}
        key = X.tobytes() if len(X) == 1 else None
        memo = getattr(self, "_one_plan", None)
        if key is not None and memo is not None and memo[0] == key:
            return {k: v.copy() for k, v in memo[1].items()}
        crit = self._criteria_of(X)
        if key is not None:
            self._one_plan = (key, {k: np.array(v, copy=True) for k, v in crit.items()})
        return crit

    def _criteria_of(self, X) -> dict[str, np.ndarray]:
        crit, genes = self.analytic(X)
        if self.simulated is not None:
            crit |= self.simulate_rows(genes, range(len(X)))
        return crit

    def analytic(self, X) -> tuple[dict[str, np.ndarray], dict]:
        """(analytic criteria, decoded genes) of the rows X (checked), no simulation."""
        batch, genes = self.plan(X, place=False)
        return analytic_criteria(batch, self.surface, self.tool_db, genes,
                                 allowance=self.allowance, feed_rate=self.feed_rate,
                                 delta_l=self.delta_l, machine=self.machine,
                                 dynamics=self.dynamics), genes

    def simulate_rows(self, genes: dict, rows) -> dict[str, np.ndarray]:
        """The simulated criteria of the given rows of decoded ``genes``: one cut simulation
        of each row's CL path (``criteria: simulated``)."""
        measured = []
        for i in rows:
            one = {k: v[i:i + 1] for k, v in genes.items()}
            path = self.planner.cl_path(one, self.programmed_feed(one))
            flat = self.tool_db.cutter(int(genes["tool"][i])).sharp_rim
            measured.append(self.simulated.measure(path, flat))
        return {name: np.array([m[name] for m in measured])
                for name in criterion_names(simulated=True)}

    def criteria(self, X) -> dict[str, np.ndarray]:
        """Every raw criterion per row of X, plus ``objective`` (Eq. 9): dict of (n,)."""
        crit = self._raw_criteria(X)
        n = len(next(iter(crit.values())))
        crit["objective"] = (weighted_sum(crit, self.weights, self.norm_bounds)
                             if self.objectives is None else np.full(n, np.nan))
        return crit

    def evaluate_params(self, params) -> dict[str, float]:
        """Every criterion (floats) of ONE decision set, given by name (tool = tool id)."""
        crit = self.criteria(self.row(params))
        return {k: float(v[0]) for k, v in crit.items()}

    def _evaluate(self, X, out, *args, **kwargs):
        screening = getattr(self.simulated, "screening", None)
        if screening is not None:  # criteria/screening.py: F, and the simulations each row cost
            out["F"], out["cost"] = screening.evaluate(self, self.check(X))
            return
        crit = self._raw_criteria(X)
        if self.objectives is None:
            out["F"] = weighted_sum(crit, self.weights, self.norm_bounds)[:, None]
        else:
            norm = normalize(crit, self.norm_bounds)
            out["F"] = np.column_stack([norm[k] for k in self.objectives]) if len(X) \
                else np.zeros((0, len(self.objectives)))

    # -- one plan -------------------------------------------------------------------------
    def labels(self, genes: dict):
        """The zone labels on the parametric mesh of the first plan of ``genes`` (None for
        a single zone fed along a given direction)."""
        layout = self.planner.layout(genes)
        return None if layout is None else layout.labels

    def programmed_feed(self, genes: dict) -> float:
        """The feed (mm/min) the first plan of ``genes`` is programmed at, in its APT and NC
        files and in both machining times: its tool's library ``feed``, else ``feed_rate``."""
        return float(self.tool_db.feeds(self.feed_rate)[int(np.atleast_1d(genes["tool"])[0])])

    def cl_path(self, params):
        """(CLPath, mesh labels or None): the toolpath of one decision set (by name, the tool
        by its id) as the machine runs it; the labels of a zoned plan (``evoplan simulate``)."""
        genes = self.genes.decode(self.row(params))
        return self.planner.cl_path(genes, self.programmed_feed(genes)), self.labels(genes)

    def artifacts(self, x) -> dict[str, bytes]:
        """Result files of one decision set ``x`` (a phenotype row, the tool as its index):
        the zone map with the plan's sections, the CC pattern on the surface and the APT CL
        program with a ``$$ ZONE z PASS k`` comment opening each section. The title's lengths
        come from the plan itself: no criterion is evaluated (no cut simulation)."""
        from .artifacts import plan_artifacts

        X = self.check(np.asarray(x, float).reshape(1, -1))
        batch, genes = self.plan(X)
        path = self.planner.cl_path(genes, self.programmed_feed(genes))
        return plan_artifacts(self, batch, genes, path)
