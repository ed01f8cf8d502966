"""Which algorithm for a real-valued problem: every single-objective algorithm at one budget.

Rastrigin and the sphere in 5 dimensions (pymoo's test problems on their own bounds:
Rastrigin on [-5, 5], the sphere ``sum (x - 0.5)^2`` on [0, 1]; and Rastrigin with its optimum moved off the centre, :func:`make`), 2000 evaluations (``("n_evals", 2000)``: counted by the engine, distinct genotypes),
seeds 1..N, through :func:`evoplan.minimize`; pymoo's own GA through
``pymoo.optimize.minimize`` at the same budget as a reference. Printed and written as a
markdown table: the median, quartiles and best of the final best value per algorithm.

The variants separate the binary codec from the operators: evoplan's GA and VEGA (Eq. 8
codec, 23 bits a variable, the paper's roulette and single-point operators), the same GA with
tournament selection and per-bit mutation at 1 / L, pymoo's GA operators on evoplan's binary
codec (``pymoo_ga`` with ``representation: binary``), and pymoo's real-coded GA, DE, CMA-ES and
PSO on the unit cube.

    python runs/bench/choose_algorithm.py [--seeds 10] [--budget 2000] [--problems ...] [--out PATH]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "reproduce"))
from outputs import add_report_options, resolve_report_paths  # noqa: E402

import evoplan  # noqa: E402

VARIANTS: dict[str, tuple[str, dict]] = {
    "ga (binary, paper operators)": ("ga", {"pop_size": 20}),
    "ga (binary, Gray code)": ("ga", {"pop_size": 20, "gray": True}),
    "ga (binary, tournament + per-bit 1/L)": ("ga", {"pop_size": 20, "selection": {"kind": "tournament"},
                                                    "mutation": {"kind": "per_bit", "rate": 1 / 115}}),
    "vega (binary, paper operators)": ("vega", {"pop_size": 20}),
    "pymoo_ga binary (pymoo operators, evoplan codec)": ("pymoo_ga", {"pop_size": 20, "representation": "binary"}),
    "pymoo_ga real (SBX + PM)": ("pymoo_ga", {"pop_size": 20}),
    "pymoo_de (DE/rand/1/bin)": ("pymoo_de", {"pop_size": 20}),
    "pymoo_cmaes": ("pymoo_cmaes", {}),
    "pymoo_pso": ("pymoo_pso", {}),
}
PROBLEMS = ("Rastrigin-5D", "Rastrigin-5D shifted", "Sphere-5D")


def make(label: str):
    """The problem of a table: pymoo's, or Rastrigin with its optimum moved to x_i = 1.3.

    pymoo's Rastrigin and sphere have their optimum at the centre of the box, where the
    real-coded operators' offspring of a spread population fall most often; the shifted
    Rastrigin (same bounds, same landscape around a point off centre) shows how much of a
    result is owed to that."""
    from pymoo.problems import get_problem
    from pymoo.problems.single.rastrigin import Rastrigin

    class ShiftedRastrigin(Rastrigin):
        def _evaluate(self, x, out, *args, **kwargs):
            super()._evaluate(x - 1.3, out, *args, **kwargs)

    if label == "Rastrigin-5D shifted":
        return ShiftedRastrigin(n_var=5)
    return get_problem(label.split("-")[0].lower(), n_var=5)


def evoplan_best(problem, name: str, settings: dict, budget: int, seed: int) -> float:
    settings = dict(settings)
    gray = settings.pop("gray", None)
    return evoplan.minimize(problem, name, ("n_evals", budget), seed=seed, gray=gray, **settings).f


def pymoo_best(problem, budget: int, seed: int) -> float:
    from pymoo.algorithms.soo.nonconvex.ga import GA
    from pymoo.optimize import minimize

    return float(minimize(problem, GA(pop_size=20), ("n_evals", budget), seed=seed).F[0])


def summary(values: list[float]) -> str:
    q1, med, q3 = np.percentile(values, [25, 50, 75])
    return f"{med:.3g} | {q1:.3g} - {q3:.3g} | {min(values):.3g}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--budget", type=int, default=2000)
    ap.add_argument("--problems", nargs="+", choices=PROBLEMS, default=list(PROBLEMS))
    add_report_options(ap)
    args = ap.parse_args()
    resolve_report_paths(args, __file__)
    seeds = range(1, args.seeds + 1)
    lines = [f"# Best value after {args.budget} evaluations, seeds 1-{args.seeds}", "",
             "`python runs/bench/choose_algorithm.py"
             f"{'' if args.seeds == 10 else f' --seeds {args.seeds}'}"
             f"{'' if args.budget == 2000 else f' --budget {args.budget}'}`", ""]
    for label in args.problems:
        problem = make(label)
        lines += [f"## {label}", "", "| algorithm | median | quartiles | best |", "|---|---|---|---|"]
        rows = {k: [evoplan_best(problem, n, s, args.budget, seed) for seed in seeds] for k, (n, s) in VARIANTS.items()}
        rows["pymoo GA itself (pymoo.optimize.minimize)"] = [pymoo_best(problem, args.budget, seed) for seed in seeds]
        for key, values in sorted(rows.items(), key=lambda kv: np.median(kv[1])):
            lines.append(f"| {key} | {summary(values)} |")
            print(f"{label:13s} {key:50s} {summary(values)}", flush=True)
        lines.append("")
    Path(args.out).write_text("\n".join(lines))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
