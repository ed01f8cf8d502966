"""The cut simulation: what a toolpath really leaves on the part, measured on a fine grid.

``design.py`` samples the design surface on square cells (one ray per cell, along the
normal or vertical); ``kernel.py`` holds the numba kernels (ray entry into the exact
flat / toroidal / ball-end cutter with its shank, the sweep between CL points);
``sweep.py`` prepares a :class:`~..clpath.CLPath` for them; ``metrics.py`` turns the
residual into scallop / gouge / uncut figures; ``figures.py`` draws the deviation map and
histogram. :func:`simulate` ties them together.
"""

from .design import DesignGrid, analytic_grid, design_grid, grid_bytes
from .metrics import KEYS, cell_labels, residual_metrics, zone_metrics
from .run import Simulation, simulate
from .sweep import Residual, sweep_path

__all__ = ["DesignGrid", "analytic_grid", "design_grid", "grid_bytes", "KEYS", "cell_labels",
           "residual_metrics", "zone_metrics", "Simulation", "simulate", "Residual", "sweep_path"]
