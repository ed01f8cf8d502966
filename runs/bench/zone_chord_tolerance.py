"""Chord tolerance of the zoning plans' CL paths: the gouge between drop-cutter CL points.

    python runs/bench/zone_chord_tolerance.py

Choi's surface with the zoning plans of ``runs/choi_zoning_vega.yaml`` (K-means, h_c 0.254
mm): tools 1 (ball R 3.175) and 2 (torus r 1) with K = 1 and 3 zones, CL points at most
1 mm apart, placed by the drop cutter (the one engine: ``Planner``). For each plan, without
the chord tolerance (the plan's CL points as placed, ``PlanBatch.cl_path``) and with 0.01 mm
(``Planner.cl_path``): the CL point count, the points the refinement added (CC-based and
drop-move checks), the largest remaining chord deviation the CC-based check reports, the
seconds to build the CL path (plan cached) and the largest gouge the cut simulation finds on
a 0.2 mm grid.
"""

from __future__ import annotations

import time

from evoplan.problems.toolpath.simulation import design_grid, simulate
from evoplan.problems.toolpath import CHOI_TOOLS, ToolpathProblem

#: Choi's zoned 3-axis configuration (runs/choi_zoning_vega.yaml's problem)
CHOI_ZONED = dict(surface="choi", tools=CHOI_TOOLS, machine="3axis", placement="drop",
                  spacing="scallop", h_c=0.254, feed_angle="optimized",
                  zoning={"method": "kmeans", "merge": False}, fixed={"step": 1.0},
                  weights={"eq4_total": 1.0}, normalization={"eq4_total": [0.0, 1.0]})


def main() -> None:
    problem = ToolpathProblem(**CHOI_ZONED)
    grid = design_grid(problem.surface, 0.2)
    print("tool zones tolerance  cl_points added deviation_mm path_s gouge_max_mm")
    for tool in (1, 2):
        for zones in (1, 3):
            params = {"tool": tool, "zones": zones}
            batch, genes = problem.plan(problem.row(params))  # plan and drop grids cached
            t = problem.tool_db.tools[int(genes["tool"][0])]
            for tolerance in (None, problem.tolerance):
                t0 = time.perf_counter()
                if tolerance is None:
                    batch, _ = problem.plan(problem.row(params))
                    path = batch.cl_path(0, t.cutter)
                else:
                    path = problem.planner.cl_path(genes)
                seconds = time.perf_counter() - t0
                gouge = simulate(path, grid).metrics["gouge_max_mm"]
                info = path.info
                dev = info.get("chord_deviation")
                added = info.get("chord_added", 0) + info.get("drop_added", 0)
                print(f"{tool:4d} {zones:5d} {tolerance!s:>9} {len(path):10d} {added:5d} "
                      f"{'-' if dev is None else f'{dev:.4f}':>12} {seconds:6.2f} {gouge:12.4f}",
                      flush=True)


if __name__ == "__main__":
    main()
