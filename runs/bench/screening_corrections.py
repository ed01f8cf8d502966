"""How well each screening correction predicts the simulated objective, held out one at a time.

Random plans of the Fountas 5-axis problem (``runs/bench/screening.py``'s objective, the
machining error chosen by ``--error``) are planned, evaluated analytically and simulated
once. For each correction of ``criteria/screening.py`` and each plan, a fresh screen learns
every other plan's pair and predicts that plan's simulated objective. Printed per
correction: the RMS prediction error over all plans and over the best 30 % by the
simulation (the plans an optimizer's screen must tell apart), and Spearman's rank
correlation of prediction and simulation among those best. ``--check-grid G`` simulates the
same plans on a G mm grid too and prints how far each machining error (the largest
deviation, the area mean) of the coarse grid is from the fine one's.

    python runs/bench/screening_corrections.py [--plans 150] [--grid 1.0] [--error mean] [--seed 7]
        [--check-grid G]
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from scipy.stats import spearmanr  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from screening import ERRORS, objective  # noqa: E402

from evoplan.problems.toolpath.criteria.objective import weighted_sum  # noqa: E402
from evoplan.problems.toolpath.criteria.screening import CORRECTIONS, Screening  # noqa: E402
from evoplan.problems.toolpath.problem import ToolpathProblem  # noqa: E402


def held_out(problem, X, crit, measured, correction: str) -> np.ndarray:
    """The prediction of each row's simulated objective by a screen that learned all others."""
    n = len(X)
    out = np.empty(n)
    for i in range(n):
        rest = np.flatnonzero(np.arange(n) != i)
        screen = Screening({"correction": correction})
        screen.learn(problem, X[rest], {k: v[rest] for k, v in crit.items()},
                     {k: v[rest] for k, v in measured.items()})
        out[i] = screen.predicted(problem, X[i:i + 1], {k: v[i:i + 1] for k, v in crit.items()})[0]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plans", type=int, default=150)
    ap.add_argument("--grid", type=float, default=1.0, help="simulation grid (mm)")
    ap.add_argument("--error", choices=sorted(ERRORS), default="mean")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--check-grid", type=float, default=None, help="a finer grid to compare with (mm)")
    args = ap.parse_args()
    problem = ToolpathProblem(criteria="simulated", simulation={"grid_mm": args.grid}, **objective(args.error))
    rng = np.random.default_rng(args.seed)
    X = rng.uniform(problem.xl, problem.xu, size=(args.plans, len(problem.xl)))
    tool = list(problem.genes.free).index("tool")
    X[:, tool] = np.rint(X[:, tool])
    t0 = time.process_time()
    crit, genes = problem.analytic(X)
    measured = problem.simulate_rows(genes, range(len(X)))
    f = weighted_sum(crit | measured, problem.weights, problem.norm_bounds)
    ok = np.isfinite(f)
    best = ok & (f <= np.percentile(f[ok], 30))
    print(f"{args.plans} random plans, {args.grid:g} mm grid, Eq. 9 with the {args.error} machining error "
          f"({ERRORS[args.error][0]}); {time.process_time() - t0:.1f} s CPU to plan and simulate them")
    print("| correction | RMS error, all | RMS error, best 30 % | Spearman, best 30 % |")
    print("|---|---|---|---|")
    for correction in CORRECTIONS:
        p = held_out(problem, X, crit, measured, correction)
        err = (p - f)[ok]
        print(f"| {correction} | {np.sqrt(np.mean(err ** 2)):.4f} | {np.sqrt(np.mean((p - f)[best] ** 2)):.4f} | "
              f"{spearmanr(p[best], f[best]).statistic:.3f} |")
    if args.check_grid is not None:
        fine = ToolpathProblem(criteria="simulated", simulation={"grid_mm": args.check_grid},
                               **objective(args.error)).simulate_rows(genes, range(len(X)))
        print(f"\nthe same plans on a {args.check_grid:g} mm grid: the {args.grid:g} mm grid's value / the "
              f"{args.check_grid:g} mm one's, percentiles 5 / 50 / 95 (all plans; the best 30 %)")
        for name in ("machining_error", "machining_error_mean"):
            r = measured[name] / fine[name]
            q = [np.percentile(r[m & np.isfinite(r)], [5, 50, 95]) for m in (ok, best)]
            print(f"- {name}: " + "; ".join(" / ".join(f"{v:.3f}" for v in x) for x in q))


if __name__ == "__main__":
    main()
