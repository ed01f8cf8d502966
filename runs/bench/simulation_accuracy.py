"""Accuracy of the default cut simulation against a dense reference sweep, on Fountas' part.

    python runs/bench/simulation_accuracy.py [--grid 0.2]

For a toroidal D16 r3 (the VEGA set: tool 6, 41.729 %, lead 2.957, tilt 0.027, step
6.338), a ball-end D12 (tool 8) and a flat-end D8 (tool 1) on the same angles and step,
the residual of the default sweep (``sweep_path(path, grid)``, by moves) is compared on
every cell with the reference: the sweep by stamps with poses 0.05 mm apart, each cell's
six best stretches refined by golden-section search to 2e-4 mm of travel. The reference
assumes nothing about the entry along a move (no convexity), so it checks the default's
bounds; its own error is about the golden-section tolerance. Printed: the largest and the
99.9th percentile of |default - reference| over the cells both reach, the share of cells
more than 1e-4 mm apart, the cells reached by one and not the other, both CPU times, and
the largest difference of the former default (the stamp sweep at its default spacing).
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from evoplan.problems.toolpath.problem import ToolpathProblem  # noqa: E402
from evoplan.problems.toolpath.simulation import design_grid, sweep_path  # noqa: E402

ANGLES = dict(stepover=41.729, lead=2.957, tilt=0.027, step=6.338)
CUTTERS = (("torus D16 r3", 6), ("ball D12", 8), ("flat D8", 1))
REFERENCE = dict(method="stamps", pose_step=0.05, tol=2e-4, n_slots=6)


def cpu(fn):
    c = time.process_time()
    out = fn()
    return out, time.process_time() - c


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=float, default=0.2, help="cell size (mm)")
    args = ap.parse_args()
    pr = ToolpathProblem()
    grid = design_grid(pr.surface, args.grid)
    print(f"Fountas part, {args.grid} mm grid, {int(grid.inside.sum())} cells; reference: "
          f"{REFERENCE}")
    print("| cutter | CL points | max diff (mm) | p99.9 diff (mm) | cells > 1e-4 mm | "
          "reached by one only | default CPU (s) | reference CPU (s) | stamps at defaults: max diff (mm) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, tool in CUTTERS:
        path, _ = pr.cl_path({"tool": tool, **ANGLES})
        sweep_path(path, design_grid(pr.surface, 2.0))  # compile / load the numba caches
        sweep_path(path, design_grid(pr.surface, 2.0), **REFERENCE)
        got, c_got = cpu(lambda: sweep_path(path, grid).values)
        ref, c_ref = cpu(lambda: sweep_path(path, grid, **REFERENCE).values)
        old = sweep_path(path, grid, method="stamps").values
        both = np.isfinite(got) & np.isfinite(ref)
        one = int((np.isfinite(got) != np.isfinite(ref)).sum())
        diff = np.abs(got[both] - ref[both])
        ok = np.isfinite(old) & np.isfinite(ref)
        old_max = np.abs(old[ok] - ref[ok]).max()
        print(f"| {name} | {len(path)} | {diff.max():.2e} | {np.quantile(diff, 0.999):.2e} | "
              f"{(diff > 1e-4).mean() * 100:.3f} % | {one} | {c_got:.2f} | {c_ref:.2f} | "
              f"{old_max:.2e} |",
              flush=True)


if __name__ == "__main__":
    main()
