"""Simulated criteria: the toolpath problem's scallop, gouge and machining error measured by
the cut simulation instead of the analytic model, under the same names.

For each parameter set the plan's CL path is swept over a design grid built once per
problem (``grid_mm``, default 0.5 mm), and

- ``scallop_max`` / ``scallop_mean``: the simulated material left (max, area mean);
- ``gouge_max``: the deepest simulated cut below the surface;
- ``undercut_max``: the simulated material left for flat-end tools (0 for the others);
- ``machining_error``: the largest deviation either way, max(scallop, gouge); it already
  holds the chord error, which the machine's straight moves leave in the part;
- ``machining_error_mean``: the area mean of the absolute deviation.

The other criteria (CC points, chord error, lengths, time) are properties of the plan and
stay as they are. The simulation costs far more than the analytic model: evaluate
populations on the processes or Dask backend (each evaluation runs on one core).
"""

from __future__ import annotations

import numpy as np

from ..simulation.design import DesignGrid, design_grid
from ..simulation.metrics import residual_metrics
from ..simulation.sweep import sweep_path
from .table import names

__all__ = ["SimulatedCriteria", "SIMULATED"]

#: the criteria the cut simulation measures (the table's ``simulated`` flag)
SIMULATED = names(simulated=True)


class SimulatedCriteria:
    """The cut simulation as a criteria source for a problem whose rows make CL paths.

    ``options``: ``grid_mm`` (0.5), ``rays`` (normal | vertical), ``allowance`` (0.5 mm),
    ``threads`` (1: the sweep's tiles shared among that many threads, same residual),
    ``screening`` (a mapping, ``criteria/screening.py``: only the plans the analytic criteria
    rank most promising are simulated; absent: every plan is).
    """

    KEYS = {"grid_mm", "rays", "allowance", "threads", "screening"}

    def __init__(self, surface, options: dict | None = None, key: str = "simulation"):
        options = dict(options or {})
        unknown = set(options) - self.KEYS
        if unknown:
            raise ValueError(f"{key}.{sorted(unknown)[0]}: unknown setting "
                             f"(known: {', '.join(sorted(self.KEYS))})")
        self.grid_mm = float(options.get("grid_mm", 0.5))
        self.allowance = float(options.get("allowance", 0.5))
        rays = options.get("rays", "normal")
        if rays not in ("normal", "vertical"):
            raise ValueError(f"{key}.rays: expected normal or vertical, got {rays!r}")
        for name in ("grid_mm", "allowance"):
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f"{key}.{name}: must be a positive number of mm")
        threads = options.get("threads", 1)
        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
            raise ValueError(f"{key}.threads: expected a whole number of threads >= 1, got {threads!r}")
        self.threads = threads
        self.screening = None
        if options.get("screening") is not None:
            from .screening import Screening

            self.screening = Screening(options["screening"], f"{key}.screening")
        self.vertical = rays == "vertical"
        self.surface = surface
        self._grid: DesignGrid | None = None

    @property
    def grid(self) -> DesignGrid:
        if self._grid is None:
            self._grid = design_grid(self.surface, self.grid_mm)
        return self._grid

    def __getstate__(self):  # a worker rebuilds the grid rather than receive it
        return {**self.__dict__, "_grid": None}

    def measure(self, path, flat: bool) -> dict[str, float]:
        """The simulated criteria (``SIMULATED``) of one CL path (``flat``: a flat-end cutter)."""
        grid = self.grid
        res = sweep_path(path, grid, vertical=self.vertical, threads=self.threads).values
        m = residual_metrics(grid, res, self.allowance)
        dev = np.abs(np.clip(res[grid.inside], -np.inf, self.allowance))
        area = grid.cell_area()[grid.inside]
        values = {
            "scallop_max": m["scallop_max_mm"], "scallop_mean": m["scallop_mean_mm"],
            "gouge_max": m["gouge_max_mm"],
            "undercut_max": m["scallop_max_mm"] if flat else 0.0,
            "machining_error": max(m["scallop_max_mm"], m["gouge_max_mm"]),
            "machining_error_mean": float((dev * area).sum() / area.sum()),
        }
        return {name: values[name] for name in SIMULATED}
