"""Speed of the cut simulation: grid size, path length, the profile, and a population.

    python runs/bench/simulation_speed.py [--fine] [--method stamps] [--profile] [--population]

- The Fountas VEGA set (tool 6, 41.729 %, lead 2.957, tilt 0.027, step 6.338) at grids of
  0.2, 0.1 and 0.05 mm (and 0.02 mm with --fine): seconds to build the design grid and to
  sweep the path, wall and CPU of this process (numba runs on one core; BLAS is held to
  one thread here).
- --method: the sweep by moves (default) or by stamps (the reference, the former default).
- The work of the sweep by moves per cell on the part (0.1 mm grid): entries computed at CL
  points, moves searched, entries computed in the searches (numba code is opaque to the
  profiler, so the kernel counts its own work).
- Path length: the same tool and angles at step-overs 20, 30 and 45 % (0.1 mm grid).
- --profile: pyinstrument's top lines for one 0.1 mm simulation.
- --population: a population of 20 random parameter sets with ``criteria: simulated``
  (0.5 mm grid), serially and split over 2 worker processes (what the processes backend
  does with a population: one chunk per worker).
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from evoplan.problems.toolpath.problem import ToolpathProblem  # noqa: E402
from evoplan.problems.toolpath.simulation import design_grid  # noqa: E402
from evoplan.problems.toolpath.simulation import sweep_path as _sweep_path  # noqa: E402

VEGA = dict(tool=6, stepover=41.729, lead=2.957, tilt=0.027, step=6.338)
NORM = {"machining_error": [0, 0.5], "cc_count": [0, 1000]}


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fine", action="store_true", help="also the 0.02 mm grid")
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--population", action="store_true")
    ap.add_argument("--method", choices=("moves", "stamps"), default="moves")
    args = ap.parse_args()

    def sweep_path(p, g):
        return _sweep_path(p, g, method=args.method)

    pr = ToolpathProblem(normalization=NORM)
    path, _ = pr.cl_path(VEGA)
    sweep_path(path, design_grid(pr.surface, 1.0))  # compile / load the numba cache
    print(f"Fountas VEGA set: {len(path)} CL points, {path.feed_length():.0f} mm of feed moves")
    print("| grid (mm) | cells on the part | grid wall / CPU (s) | sweep wall / CPU (s) | total CPU (s) |")
    print("|---|---|---|---|---|")
    for h in (0.2, 0.1, 0.05) + ((0.02,) if args.fine else ()):
        grid, gw, gc = timed(lambda: design_grid(pr.surface, h))
        _, sw, sc = timed(lambda: sweep_path(path, grid))
        print(f"| {h} | {int(grid.inside.sum())} | {gw:.2f} / {gc:.2f} | {sw:.2f} / {sc:.2f} | "
              f"{gc + sc:.2f} |", flush=True)
    grid = design_grid(pr.surface, 0.1)
    if args.method == "moves":
        work = sweep_path(path, grid).work
        cells = int(grid.inside.sum())
        print("\nwork per cell (0.1 mm grid): " + ", ".join(
            f"{k} {v / cells:.2f}" for k, v in work.items()))
    print("\n| step-over (%) | CL points | feed length (mm) | sweep CPU (s), 0.1 mm grid |")
    print("|---|---|---|---|")
    for so in (20.0, 30.0, 45.0):
        p, _ = pr.cl_path({**VEGA, "stepover": so})
        _, _, sc = timed(lambda: sweep_path(p, grid))
        print(f"| {so:g} | {len(p)} | {p.feed_length():.0f} | {sc:.2f} |", flush=True)
    if args.profile:
        from pyinstrument import Profiler

        prof = Profiler()
        prof.start()
        sweep_path(path, design_grid(pr.surface, 0.1))
        prof.stop()
        print(prof.output_text(unicode=False, color=False, show_all=False)[:3000])
    if args.population:
        sim = ToolpathProblem(criteria="simulated", normalization=NORM)
        rng = np.random.default_rng(0)
        X = sim.xl + rng.random((20, 5)) * (sim.xu - sim.xl)
        sim.evaluate(X[:1])  # the design grid, once per process
        _, w, c = timed(lambda: sim.evaluate(X))
        print(f"\npopulation of 20, criteria: simulated (0.5 mm grid), serial: {w:.2f} s wall, "
              f"{c:.2f} s CPU ({w / 20 * 1000:.0f} ms per evaluation)")
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(2) as pool:
            list(pool.map(sim.evaluate, [X[:1], X[1:2]]))  # warm the workers
            _, w2, _ = timed(lambda: np.vstack(list(pool.map(sim.evaluate, np.array_split(X, 2)))))
        print(f"the same on 2 worker processes: {w2:.2f} s wall ({w / w2:.2f}x)")


if __name__ == "__main__":
    main()
