"""Threads in the cut simulation: the Fountas VEGA set swept with 1 and N threads, interleaved.

    python runs/bench/simulation_threads.py [--grid 0.1] [--threads 2] [--repeat 3]

Prints the median wall seconds of each, the speed-up, and whether the residuals are equal bit
for bit. Not a test: measured figures (say whether the host was shared: other processes take
cores the threads would use).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from evoplan.problems.toolpath import ToolpathProblem
from evoplan.problems.toolpath.simulation import sweep_path
from evoplan.problems.toolpath.simulation.design import design_grid

VEGA = dict(tool=6, stepover=41.729, lead=2.957, tilt=0.027, step=6.338)
NORM = {"machining_error": [0, 0.5], "cc_count": [0, 1000]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=float, default=0.1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    pr = ToolpathProblem(normalization=NORM)
    path, _ = pr.cl_path(VEGA)
    grid = design_grid(pr.surface, args.grid)
    sweep_path(path, design_grid(pr.surface, 1.0), threads=args.threads)  # compile / load the cache
    times = {1: [], args.threads: []}
    cpu = {1: [], args.threads: []}
    out = {}
    for _ in range(args.repeat):
        for n in times:
            t0, c0 = time.perf_counter(), time.process_time()
            out[n] = sweep_path(path, grid, threads=n).values
            times[n].append(time.perf_counter() - t0)
            cpu[n].append(time.process_time() - c0)
    one, many = np.median(times[1]), np.median(times[args.threads])
    print(f"grid {args.grid} mm, {int(grid.inside.sum())} cells: 1 thread {one:.2f} s, "
          f"{args.threads} threads {many:.2f} s (wall medians of {args.repeat}): {one / many:.2f}x; "
          f"bit-identical: {np.array_equal(out[1], out[args.threads], equal_nan=True)}; CPU seconds "
          f"{np.median(cpu[1]):.2f} and {np.median(cpu[args.threads]):.2f} (CPU / wall with threads: "
          f"{np.median(cpu[args.threads]) / many:.2f}, the cores the threads actually got)")


if __name__ == "__main__":
    main()
