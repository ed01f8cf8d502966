"""Speed of one plan per finishing strategy on Choi's whole surface, one core.

    python runs/bench/strategy_speed.py [--repeats 5] [--profile STRATEGY]

Choi's surface, 3-axis, one zone, the torus R 3.175 r 1, h_c 0.254 mm, step 1 mm. Per
strategy: the CPU seconds of the first plan of a new planner (the passes of the zone
built: for ``isoscallop``, every offset from the master pass) and of a plan whose step
differs (what depends only on the zoning, the tool and h_c is memoized, so a population
re-plans only what its genes change), each the median of ``--repeats``. Target: an
iso-scallop plan in at most 0.5 s. ``--profile NAME``: pyinstrument's top lines for that
strategy's first plan.
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from evoplan.problems.toolpath.geometry.spec import parse_surface  # noqa: E402
from evoplan.problems.toolpath.plan.planner import Planner  # noqa: E402
from evoplan.problems.toolpath.plan.strategies import STRATEGIES  # noqa: E402
from evoplan.problems.toolpath.spec import parse_tools  # noqa: E402
from evoplan.problems.toolpath.tools import CHOI_TOOLS  # noqa: E402

TORUS = 1  # CHOI_TOOLS[1]: R 3.175, r 1


def planner(surface, tools, name):
    return Planner(surface, tools, machine="3axis", spacing="scallop", h_c=0.254,
                   feed_angle=None, strategy=name, tolerance=0.01)


def genes(step):
    return {"tool": np.array([TORUS]), "step": np.array([step])}


def timed(fn) -> float:
    t = time.process_time()
    fn()
    return time.process_time() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--profile", choices=list(STRATEGIES), default=None)
    args = ap.parse_args()
    surface, tools = parse_surface("choi"), parse_tools(CHOI_TOOLS)
    planner(surface, tools, "parallel").plan(genes(1.0))  # imports and compiled kernels warm
    print(f"{'strategy':<14} {'first plan s':>12} {'re-plan s':>10} {'CC points':>10}")
    for name in STRATEGIES:
        first, again = [], []
        for _ in range(args.repeats):
            pl = planner(surface, tools, name)
            first.append(timed(lambda: pl.plan(genes(1.0))))
            again.append(timed(lambda: pl.plan(genes(1.5))))
        n = int(pl.plan(genes(1.0)).p.shape[0])
        print(f"{name:<14} {np.median(first):>12.3f} {np.median(again):>10.3f} {n:>10d}", flush=True)
    if args.profile:
        from pyinstrument import Profiler

        pl = planner(surface, tools, args.profile)
        with Profiler() as prof:
            pl.plan(genes(1.0))
        print(prof.output_text(unicode=False, color=False, show_all=False))


if __name__ == "__main__":
    main()
