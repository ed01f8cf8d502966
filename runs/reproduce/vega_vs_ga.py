"""VEGA against the GA at equal distinct-evaluation budgets, and Fountas' Table 1 again.

Runs (or resumes: finished runs are reused) these studies and prints their tables:

1. ``runs/kubota_vega_vs_ga.yaml``: Kubota's function, 30 seeds, 1000 distinct evaluations;
   and the same at 6000 distinct evaluations;
2. ``runs/fountas_fig7.yaml``: the Fig. 7 analog on the toolpath problem, 6000 distinct
   evaluations (``--toolpath-seeds`` repetitions, 30 in the study file; 0 skips it);
3. ``runs/fountas_viral_parameters.yaml`` with ``--table1``: Fountas' Table 1 factor study
   (50 generations, 30 seeds per level).

For each: per variant the median, quartiles and best final value (Δf where the optimum is
known), evaluations and cache hits; the Wilcoxon signed-rank tests against the reference
with Holm's correction; the Friedman test; the Bayesian signed-rank probabilities.

    python runs/reproduce/vega_vs_ga.py [--studies results/reproduce] [--out PATH | --regenerate] [--toolpath-seeds 30] [--table1]
                                        [--backend processes --workers 2]

Writes ``runs/reproduce/vega_vs_ga.md`` (what it prints).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from evoplan.study.config import load_study
from evoplan.study.curves import DEFAULT_TARGETS, reference_values, runtimes, step_history
from evoplan.study.report import markdown_table
from evoplan.study.runner import run_study
from outputs import add_report_options, resolve_report_paths, write_report  # runs/reproduce/outputs.py

RUNS = Path(__file__).resolve().parents[1]
# Regions of practical equivalence of the Bayesian test, fixed before the runs: on Kubota every
# value below 1e-9 is the codec floor's neighbourhood (the floor is 6.67e-13); on the toolpath
# objective (Eq. 9, order 0.01-0.1) a difference below 1e-4 does not matter.
KUBOTA_ROPE, TOOLPATH_ROPE = 1e-9, 1e-4


def study_tables(folder: Path) -> list[str]:
    runs = pd.read_csv(folder / "runs.csv")
    factor = runs["factor"].astype(object)
    runs["variant"] = runs["algorithm"].where(factor.isna(), factor.astype(str) + "=" + runs["level"].astype(str))
    runs["value"] = runs["final_best"] - runs["optimum"].fillna(0.0)
    g = runs.groupby("variant", sort=False)
    table = pd.DataFrame({
        "runs": g.size(), "median": g["value"].median(), "q1": g["value"].quantile(0.25),
        "q3": g["value"].quantile(0.75), "best": g["value"].min(), "evaluations": g["evaluations"].median(),
        "cache hits": g["cache_hits"].median(), "generations": g["generations"].median(),
        "stalled": g["stop_reason"].apply(lambda s: int((s == "stalled").sum())),
    }).reset_index()
    out = [markdown_table(table), ""]
    bias = generation_end_bias(folder, runs)
    if len(bias):
        out += ["First hits read at generation ends instead of at the evaluation that hit the target:", "",
                markdown_table(bias), ""]
    tests = pd.read_csv(folder / "tests.csv")
    if len(tests):
        cols = ["factor", "reference", "algorithm", "level", "n", "median_difference", "effect", "p_value",
                "p_holm", "verdict"]
        out += ["Wilcoxon signed-rank against the reference, Holm-adjusted:", "",
                markdown_table(tests[cols]), ""]
    friedman = pd.read_csv(folder / "friedman.csv")
    if len(friedman):
        out += ["Friedman test:", "", markdown_table(friedman), ""]
    bayes = folder / "bayes.csv"
    if bayes.is_file() and len(b := pd.read_csv(bayes)):
        cols = ["factor", "reference", "algorithm", "level", "n", "rope", "p_better", "p_equivalent", "p_worse"]
        out += ["Bayesian signed-rank: probability the variant is better / equivalent within the rope / worse:",
                "", markdown_table(b[cols]), ""]
    return out


def generation_end_bias(folder: Path, runs: pd.DataFrame) -> pd.DataFrame:
    """Mean first-hit runtime read at generation ends minus at the evaluation, per variant
    (over the (run, target) pairs hit within the budget; COCO's 51 targets)."""
    f_ref = reference_values(runs)
    out = {}
    for r in runs[runs["status"] == "ok"].itertuples(index=False):
        history = pd.read_csv(folder / "histories" / f"{r.key}.csv")
        trace = pd.read_csv(folder / "traces" / f"{r.key}.csv")
        targets = f_ref.loc[(r.problem, r.dimension)] + DEFAULT_TARGETS
        coarse = runtimes(history, r.final_best, r.budget, targets)
        exact = runtimes(step_history(trace, history), r.final_best, r.budget, targets)
        hit = np.isfinite(coarse) & np.isfinite(exact)
        out.setdefault(r.variant, []).extend((coarse[hit] - exact[hit]).tolist())
    return pd.DataFrame([{"variant": v, "pairs": len(d), "mean overstatement (evaluations)": np.mean(d)}
                         for v, d in out.items() if d])


def one(title: str, path: Path, out: Path, args, rope: float, **changes) -> list[str]:
    """Run one study (its ``statistics.rope`` set to ``rope``) and return its tables."""
    study = load_study(path)
    statistics = study.statistics.model_copy(update={"rope": rope})
    study = study.model_copy(update={"statistics": statistics, **changes})
    t0 = time.perf_counter()
    run_study(study, str(path), out, backend=args.backend, workers=args.workers, progress=False)
    wall = time.perf_counter() - t0
    log = json.loads((out / "execution.json").read_text())
    ran = [e for e in log if e["ran"]]
    made = "; ".join(f"{e['ran']} runs in {e['wall_seconds']:.0f} s on {e['backend']} ({e['workers']} workers)"
                     for e in ran)
    lines = [f"## {title}", "", f"`{path.relative_to(RUNS.parent)}` into `{out}` ({study.seeds} seeds; "
             f"{made}; {wall:.0f} s this invocation)", ""]
    return lines + study_tables(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--studies", default="results/reproduce", help="folder of the studies")
    add_report_options(ap)
    ap.add_argument("--toolpath-seeds", type=int, default=30)
    ap.add_argument("--table1", action="store_true", help="also Fountas' Table 1 factor study")
    ap.add_argument("--backend", default="processes")
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    resolve_report_paths(args, __file__)
    root = Path(args.studies)
    lines = ["# VEGA against the GA at equal distinct-evaluation budgets", "",
             "`python runs/reproduce/vega_vs_ga.py " + (f"--studies {args.studies} " if args.studies != "results/reproduce" else "")
             + (f"--toolpath-seeds {args.toolpath_seeds} " if args.toolpath_seeds != 30 else "")
             + ("--table1" if args.table1 else "") + "`", "",
             "Values are Δf = f - f_opt where the optimum is known (Kubota: f_opt = 0; the 23-bit codec "
             "cannot code 0, its floor is 6.67e-13), else raw objective values.", ""]
    kubota = RUNS / "kubota_vega_vs_ga.yaml"
    lines += one("Kubota, 1000 distinct evaluations", kubota, root / "kubota_vega_vs_ga", args, KUBOTA_ROPE)
    budget = load_study(kubota).budget.model_copy(update={"evaluations": 6000})
    lines += one("Kubota, 6000 distinct evaluations", kubota, root / "kubota_vega_vs_ga_6000", args, KUBOTA_ROPE,
                 budget=budget)
    if args.toolpath_seeds:
        lines += one("Toolpath, Fig. 7 analog, 6000 distinct evaluations", RUNS / "fountas_fig7.yaml",
                     root / "fountas_fig7", args, TOOLPATH_ROPE, seeds=args.toolpath_seeds)
    if args.table1:
        lines += one("Fountas Table 1 (one factor at a time, 50 generations)", RUNS / "fountas_viral_parameters.yaml",
                     root / "fountas_viral_parameters", args, KUBOTA_ROPE)
    text = "\n".join(lines) + "\n"
    write_report(args, text)


if __name__ == "__main__":
    main()
