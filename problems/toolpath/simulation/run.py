"""One simulation: a CL path over a surface (or a ready design grid) -> residual + figures."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..clpath import CLPath
from ..geometry.surface import Surface
from .design import DesignGrid, design_grid
from .metrics import cell_labels, residual_metrics, zone_metrics
from .sweep import Residual, sweep_path

__all__ = ["Simulation", "simulate", "check_on_part"]


@dataclass
class Simulation:
    """The grid, the residual, the figures (``metrics``) and per-zone figures."""

    grid: DesignGrid
    residual: Residual
    metrics: dict
    zones: list[dict] = field(default_factory=list)
    labels: np.ndarray | None = None

    def summary(self, path: CLPath, seconds: float) -> dict:
        """The ``simulation.json`` record."""
        return {**self.metrics, "grid_mm": self.grid.h, "cl_points": len(path),
                "rays": "vertical" if self.residual.vertical else "normal",
                "cutter": path.cutter.to_dict(),
                "cells": int(self.grid.inside.sum()), "seconds": seconds,
                "sweep_seconds": self.residual.seconds, "zones": self.zones}


def check_on_part(path: CLPath, grid: DesignGrid) -> None:
    """ValueError unless some CL point lies over the part's footprint (within the radius)."""
    if len(path) == 0:
        raise ValueError("toolpath: the path is empty")
    ys, xs = np.nonzero(grid.inside)
    lo = np.array([grid.x0 + xs.min() * grid.h, grid.y0 + ys.min() * grid.h]) - path.radius
    hi = np.array([grid.x0 + xs.max() * grid.h, grid.y0 + ys.max() * grid.h]) + path.radius
    on = ((path.tip[:, :2] >= lo) & (path.tip[:, :2] <= hi)).all(axis=1)
    if not on.any():
        raise ValueError(f"toolpath: no CL point lies over the surface's footprint "
                         f"x [{lo[0]:.1f}, {hi[0]:.1f}], y [{lo[1]:.1f}, {hi[1]:.1f}] mm")


def simulate(path: CLPath, surface: Surface | DesignGrid, grid_mm: float = 0.1, *,
             vertical: bool = False, allowance: float = 0.5, gouge_threshold: float = 1e-3,
             mesh_labels: np.ndarray | None = None, max_bytes: float | None = None,
             **sweep_options) -> Simulation:
    """Cut ``path`` over ``surface`` on a ``grid_mm`` grid and measure what is left.

    ``mesh_labels``: zone labels on the (u, v) mesh of a zoned plan, for per-zone figures.
    """
    grid = surface if isinstance(surface, DesignGrid) else design_grid(
        surface, grid_mm, max_bytes=max_bytes)
    check_on_part(path, grid)
    res = sweep_path(path, grid, vertical=vertical, **sweep_options)
    metrics = residual_metrics(grid, res.values, allowance, gouge_threshold)
    labels, zones = None, []
    if mesh_labels is not None and grid.u is not None:
        labels = cell_labels(grid, np.asarray(mesh_labels))
        zones = zone_metrics(grid, res.values, labels, allowance, gouge_threshold)
    return Simulation(grid, res, metrics, zones, labels)
