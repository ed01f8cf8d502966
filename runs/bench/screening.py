"""Multi-fidelity screening against full simulation at an equal budget of simulations.

The Fountas 5-axis problem (Eq. 14 surface, nine tools, feed along X, Eq. 9 = 0.5 machining
error + 0.5 CC points) with the machining error (and scallop, gouge) measured by the cut
simulation (``criteria: simulated``), optimized by the GA of ``runs/fountas_toolpath_ga.yaml``
(population 20, elitism 1, rank roulette, single-point crossover 0.9 and mutation 0.5, the
46-bit chromosome) for seeds 1..N, each arm at a budget of B simulations
(``termination.evaluations``: the engine charges a screened plan 0, a simulated one 1):

- ``full``: every new plan is simulated (``criteria: simulated``);
- ``ratio``, ``nearest``, ``offset``: ``simulation.screening`` (``criteria/screening.py``,
  fraction 0.25 and the elite) with that correction and ``error_quantile`` ``--error-quantile``
  (the fraction simulated only where predicted within that quantile of the recent prediction
  errors of the best); ``ratio_no_margin``: the ratio correction, the whole fraction.

``--error`` chooses Eq. 9's machining error: ``max``, the largest deviation (the paper's;
a coarse grid samples a cusp below its top, so it depends on where the cusps fall between
the grid's nodes), or ``mean``, the area mean of the deviation, which a coarse grid measures
well. The normalization bounds are given (largest deviation [0, 0.5] mm, mean [0, 0.25] mm,
CC points [0, 1000]), so no simulation is spent outside the budget on a normalization
design. ``--check-grid G`` simulates each run's best plan again on a G mm grid (outside the
budget). Reported: the final
simulated objective per arm (median, quartiles; Wilcoxon signed-rank over the seeds, which
pair the arms' initial populations), and the simulations the screened runs need for their
median best-so-far to reach the full simulation's final median.

    python runs/bench/screening.py [--seeds 10] [--budget 400] [--grid 1.0] [--fraction 0.25]
        [--error max|mean] [--error-quantile Q] [--check-grid G] [--arms full ratio]
        [--out PATH | --regenerate]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.stats import wilcoxon

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "reproduce"))
from outputs import add_report_options, resolve_report_paths, write_report  # noqa: E402

import evoplan  # noqa: E402
from evoplan.problems.toolpath.problem import ToolpathProblem  # noqa: E402

#: the machining-error criterion of Eq. 9 (``--error``) -> its normalization bounds (mm)
ERRORS = {"max": ("machining_error", [0, 0.5]), "mean": ("machining_error_mean", [0, 0.25])}
GA = dict(population=20, elitism=1, fitness={"normalize": "rank", "pressure": 2.0},
          selection={"kind": "roulette"}, crossover={"kind": "single_point", "rate": 0.9},
          mutation={"kind": "single_point", "rate": 0.5})
CODEC = dict(bits=10, variables={"stepover": {"bits": 11}, "lead": {"bits": 11},
                                 "tilt": {"bits": 10}, "step": {"bits": 10}})


def objective(error: str) -> dict:
    """The Eq. 9 weights and normalization bounds with the machining error ``error``."""
    name, bounds = ERRORS[error]
    return {"weights": {name: 0.5, "cc_count": 0.5},
            "normalization": {name: bounds, "cc_count": [0, 1000]}}


def one_run(arm: str, seed: int, budget: int, grid: float, fraction: float, error: str,
            check_grid: float | None = None, quantile: float | None = 0.5) -> dict:
    """One GA run of an arm: its best-so-far trace over simulations, counts and CPU time."""
    sim = {"grid_mm": grid}
    if arm != "full":
        correction, _, rule = arm.partition("_")
        sim["screening"] = {"fraction": fraction, "correction": correction,
                            "error_quantile": None if rule == "no_margin" else quantile}
    problem = ToolpathProblem(criteria="simulated", simulation=sim, **objective(error))
    states = []
    t0 = time.process_time()
    r = evoplan.minimize(problem, "ga", {"evaluations": budget}, seed=seed, callback=states.append,
                         **CODEC, **GA)
    cpu = time.process_time() - t0
    trace = np.full(r.evaluations + 1, np.inf)  # best after c simulations
    for c, value in states[-1].improvements:
        trace[c:] = np.minimum(trace[c:], value)
    screen = problem.simulated.screening
    plans = r.evaluations if screen is None else screen.simulations + screen.screened
    check = ToolpathProblem(criteria="simulated", simulation={"grid_mm": grid},
                            **objective(error)).evaluate_params(r.x)["objective"]
    fine = math.nan
    if check_grid is not None:  # the same best plan, measured on a finer grid
        fine = ToolpathProblem(criteria="simulated", simulation={"grid_mm": check_grid},
                               **objective(error)).evaluate_params(r.x)["objective"]
    return {"best": r.f, "trace": trace, "simulations": r.evaluations, "plans": plans,
            "generations": int(r.history["generation"].iloc[-1]), "cpu": cpu, "simulated_best": check,
            "fine": fine, "x": r.x}


def best_at(run: dict, c: int) -> float:
    t = run["trace"]
    return float(t[min(c, len(t) - 1)])


def needed(runs: list[dict], target: float, budget: int) -> int | None:
    """The fewest simulations at which the median best-so-far of ``runs`` is <= target."""
    for c in range(1, budget + 1):
        if np.median([best_at(r, c) for r in runs]) <= target:
            return c
    return None


def quartiles(x) -> str:
    q1, med, q3 = np.percentile(x, [25, 50, 75])
    return f"{med:.4f} ({q1:.4f} - {q3:.4f})"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--budget", type=int, default=400, help="simulations per run")
    ap.add_argument("--grid", type=float, default=1.0, help="simulation grid (mm)")
    ap.add_argument("--fraction", type=float, default=0.25)
    ap.add_argument("--error", choices=sorted(ERRORS), default="max",
                    help="Eq. 9's machining error: the largest deviation (the paper's) or the area mean")
    ap.add_argument("--check-grid", type=float, default=None,
                    help="also simulate each run's best on this finer grid (mm), not counted in the budget")
    ap.add_argument("--arms", nargs="+", choices=["full", "ratio", "nearest", "offset", "ratio_no_margin"],
                    default=["full", "ratio"])
    ap.add_argument("--error-quantile", type=float, default=0.5,
                    help="the screened arms' simulation.screening.error_quantile (the _no_margin arm: none)")
    add_report_options(ap)
    args = ap.parse_args()
    resolve_report_paths(args, __file__)
    seeds = range(1, args.seeds + 1)
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    runs = {}
    for arm in args.arms:
        runs[arm] = []
        for seed in seeds:
            runs[arm].append(one_run(arm, seed, args.budget, args.grid, args.fraction, args.error,
                                    args.check_grid, args.error_quantile))
            r = runs[arm][-1]
            print(f"{arm:8s} seed {seed:2d}: best {r['best']:.4f} after {r['simulations']} simulations, "
                  f"{r['plans']} plans, {r['generations']} generations, {r['cpu']:.1f} s CPU"
                  + ("" if args.check_grid is None else f"; at {args.check_grid:g} mm {r['fine']:.4f}")
                  + f"; plan {{{', '.join(f'{k}: {float(v):.4g}' for k, v in r['x'].items())}}}",
                  flush=True)
    wall = time.perf_counter() - t0
    assert all(r["best"] == r["simulated_best"] for rs in runs.values() for r in rs), "a best was not simulated"
    B = args.budget
    full = runs.get("full")
    target = float(np.median([r["best"] for r in full])) if full else None
    cmd = (f"python runs/bench/screening.py --seeds {args.seeds} --budget {B} --grid {args.grid:g}"
           f" --fraction {args.fraction:g} --error {args.error} --error-quantile {args.error_quantile:g}"
           f" --arms {' '.join(args.arms)}"
           + ("" if args.check_grid is None else f" --check-grid {args.check_grid:g}"))
    fine_head = "" if args.check_grid is None else f" the same bests simulated at {args.check_grid:g} mm |"
    lines = [f"# Screening vs full simulation: Fountas 5-axis, GA, {B} simulations a run, seeds 1-{args.seeds}", "",
             f"`{cmd}`", "",
             f"Cut simulation on a {args.grid:g} mm grid (rays along the normal); screening fraction "
             f"{args.fraction:g} (each plan of it simulated only where predicted within the "
             f"{args.error_quantile:g} quantile of the screen's recent prediction errors of the best; "
             "`_no_margin`: the whole fraction) plus the elite. Every run's best was checked against a fresh "
             "simulation of its plan: equal, bit for bit.", "",
             "| arm | final objective, median (quartiles) | best at B/4 | simulations used | plans evaluated | "
             "generations | simulations to reach the full median | CPU s a run |" + fine_head,
             "|---|---|---|---|---|---|---|---|" + ("---|" if fine_head else "")]
    for arm, rs in runs.items():
        reach = needed(rs, target, B) if target is not None else None
        lines.append(
            f"| {arm} | {quartiles([r['best'] for r in rs])} | "
            f"{np.median([best_at(r, B // 4) for r in rs]):.4f} | {np.median([r['simulations'] for r in rs]):.0f} "
            f"({min(r['simulations'] for r in rs)} - {max(r['simulations'] for r in rs)}) | "
            f"{np.median([r['plans'] for r in rs]):.0f} | "
            f"{np.median([r['generations'] for r in rs]):.0f} | "
            f"{'-' if reach is None else reach} | {np.median([r['cpu'] for r in rs]):.1f} |"
            + (f" {quartiles([r['fine'] for r in rs])} |" if fine_head else ""))
    lines.append("")
    if full:
        for arm, rs in runs.items():
            if arm == "full":
                continue
            a, b = [r["best"] for r in full], [r["best"] for r in rs]
            quarter = [best_at(r, B // 4) for r in rs]
            p_eq = wilcoxon(a, b).pvalue if any(x != y for x, y in zip(a, b)) else 1.0
            p_q = wilcoxon(a, quarter).pvalue if any(x != y for x, y in zip(a, quarter)) else 1.0
            reach = needed(rs, target, B)
            ratio = "not reached" if reach is None else f"{B / reach:.1f}x fewer simulations"
            per_seed = [next((c for c in range(1, B + 1) if best_at(r, c) <= target), None) for r in rs]
            lines += [f"- **{arm}** vs full at a budget of {B} simulations each (a run stops earlier when "
                      f"its cache stalls: no new simulation in 100 generations): Wilcoxon signed-rank p = {p_eq:.3g} "
                      f"(screening better in {sum(y < x for x, y in zip(a, b))} of {len(a)} seeds); "
                      f"{arm} after {B // 4} simulations vs full after {B}: p = {p_q:.3g} "
                      f"(better or equal in {sum(y <= x for x, y in zip(a, quarter))} of {len(a)}).",
                      f"- The full simulation's final median {target:.4f} is reached by the median of the "
                      f"{arm} runs after {reach if reach else '-'} simulations: {ratio} (target: >= 4x). "
                      f"Per seed: {', '.join('-' if c is None else str(c) for c in per_seed)}."]
    lines += ["", f"Total wall {wall:.0f} s; load average {load0:.1f} at the start, "
              f"{os.getloadavg()[0]:.1f} at the end (2 cores, shared).", ""]
    write_report(args, "\n".join(lines))


if __name__ == "__main__":
    main()
