"""Speed-up of a multi-objective run on the processes and Dask backends (a measurement, not a test).

The shipped NSGA-II run ``runs/fountas_toolpath_pareto.yaml`` (machining error and machining
time of 5-axis finishing of Fountas' surface, population 20) is run by ``evoplan run`` with the
serial evaluator, then on ``--backend`` with ``--workers`` workers, ``--repeat`` times each,
alternating; the command's wall time is taken (start-up and the pool included) and, from each
run's ``history.csv``, the seconds of the generations themselves and the median seconds of a
generation after the first (the first carries the pool's start: its workers' imports and
compiled kernels). Every parallel run's ``pareto.csv`` must equal the serial one's.
``--population`` sets a larger population (more evaluations a generation to share out); the
plans cost what they cost, so the speed-up shows what the pool's overhead leaves of the
evaluation time.

    python runs/bench/multiobjective_parallel.py [--backend processes|dask] [--workers 2]
        [--population 20] [--generations 10] [--repeat 2]

Writes its run folders under a temporary directory (removed at the end).
"""

from __future__ import annotations

import argparse
import filecmp
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

RUN_FILE = Path(__file__).resolve().parents[1] / "fountas_toolpath_pareto.yaml"


def timed_run(out: Path, settings: list[str]) -> tuple[float, float, float]:
    """(wall seconds of the command, seconds of its generations from history.csv, median
    seconds of a generation after the first)."""
    sets = [arg for s in settings for arg in ("--set", s)]
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "evoplan", "run", str(RUN_FILE), "--out", str(out), "--quiet", *sets],
                   check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    seconds = pd.read_csv(out / "history.csv")["seconds"]
    return wall, float(seconds.iloc[-1]), float(seconds.diff().iloc[1:].median())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--backend", choices=("processes", "dask"), default="processes")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--population", type=int, default=20)
    ap.add_argument("--generations", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    common = [f"algorithm.pop_size={args.population}", f"termination.generations={args.generations}"]
    parallel = [f"evaluation.backend={args.backend}", f"evaluation.workers={args.workers}"]
    times: dict[str, list[tuple[float, float, float]]] = {"serial": [], args.backend: []}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.repeat):
            times["serial"].append(timed_run(Path(tmp) / f"serial{r}", common))
            times[args.backend].append(timed_run(Path(tmp) / f"parallel{r}", common + parallel))
        same = all(filecmp.cmp(Path(tmp) / "serial0" / "pareto.csv", Path(tmp) / f"parallel{r}" / "pareto.csv",
                               shallow=False) for r in range(args.repeat))
    wall, gens, step = ({k: np.median([t[i] for t in v]) for k, v in times.items()} for i in range(3))
    print(f"NSGA-II, population {args.population}, {args.generations} generations, median of {args.repeat}:")
    for k in times:
        print(f"  {k:10s} command {wall[k]:6.2f} s wall, generations {gens[k]:6.2f} s, "
              f"a later generation {step[k]:.3f} s")
    print(f"  speed-up {args.backend} x{args.workers}: command {wall['serial'] / wall[args.backend]:.2f}x, "
          f"generations {gens['serial'] / gens[args.backend]:.2f}x, a later generation "
          f"{step['serial'] / step[args.backend]:.2f}x; same pareto.csv: {same}")


if __name__ == "__main__":
    main()
