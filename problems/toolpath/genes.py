"""The decisions of the toolpath problem: its genes, their ranges, the fixed ones, the chromosome.

A configuration reads some of these genes (``Planner.gene_names``, in this order):

    name      meaning                                             default range
    tool      the cutter: a choice over the tool database          every tool
    stepover  % of the tool diameter, XY spacing of the planes    [20, 45]   (spacing stepover)
    lead      degrees, about the cross-feed axis                  [0, 5]     (5-axis)
    tilt      degrees, about the feed                             [0, 2]     (5-axis)
    step      maximum distance between CC points, mm              [5, 10]
    zones     the zoning method's gene: K (kmeans), k_lz (amas)    the method's
    strategy  the pass layout: a choice over the run file's list   every listed strategy

Each gene is either a **variable** of the chromosome, over ``ranges: {name: [lo, hi]}``, or
**fixed** by ``fixed: {name: value}`` (the tool by its id; a database of one tool fixes
the tool; a one-point range ``[v, v]`` is ``fixed: {name: v}``): a fixed gene is not in the
chromosome (``n_var``, ``xl``/``xu`` and the pymoo ``variables`` hold only the free genes)
and its value is inserted when a row is decoded. The phenotype row ``X`` holds the free
genes in the order above, the tool as its INDEX into the database.
"""

from __future__ import annotations

import itertools
from typing import Callable

import numpy as np
from pymoo.core.variable import Choice, Integer, Real

from .checks import number
from .spec.genes import DEFAULT_RANGES

__all__ = ["GENE_ORDER", "PARAM_NAMES", "DEFAULT_RANGES", "GeneSpace"]

GENE_ORDER = ("tool", "stepover", "lead", "tilt", "step")
PARAM_NAMES = GENE_ORDER


def _points_as_fixed(ranges, fixed):
    """(ranges, fixed) with every one-point range ``name: [v, v]`` moved to ``fixed`` (that
    gene then has one value: the plan is given, not searched)."""
    ranges, fixed = dict(ranges or {}), dict(fixed or {})
    for name, value in list(ranges.items()):
        try:
            lo, hi = (float(x) for x in value)
        except (TypeError, ValueError):
            continue
        if lo == hi and np.isfinite(lo):
            fixed[name] = ranges.pop(name)[0]
    return ranges, fixed


class GeneSpace:
    """The genes of one configuration: ranges, fixed values, chromosome and decoding.

    ``names``: the genes the plan reads (chromosome order); ``tools``: the tool database;
    ``ranges`` / ``fixed``: the specification's mappings, whose values it has checked
    (``spec/genes.py``: the continuous genes' values, the tool never a range, no gene both
    ranged and fixed); ``absent``: gene -> why this configuration has no such gene (for
    one-line errors); ``zone_gene``: the zoning method's gene (``Gene``) or None, with
    ``zone_range(value) -> (lo, hi)`` and ``zone_value(value)`` its checks. Checked here is
    what depends on the configuration: which genes exist, the zone gene's values, the tool
    ids, the strategy names.
    """

    def __init__(self, names, tools, ranges=None, fixed=None, absent=None, zone_gene=None,
                 zone_range: Callable | None = None, zone_value: Callable | None = None,
                 choices: dict | None = None):
        self.names, self.tools = tuple(names), tools
        self.integer = {zone_gene.name} if zone_gene is not None and zone_gene.integer else set()
        # categorical genes (``strategy``): name -> the option names, decoded as an index
        self.choices = {k: tuple(v) for k, v in (choices or {}).items() if k in self.names}
        self.integer |= set(self.choices)
        absent = dict(absent or {})
        known = (list(GENE_ORDER) + list(absent) + ([zone_gene.name] if zone_gene else [])
                 + list(self.choices))
        ranges, fixed = _points_as_fixed(ranges, fixed)
        self.fixed = self._fixed(fixed, absent, known, zone_gene, zone_value)
        if len(tools) == 1 and "tool" in self.names:
            self.fixed.setdefault("tool", 0.0)  # a database of one tool fixes the tool
        self.bounds = self._ranges(ranges, absent, known, zone_gene, zone_range)
        self.free = tuple(n for n in self.names if n not in self.fixed)
        self.xl = np.array([0.0 if n == "tool" else self.bounds[n][0] for n in self.free])
        self.xu = np.array([len(tools) - 1.0 if n == "tool" else self.bounds[n][1]
                            for n in self.free])
        self.variables = {n: self._variable(n) for n in self.free}

    # -- configuration ------------------------------------------------------------------
    def _unknown(self, name, key, absent, known):
        if name in absent:
            return ValueError(f"{key}: not a gene of this configuration ({absent[name]})")
        return ValueError(f"{key}: unknown gene (known: {', '.join(dict.fromkeys(known))})")

    def _fixed(self, spec, absent, known, zone_gene, zone_value) -> dict[str, float]:
        if spec is None:
            return {}
        out = {}
        for name, value in spec.items():
            key = f"fixed.{name}"
            if name not in self.names:
                raise self._unknown(name, key, absent, known)
            if name == "tool":
                try:
                    out[name] = float(self.tools.index_of(value))
                except (TypeError, ValueError):
                    raise ValueError(f"{key}: no tool with id {value!r} (ids: "
                                     f"{', '.join(map(str, self.tools.ids))})") from None
                continue
            if name in self.choices:
                if value not in self.choices[name]:
                    raise ValueError(f"{key}: expected one of {', '.join(self.choices[name])}, "
                                     f"got {value!r}")
                out[name] = float(self.choices[name].index(value))
                continue
            x = number(value, key)
            if zone_gene is not None and name == zone_gene.name:
                if zone_gene.integer and x != int(x):
                    raise ValueError(f"{key}: expected an integer, got {value!r}")
                zone_value(x, key)
            out[name] = x
        return out

    def _ranges(self, spec, absent, known, zone_gene, zone_range) -> dict:
        spec = dict(spec or {})
        for name in spec:
            key = f"ranges.{name}"
            if name not in self.names:
                raise self._unknown(name, key, absent, known)
            if name in self.choices:
                raise ValueError(f"{key}: {name} is a choice among "
                                 f"{', '.join(self.choices[name])} (fix one with fixed: "
                                 f"{{{name}: NAME}})")
        out = {}
        for name in self.names:
            if name == "tool" or name in self.fixed:
                continue
            if name in self.choices:
                out[name] = (0.0, len(self.choices[name]) - 1.0)
                continue
            if zone_gene is not None and name == zone_gene.name:
                out[name] = tuple(float(b) for b in zone_range(spec.get(name, zone_gene.bounds)))
                continue
            out[name] = tuple(spec[name]) if name in spec else DEFAULT_RANGES[name]
        return out

    def _variable(self, name):
        if name == "tool":
            return Choice(options=[int(i) for i in self.tools.ids])
        if name in self.choices:
            return Integer(bounds=(0, len(self.choices[name]) - 1))
        if name in self.integer:
            return Integer(bounds=tuple(int(b) for b in self.bounds[name]))
        return Real(bounds=self.bounds[name])

    @property
    def n_var(self) -> int:
        return len(self.free)

    # -- rows ---------------------------------------------------------------------------
    def check(self, X) -> np.ndarray:
        """X as (n, n_var) float; ``params.<name>: ...`` for a value out of range. Rows may
        be mappings name -> value (pymoo's mixed-variable form; the tool by its id)."""
        if isinstance(X, dict) or (np.ndim(X) == 1 and len(X) and isinstance(X[0], dict)):
            X = np.array([[self.tools.index_of(r["tool"]) if k == "tool" else r[k]
                           for k in self.free] for r in ([X] if isinstance(X, dict) else X)],
                         dtype=float)
        d = self.n_var
        X = np.asarray(X, dtype=float)
        if d == 0:  # every gene fixed: a row is empty, only the count of rows means anything
            return X.reshape(len(X) if X.ndim == 2 else 1, 0)
        if X.size == 0:
            return X.reshape(0, d)
        X = np.atleast_2d(X)
        if X.ndim != 2 or X.shape[1] != d:
            raise ValueError(f"params: expected X of shape (n, {d}) ({', '.join(self.free)}), "
                             f"got {X.shape}")
        bad = ~np.isfinite(X)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            raise ValueError(f"params.{self.free[j]}: not a finite number in row {i}")
        rounded = np.array([n == "tool" or n in self.integer for n in self.free])
        slack = np.where(rounded, 0.5, 1e-9 * np.maximum(1, np.maximum(abs(self.xl), abs(self.xu))))
        out = (X < self.xl - slack) | np.where(rounded, X >= self.xu + slack, X > self.xu + slack)
        if out.any():
            i, j = np.argwhere(out)[0]
            name = self.free[j]
            rng = (f"0 .. {len(self.tools) - 1} (a tool index)" if name == "tool"
                   else f"[{self.xl[j]:g}, {self.xu[j]:g}]")
            where = f" (row {i})" if len(X) > 1 else ""
            raise ValueError(f"params.{name}: {X[i, j]:g} outside {rng}{where}")
        return X

    def row(self, params) -> np.ndarray:
        """One decision set by name -> X row (1, n_var). ``tool`` is the tool ID here (as in
        ``--set tool=6``). A fixed gene may be given only with its fixed value."""
        if not isinstance(params, dict):
            return self.check(params)[:1]
        unknown = sorted(set(params) - set(self.names))
        if unknown:
            raise ValueError(f"params.{unknown[0]}: unknown parameter "
                             f"(known: {', '.join(self.names)})")
        for name, value in self.fixed.items():
            if name in params:
                given = (self.tools.index_of(params[name]) if name == "tool"
                         else self._choice(name, params[name]) if name in self.choices
                         else number(params[name], f"params.{name}"))
                if given != value:
                    shown = (self.tools.ids[int(value)] if name == "tool" else
                             self.choices[name][int(value)] if name in self.choices
                             else f"{value:g}")
                    raise ValueError(f"params.{name}: fixed at {shown} by the problem's config")
        missing = [k for k in self.free if k not in params]
        if missing:
            raise ValueError(f"params.{missing[0]}: missing")
        x = [float(self.tools.index_of(params[k])) if k == "tool" else
             self._choice(k, params[k]) if k in self.choices else number(params[k], f"params.{k}")
             for k in self.free]
        return self.check(np.array([x]))

    def _choice(self, name, value) -> float:
        """The index of a categorical gene's option given by name (or index)."""
        opts = self.choices[name]
        if value in opts:
            return float(opts.index(value))
        if isinstance(value, (int, float)) and not isinstance(value, bool) and value in range(len(opts)):
            return float(value)
        raise ValueError(f"params.{name}: expected one of {', '.join(opts)}, got {value!r}")

    def decode(self, X) -> dict[str, np.ndarray]:
        """Rows X (n, n_var) -> every gene as an (n,) array, fixed ones inserted; ``tool`` the
        index (int), an integer gene rounded."""
        X = np.asarray(X, float)
        X = X.reshape(-1, self.n_var) if self.n_var else X.reshape(len(X) if X.ndim == 2 else 1, 0)
        n = len(X)
        genes = {}
        for name in self.names:
            col = np.full(n, self.fixed[name]) if name in self.fixed \
                else X[:, self.free.index(name)]
            if name == "tool":
                col = np.clip(np.rint(col), 0, len(self.tools) - 1).astype(np.int64)
            elif name in self.choices:
                col = np.clip(np.rint(col), 0, len(self.choices[name]) - 1)
            elif name in self.integer:
                col = np.rint(col)
            genes[name] = col
        return genes

    def named(self, x) -> dict:
        """Every gene of one row by name (the tool by its id, fixed genes included)."""
        genes = self.decode(x)
        return {k: (int(self.tools.ids[int(v[0])]) if k == "tool" else
                    self.choices[k][int(v[0])] if k in self.choices else
                    int(v[0]) if k in self.integer else float(v[0])) for k, v in genes.items()}

    def design(self, n_random: int = 64, seed: int = 0) -> np.ndarray:
        """The fixed normalization design over the FREE genes (rows of X): every tool at the
        corners and the centre of the other free ranges, plus ``n_random`` seeded uniform
        rows over the whole box (with the five genes free, the design of Fountas' problem)."""
        free, lo, hi = self.free, self.xl, self.xu
        if not free:  # every gene fixed: one plan, one empty row
            return np.zeros((1, 0))
        t = free.index("tool") if "tool" in free else None
        cont = [j for j in range(len(free)) if j != t]
        if cont:
            corners = np.array(list(itertools.product(*[(lo[j], hi[j]) for j in cont])))
            corners = np.vstack([corners, (lo[cont] + hi[cont]) / 2])
        else:  # the tool is the only free gene: one row per tool
            corners = np.zeros((1, 0))
        tools = range(len(self.tools)) if t is not None else [None]
        grid = []
        for k in tools:
            rows = np.empty((len(corners), len(free)))
            rows[:, cont] = corners
            if t is not None:
                rows[:, t] = k
            grid.append(rows)
        rng = np.random.default_rng(seed)
        rand = lo + rng.random((n_random, len(free))) * (hi - lo)
        if t is not None:
            rand[:, t] = rng.integers(0, len(self.tools), n_random)
        return np.vstack(grid + [rand])
