"""Speed of the one toolpath engine (planner + analytic criteria), one core.

    python runs/bench/engine_speed.py [--batch 200] [--repeats 10] [--profile] [--compare]

- Unzoned: Fountas' part, 5-axis, random parameter sets over the paper's ranges (nine
  tools, step-over 20-45 %, lead 0-5, tilt 0-2 deg, step 5-10 mm), whole batches:
  evaluations per second (target: at least 1000).
- Zoned: Choi's surface, 3-axis, K-means K = 1..6 with per-zone direction optimization,
  four R 3.175 tools, fixed step-over 40-90 % and step 0.5-2 mm: the first evaluation of a
  (K, tool) pair builds its layout (zoning, merging, directions: memoized), every later
  one reuses it. Printed: the layout cost, and milliseconds per memoized evaluation
  (target: at most 50 ms).
- The numpy-floor GA of ``floor.py`` before and after, as this host's speed at the time.
- --profile: pyinstrument's top lines for a memoized zoned population.
- --compare: the compiled passes (``geometry/rows.interp_rows``, the torus family's
  ``cc_to_tip``) against their numpy references (``interp_rows_numpy``,
  ``Cutter.cc_to_tip``) on the same batches, interleaved in this process: the ratio, and
  every criterion checked equal bit for bit.
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
from evoplan.problems.toolpath.spec import parse_tools  # noqa: E402
from evoplan.problems.toolpath.tools import CHOI_TOOLS  # noqa: E402

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


def _use_numpy(numpy: bool) -> None:
    """Swap the compiled passes for their numpy references (``--compare``) or back."""
    from evoplan.problems.toolpath.criteria import scallop
    from evoplan.problems.toolpath.cutters import shapes
    from evoplan.problems.toolpath.cutters.base import Cutter
    from evoplan.problems.toolpath.geometry import rows

    compiled = _use_numpy.__dict__.setdefault("compiled", (rows.interp_rows, shapes._Revolved.cc_to_tip))
    interp, tip = (rows.interp_rows_numpy, Cutter.cc_to_tip) if numpy else compiled
    scallop.interp_rows = interp
    shapes._Revolved.cc_to_tip = tip


def compare(args) -> None:
    """Interleaved A/B of the numpy references and the compiled passes on the same batches."""
    cases = []
    surface, tools = parse_surface("fountas"), parse_tools(None)
    planner = Planner(surface, tools, machine="5axis")
    n = args.batch
    cases.append(("unzoned (Fountas, 5-axis), evaluations/s", planner, surface, tools, "5axis", lambda rng: dict(
        tool=rng.integers(0, 9, n), stepover=rng.uniform(20, 45, n), lead=rng.uniform(0, 5, n),
        tilt=rng.uniform(0, 2, n), step=rng.uniform(5, 10, n)), n))
    surface, tools = parse_surface("choi"), parse_tools(CHOI_TOOLS)
    planner = Planner(surface, tools, machine="3axis", spacing="stepover", feed_angle=None,
                      h_c=0.254, zoning=ZoningSpec("kmeans"))
    for k in range(1, 7):
        for tool in range(2):
            planner.layouts.get(k, tool)
    cases.append(("zoned memoized (Choi, K 1..6, 2 tools), evaluations/s", planner, surface, tools, "3axis",
                  lambda rng: dict(tool=rng.integers(0, 2, 20), stepover=rng.uniform(40, 90, 20),
                                   step=rng.uniform(0.5, 2.0, 20), zones=rng.integers(1, 7, 20)), 20))
    for label, planner, surface, tools, machine, draw, size in cases:
        times = {True: [], False: []}
        for numpy in (True, False):  # warm-up (compilation)
            _use_numpy(numpy)
            evaluate(planner, surface, tools, draw(np.random.default_rng(10 ** 6)), machine)
        for rep in range(args.repeats):
            out = {}
            for numpy in (True, False):
                _use_numpy(numpy)
                genes = draw(np.random.default_rng(rep))
                t = time.process_time()
                out[numpy] = evaluate(planner, surface, tools, genes, machine)
                times[numpy].append(time.process_time() - t)
            assert all(np.array_equal(out[True][k], out[False][k], equal_nan=True) for k in out[True]), label
        ref, new = np.median(times[True]), np.median(times[False])
        print(f"{label}: numpy references {size / ref:.0f}, compiled {size / new:.0f}: {ref / new:.2f}x "
              f"({args.repeats} interleaved repeats, every criterion bit-identical; load {os.getloadavg()[0]:.1f})")
    _use_numpy(False)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--compare", action="store_true", help="compiled passes vs their numpy references")
    args = ap.parse_args()
    if args.compare:
        compare(args)
        return
    rng = np.random.default_rng(args.seed)
    before = floor_seconds()
    unzoned(args, rng)
    zoned(args, rng)
    print(f"numpy-floor GA (floor.py, pop 200 x 200), CPU s, before / after: {before:.4f} / {floor_seconds():.4f}")


def floor_seconds(rounds: int = 5) -> float:
    """The numpy floor's CPU seconds in this process, median of ``rounds`` (how fast this
    host is now: machines of this kind differ by up to 1.6x)."""
    from floor import floor_ga  # noqa: PLC0415 - the sibling benchmark (runs/bench/floor.py)

    times = []
    for seed in range(rounds):
        t0 = time.process_time()
        floor_ga(200, 200, seed)
        times.append(time.process_time() - t0)
    return float(np.median(times))


if __name__ == "__main__":
    main()
