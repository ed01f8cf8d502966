"""Speed of the one toolpath engine (planner + analytic criteria), one core.

    python runs/bench/engine_speed.py [--batch 200] [--repeats 10] [--profile]

- Unzoned: Fountas' part, 5-axis, random parameter sets over the paper's ranges (nine
  tools, step-over 20-45 %, lead 0-5, tilt 0-2 deg, step 5-10 mm), whole batches:
  evaluations per second (target: at least 1000).
- Zoned: Choi's surface, 3-axis, K-means K = 1..6 with per-zone direction optimization,
  four R 3.175 tools, fixed step-over 40-90 % and step 0.5-2 mm: the first evaluation of a
  (K, tool) pair builds its layout (zoning, merging, directions: memoized), every later
  one reuses it. Printed: the layout cost, and milliseconds per memoized evaluation
  (target: at most 50 ms).
- --profile: pyinstrument's top lines for a memoized zoned population.
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from evoplan.problems.toolpath.criteria.analytic import analytic_criteria  # noqa: E402
from evoplan.problems.toolpath.geometry.spec import parse_surface  # noqa: E402
from evoplan.problems.toolpath.plan.planner import Planner  # noqa: E402
from evoplan.problems.toolpath.plan.zones import ZoningSpec  # noqa: E402
from evoplan.problems.toolpath.tools import parse_tools  # noqa: E402
from evoplan.problems.toolpath.zoned import CHOI_TOOLS  # noqa: E402

def evaluate(planner, surface, tools, genes, machine):
    batch = planner.plan(genes, place=False)
    return analytic_criteria(batch, surface, tools, genes, allowance=0.5, feed_rate=1000.0,
                             delta_l=40.0, machine=machine)


def cpu_times(planner, surface, tools, draw, machine, repeats) -> list[float]:
    """CPU seconds of ``repeats`` evaluations of fresh batches ``draw()``."""
    times = []
    for _ in range(repeats):
        genes = draw()
        t = time.process_time()
        evaluate(planner, surface, tools, genes, machine)
        times.append(time.process_time() - t)
    return times


def unzoned(args, rng):
    surface, tools = parse_surface("fountas"), parse_tools(None)
    planner = Planner(surface, tools, machine="5axis")
    n = args.batch

    def draw():
        return dict(tool=rng.integers(0, 9, n), stepover=rng.uniform(20, 45, n),
                    lead=rng.uniform(0, 5, n), tilt=rng.uniform(0, 2, n),
                    step=rng.uniform(5, 10, n))

    evaluate(planner, surface, tools, draw(), "5axis")  # warm-up
    times = cpu_times(planner, surface, tools, draw, "5axis", args.repeats)
    t = np.median(times)
    print(f"unzoned (Fountas, 5-axis): batch {n} x {args.repeats}: median {t * 1e3:.1f} ms CPU "
          f"per batch = {n / t:.0f} evaluations/s (best {n / min(times):.0f})")


def zoned(args, rng):
    surface, tools = parse_surface("choi"), parse_tools(CHOI_TOOLS)
    planner = Planner(surface, tools, machine="3axis", spacing="stepover", feed_angle=None,
                      h_c=0.254, zoning=ZoningSpec("kmeans"))
    planner.layouts.features, planner.layouts.samples  # noqa: B018 (built once per problem)
    n = 20

    def draw():
        return dict(tool=rng.integers(0, 4, n), stepover=rng.uniform(40, 90, n),
                    step=rng.uniform(0.5, 2.0, n), zones=rng.integers(1, 7, n))

    t = time.process_time()
    for k in range(1, 7):
        for tool in range(4):
            planner.layouts.get(k, tool)
    fill = time.process_time() - t
    print(f"zoned (Choi, 3-axis, K-means 1..6 x 4 tools): 24 layouts in {fill:.1f} s CPU "
          f"({fill / 24 * 1e3:.0f} ms per layout: zoning, merging, per-zone directions)")
    t = np.median(cpu_times(planner, surface, tools, draw, "3axis", args.repeats))
    print(f"zoned, memoized: population {n} x {args.repeats}: median {t * 1e3:.0f} ms CPU = "
          f"{t / n * 1e3:.1f} ms per evaluation")
    if args.profile:
        from pyinstrument import Profiler

        prof = Profiler()
        prof.start()
        for _ in range(5):
            evaluate(planner, surface, tools, draw(), "3axis")
        prof.stop()
        print(prof.output_text(unicode=False, color=False))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--profile", action="store_true")
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    unzoned(args, rng)
    zoned(args, rng)


if __name__ == "__main__":
    main()
