"""The cut simulation as referee of 3-axis placement: a toroidal cutter put tangent at the
CC point (the analytic model's placement) cuts into Choi's surface elsewhere under its
footprint; the drop-cutter placement never does. Each CL point is stamped alone (one
section per point), so what is measured is the placement, not the moves between points."""

import dataclasses

import numpy as np

from evoplan.problems.toolpath.simulation import design_grid, simulate
from evoplan.problems.toolpath import ToolpathProblem
from tests.choi_zoning import choi_zoning


def test_cc_placement_gouges_and_drop_cutter_does_not():
    params = choi_zoning(fixed={"step": 3.0})
    grid = None
    gouge = {}
    for placement in ("cc", "drop"):
        pr = ToolpathProblem(**{**params, "placement": placement})
        path, _ = pr.cl_path(dict(tool=2, zones=1))
        grid = grid or design_grid(pr.surface, 0.4)
        alone = dataclasses.replace(path, section=np.arange(len(path)))
        gouge[placement] = simulate(alone, grid).metrics["gouge_max_mm"]
    assert gouge["cc"] > 0.01
    assert gouge["drop"] < 1e-6
