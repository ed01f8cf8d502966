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

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .screening import Screening, ScreeningSettings, at_least_one, settings_error
from .table import names

__all__ = ["SimulatedCriteria", "SimulationSettings", "SIMULATED"]

#: the criteria the cut simulation measures (the table's ``simulated`` flag)
SIMULATED = names(simulated=True)


class SimulationSettings(BaseModel):
    """A run file's ``simulation`` mapping (``criteria: simulated`` only): how the cut
    simulation measures a plan. Unknown keys are refused."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    grid_mm: float = Field(0.5, description="design grid spacing, mm (> 0)")
    rays: Literal["normal", "vertical"] = Field(
        "normal", description="normal: along the surface normal; vertical: along Z")
    allowance: float = Field(0.5, description="the finishing stock, mm (> 0): a cell no cutter "
                             "pose reached keeps that much")
    threads: int = Field(1, description="the sweep's tiles shared among that many threads "
                         "(same residual; evaluation.backend serial only)")
    screening: Annotated[ScreeningSettings | None, Field(
        description="only the plans the analytic criteria rank most promising are simulated "
                    "(criteria/screening.py); absent: every plan is")] = None

    @field_validator("grid_mm", "allowance", mode="before")
    @classmethod
    def _mm(cls, v):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v > 0):
            raise ValueError("must be a positive number of mm")
        return float(v)

    @field_validator("rays", mode="before")
    @classmethod
    def _rays(cls, v):
        if v not in ("normal", "vertical"):
            raise ValueError(f"expected normal or vertical, got {v!r}")
        return v

    @field_validator("threads", mode="before")
    @classmethod
    def _threads(cls, v):
        return at_least_one(v, " of threads")

    @classmethod
    def of(cls, options, key: str = "simulation") -> "SimulationSettings":
        """The settings of a plain mapping (None: the defaults); one-line ``ValueError``
        starting with ``key`` (``simulation.rays: expected normal or vertical, got 'x'``)."""
        if isinstance(options, cls):
            return options
        try:
            return cls.model_validate(dict(options or {}))
        except ValidationError as e:
            raise ValueError(settings_error(e, key, {(): cls, ("screening",): ScreeningSettings})) from None


class SimulatedCriteria:
    """The cut simulation as a criteria source for a problem whose rows make CL paths.

    ``settings``: a :class:`SimulationSettings` (a plain mapping is validated into one, its
    errors starting with ``key``): ``grid_mm``, ``rays`` (normal | vertical), ``allowance``,
    ``threads``, ``screening`` (``criteria/screening.py``: only the plans the analytic
    criteria rank most promising are simulated; absent: every plan is).
    """

    def __init__(self, surface, settings: SimulationSettings | dict | None = None,
                 key: str = "simulation"):
        self.settings = SimulationSettings.of(settings, key)
        self.grid_mm = self.settings.grid_mm
        self.allowance = self.settings.allowance
        self.threads = self.settings.threads
        self.screening = None
        if self.settings.screening is not None:
            self.screening = Screening(self.settings.screening)
        self.vertical = self.settings.rays == "vertical"
        self.surface = surface
        self._grid = None

    @property
    def grid(self):
        """The design grid (``simulation/design.py``), built at the first measure: the
        settings model is imported with the spec, the simulation only when it runs."""
        if self._grid is None:
            from ..simulation.design import design_grid

            self._grid = design_grid(self.surface, self.grid_mm)
        return self._grid

    def __getstate__(self):  # a worker rebuilds the grid rather than receive it
        return {**self.__dict__, "_grid": None}

    def measure(self, path, flat: bool) -> dict[str, float]:
        """The simulated criteria (``SIMULATED``) of one CL path (``flat``: a flat-end cutter)."""
        from ..simulation.metrics import residual_metrics
        from ..simulation.sweep import sweep_path

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
