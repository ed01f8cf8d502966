"""``ToolpathProblem``: the toolpath simulator as a batched pymoo problem (Fountas et al.).

Chromosome X (n, 5) float, one row per parameter set:

    col  name      meaning                                           default range
    0    tool      INDEX into the tool database (rounded)            0 .. n_tools - 1
    1    stepover  % of the tool diameter, XY spacing of the planes  [20, 45]
    2    lead      degrees, about the cross-feed axis                [0, 5]
    3    tilt      degrees, about the feed                           [0, 2]
    4    step      maximum discretization step, mm                   [5, 10]

Fountas prints the step range as "[0.005-0.01]" and Table 2 as "x 10^-3 mm"; with those
values a pass of ~96 mm would hold ~10^4 points, not the reported 289-337 CC points in
total, so they are metres: 5-10 mm. ``variables`` maps the names to pymoo variables
(``tool`` as a Choice over the tool IDS); ``xl``/``xu`` are the numeric bounds above.

F: (n, 1) the weighted sum of normalized criteria (Eq. 9, ``objective.py``), or with
``objectives=[names]`` (n, k) the normalized criteria themselves (for a Pareto front).
:meth:`criteria` returns every raw criterion; :meth:`pattern` one toolpath's CC pattern.
"""

from __future__ import annotations

import textwrap

import numpy as np
from pymoo.core.problem import Problem
from pymoo.core.variable import Choice, Real

from .checks import interval, number
from .criteria.objective import (
    OBJECTIVE_CRITERIA, bounds_from_sample, normalization_design, normalize, parse_bounds,
    parse_weights, weighted_sum,
)
from .simulator import ToolpathSimulator
from .geometry.spec import parse_surface
from .tools import parse_tools

__all__ = ["ToolpathProblem", "PARAM_NAMES", "DEFAULT_RANGES"]

PARAM_NAMES = ("tool", "stepover", "lead", "tilt", "step")
DEFAULT_RANGES = {"stepover": (20.0, 45.0), "lead": (0.0, 5.0), "tilt": (0.0, 2.0),
                  "step": (5.0, 10.0)}


def _ranges(spec) -> dict[str, tuple[float, float]]:
    out = dict(DEFAULT_RANGES)
    if spec is None:
        return out
    if not isinstance(spec, dict):
        raise ValueError(f"ranges: expected a mapping name -> [lo, hi], got {spec!r}")
    for name, b in spec.items():
        key = f"ranges.{name}"
        if name not in DEFAULT_RANGES:
            raise ValueError(f"{key}: unknown parameter (known: {', '.join(DEFAULT_RANGES)})")
        lo, hi = interval(b, key)
        if name in ("stepover", "step") and lo <= 0:
            raise ValueError(f"{key}: must be > 0, got {b!r}")
        if name in ("lead", "tilt") and not (-90 < lo and hi < 90):
            raise ValueError(f"{key}: angles must lie in (-90, 90) degrees, got {b!r}")
        out[name] = (lo, hi)
    return out


class ToolpathProblem(Problem):
    """Zig-zag finishing of a free-form surface, evaluated by simulation (batched).

    All arguments are plain data (a YAML ``params:`` mapping): ``surface`` (see
    ``spec.py``; default Fountas Eq. 14), ``tools`` (list of mappings, default the nine
    tools of ``tools.py``), ``weights`` (criterion -> weight, default machining_error 0.5 +
    cc_count 0.5), ``feed_rate`` mm/min (1000), ``tolerance`` cut tolerance mm (0.01),
    ``feed_angle`` degrees from +X (0), ``ranges`` {stepover, lead, tilt, step: [lo, hi]},
    ``allowance`` finishing stock mm (0.5), ``normalization`` explicit {criterion: [lo, hi]},
    ``normalization_samples`` / ``seed`` for the fixed normalization design, ``objectives``
    a list of criteria for a multi-objective F, ``base_dir`` for relative pole files,
    ``criteria`` ``analytic`` (default) or ``simulated`` (scallop, gouge and machining error
    measured by the cut simulation, ``criteria/simulated.py``, with ``simulation``
    settings {grid_mm, rays, allowance}; the normalization design is simulated too).
    Bad input raises a one-line ValueError starting with the key path.
    """

    def __init__(self, surface="fountas", tools=None, weights=None, feed_rate=1000.0,
                 tolerance=0.01, feed_angle=0.0, ranges=None, allowance=0.5,
                 normalization=None, normalization_samples=64, seed=0, objectives=None,
                 base_dir=None, max_rounds=6, criteria="analytic", simulation=None):
        surf = parse_surface(surface, "surface", base_dir)
        self.tool_db = parse_tools(tools, "tools")
        self.weights = parse_weights(weights, "weights")
        angle = number(feed_angle, "feed_angle")
        self.ranges = _ranges(ranges)
        if objectives is not None:
            if isinstance(objectives, str) or not objectives:
                raise ValueError(f"objectives: expected a list of criteria, got {objectives!r}")
            for name in objectives:
                if name not in OBJECTIVE_CRITERIA:
                    raise ValueError(f"objectives: unknown criterion {name!r} "
                                     f"(known: {', '.join(OBJECTIVE_CRITERIA)})")
            objectives = list(objectives)
        self.objectives = objectives
        self.simulator = ToolpathSimulator(
            surf, self.tool_db, feed_angle=angle,
            tolerance=number(tolerance, "tolerance", positive=True),
            feed_rate=number(feed_rate, "feed_rate", positive=True),
            allowance=number(allowance, "allowance", positive=True), max_rounds=int(max_rounds))
        if criteria not in ("analytic", "simulated"):
            raise ValueError(f"criteria: expected analytic or simulated, got {criteria!r}")
        self.simulated = None
        if criteria == "simulated":
            from .criteria.simulated import SimulatedCriteria

            self.simulated = SimulatedCriteria(surf, simulation)
        elif simulation is not None:
            raise ValueError("simulation: only used with criteria: simulated")
        n_tools = len(self.tool_db)
        xl = np.array([0.0] + [self.ranges[k][0] for k in PARAM_NAMES[1:]])
        xu = np.array([float(n_tools - 1)] + [self.ranges[k][1] for k in PARAM_NAMES[1:]])
        self.variables = {
            "tool": Choice(options=[int(i) for i in self.tool_db.ids]),
            **{k: Real(bounds=self.ranges[k]) for k in PARAM_NAMES[1:]},
        }
        names = objectives if objectives is not None else list(self.weights)
        given = parse_bounds(normalization, names)
        missing = [k for k in names if k not in given]
        if missing:
            design = normalization_design(n_tools, xl, xu, int(normalization_samples), int(seed))
            given.update(bounds_from_sample(self._raw_criteria(design), missing))
        self.norm_bounds = {k: given[k] for k in names}
        super().__init__(n_var=5, n_obj=1 if objectives is None else len(objectives),
                         xl=xl, xu=xu, vtype=float, vars=self.variables)

    # ---------------------------------------------------------------------------------
    @property
    def n_tools(self) -> int:
        return len(self.tool_db)

    def check(self, X) -> np.ndarray:
        """X as (n, 5) float; ValueError ``params.<name>: ...`` for a value out of range.
        Rows may also be mappings name -> value (pymoo's mixed-variable form, ``vars``; the
        tool given by its id)."""
        if isinstance(X, dict) or (np.ndim(X) == 1 and len(X) and isinstance(X[0], dict)):
            X = np.array([[self.tool_db.index_of(r["tool"])] + [r[k] for k in PARAM_NAMES[1:]]
                          for r in ([X] if isinstance(X, dict) else X)], dtype=float)
        X = np.asarray(X, dtype=float)
        if X.size == 0:
            return X.reshape(0, 5)
        X = np.atleast_2d(X)
        if X.ndim != 2 or X.shape[1] != 5:
            raise ValueError(f"params: expected X of shape (n, 5), got {X.shape}")
        bad = ~np.isfinite(X)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            raise ValueError(f"params.{PARAM_NAMES[j]}: not a finite number in row {i}")
        lo = self.xl - np.r_[0.5, 1e-9 * np.maximum(1, np.abs(self.xl[1:]))]
        hi = self.xu + np.r_[0.5 - 1e-9, 1e-9 * np.maximum(1, np.abs(self.xu[1:]))]
        out = (X < lo) | (X >= hi) & (np.arange(5) == 0) | (X > hi) & (np.arange(5) > 0)
        if out.any():
            i, j = np.argwhere(out)[0]
            rng = (f"0 .. {self.n_tools - 1} (a tool index)" if j == 0
                   else f"[{self.xl[j]:g}, {self.xu[j]:g}]")
            where = f" (row {i})" if len(X) > 1 else ""
            raise ValueError(f"params.{PARAM_NAMES[j]}: {X[i, j]:g} outside {rng}{where}")
        return X

    def row(self, params) -> np.ndarray:
        """One parameter set by name -> X row (1, 5). ``tool`` is the tool ID here (as in
        ``--set tool=6``); the row holds its index. Range errors name ``params.<name>``."""
        if not isinstance(params, dict):
            return self.check(params)[:1]
        unknown = set(params) - set(PARAM_NAMES)
        if unknown:
            raise ValueError(f"params.{sorted(unknown)[0]}: unknown parameter "
                             f"(known: {', '.join(PARAM_NAMES)})")
        missing = [k for k in PARAM_NAMES if k not in params]
        if missing:
            raise ValueError(f"params.{missing[0]}: missing")
        x = [float(self.tool_db.index_of(params["tool"]))]
        x += [number(params[name], f"params.{name}") for name in PARAM_NAMES[1:]]
        return self.check(np.array([x]))

    def _raw_criteria(self, X) -> dict[str, np.ndarray]:
        """The analytic criteria of X (n, 5), with the simulated ones in place of the
        analytic scallop, gouge and machining error under ``criteria: simulated``."""
        crit = self.simulator.criteria(X)
        if self.simulated is not None and len(X):
            rows = []
            for x in X:
                sharp_rim = self.tool_db.cutter(int(round(x[0]))).sharp_rim
                rows.append(self.simulated.measure(self.simulator.cl_path(x), sharp_rim))
            for name in rows[0]:
                crit[name] = np.array([row[name] for row in rows])
        return crit

    def criteria(self, X) -> dict[str, np.ndarray]:
        """Every raw criterion per row of X (n, 5), plus ``objective`` (Eq. 9): dict of (n,)."""
        crit = self._raw_criteria(self.check(X))
        crit["objective"] = weighted_sum(crit, self.weights, self.norm_bounds) if self.objectives is None \
            else np.full(len(crit["cc_count"]), np.nan)
        return crit

    def evaluate_params(self, params) -> dict[str, float]:
        """Every criterion (floats) of ONE parameter set, given by name (tool = tool id)."""
        crit = self.criteria(self.row(params))
        return {k: float(v[0]) for k, v in crit.items()}

    def pattern(self, params):
        """The CC pattern (``simulator.CCPattern``) of one parameter set (mapping or row)."""
        return self.simulator.pattern(self.row(params)[0])

    @property
    def surface(self):
        """The part's design surface."""
        return self.simulator.surface

    @property
    def simulation_tolerance(self) -> float:
        """The tolerance band of a simulated cut's deviation map: the cut tolerance (mm)."""
        return self.simulator.tolerance

    def cl_path(self, params):
        """(CLPath, None): the toolpath of one parameter set as the machine runs it (no zones)."""
        return self.simulator.cl_path(self.row(params)[0]), None

    def artifacts(self, x) -> dict[str, bytes]:
        """Result files of one parameter set ``x: (5,)`` (a phenotype row, tool as its index):
        the CC pattern on the surface (Fountas Fig. 2 analog) and the APT CL program."""
        from .export.apt_write import apt_program
        from .figures import cc_pattern_png

        x = self.check(x)[0]
        tool = self.tool_db.tools[int(round(x[0]))]
        cc = self.simulator.pattern(x)
        settings = (f"tool {tool.id} ({tool.label()}), step-over {x[1]:.3f} %, lead {x[2]:.3f} deg, "
                    f"tilt {x[3]:.3f} deg, step {x[4]:.3f} mm")
        png = cc_pattern_png(self.simulator.surface, cc.points, cc.pass_index, title=settings,
                             color=cc.chord_error, color_label="chord error (mm)")
        apt = apt_program(cc.tool_tip, cc.axis, cc.pass_index, diameter=tool.diameter,
                          corner_radius=tool.corner_radius, feed_rate=self.simulator.feed_rate,
                          part="EVOPLAN TOOLPATH", comments=textwrap.wrap(settings, 66))
        return {"cc_pattern.png": png, "toolpath.apt": apt.encode()}

    def _evaluate(self, X, out, *args, **kwargs):
        crit = self._raw_criteria(self.check(X))
        if self.objectives is None:
            out["F"] = weighted_sum(crit, self.weights, self.norm_bounds)[:, None]
        else:
            norm = normalize(crit, self.norm_bounds)
            out["F"] = np.column_stack([norm[k] for k in self.objectives])
