"""Benchmark: evaluations per second of the toolpath problem on Fountas' surface.

Whole batches of random parameter sets drawn uniformly over the paper's ranges (all nine
tools, step-over 20-45 %, lead 0-5 deg, tilt 0-2 deg, step 5-10 mm), one process.
Run:  python runs/bench/toolpath_speed.py [--batch 200] [--repeats 10] [--seed 0]
Pin it to one core for the reference figure:  taskset -c 0 python runs/bench/toolpath_speed.py
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from evoplan.problems.toolpath import ToolpathProblem  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    t0 = time.perf_counter()
    problem = ToolpathProblem()
    t_build = time.perf_counter() - t0
    rng = np.random.default_rng(args.seed)
    lo, hi = problem.xl, problem.xu
    batches = []
    for _ in range(args.repeats):
        X = lo + rng.random((args.batch, problem.n_var)) * (hi - lo)
        X[:, 0] = rng.integers(0, problem.n_tools, args.batch)
        batches.append(X)
    problem.evaluate(batches[0])  # warm-up
    times = []
    for X in batches:
        t = time.perf_counter()
        problem.evaluate(X)
        times.append(time.perf_counter() - t)
    times = np.array(times)
    print(f"construction (tables + normalization sample): {t_build:.2f} s")
    print(f"batch {args.batch} x {args.repeats}: median {np.median(times) * 1e3:.1f} ms/batch, "
          f"{args.batch / np.median(times):.0f} evals/s (best {args.batch / times.min():.0f}, "
          f"worst {args.batch / times.max():.0f})")


if __name__ == "__main__":
    main()
