"""``report.md``: a study's setting, method, tables and figures on one page."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from .statistics import BLOCK, VARIANT, smallest_p

METHOD = """\
- **Budget, counted the same way.** Every algorithm (evoplan's GA and VEGA, and the pymoo and
  DEAP adapters) runs as an ask/tell algorithm inside evoplan's engine, which evaluates every
  batch asked for, answers a genotype it has already evaluated from the run's cache, and
  charges the budget with {budget_text}. It stops after the generation in which the budget is
  reached. `final_best` is the best value among the first `budget` evaluations in evaluation
  order (exactly the budget for every algorithm); `evaluations` is what the run used in all
  (at most one batch more); `cache_hits` the genotypes answered by the cache.
- **Seeds.** The seed of repetition r on a problem is derived from the study seed, the problem
  and r (`numpy.random.SeedSequence`), not from the algorithm nor the level: runs are paired
  by repetition (evoplan's GA and VEGA start from the same population), identical whichever
  backend ran them.
- **Tests.** {test_text} Holm's correction within each problem (and factor); alpha = {alpha}.
  *better/worse* = significantly lower/higher final values than the reference, the direction
  given by the rank-biserial correlation r (negative: lower values than the reference).
  With three or more variants: Friedman test over the repetitions as blocks, Nemenyi
  post-hoc pairs and a critical-difference diagram (`friedman.csv`, `nemenyi.csv`,
  `figures/critical_difference.png`). Bayesian signed-rank test against the reference
  (`bayes.csv`: probabilities that a variant is better, equivalent within rope = {rope}, worse).
- **Ranks.** Within each problem and repetition, variants are ranked by final value (1 = best,
  failed runs last); the mean over repetitions is `mean_rank`.
- **Values.** Where the optimum f_opt is known (BBOB through ioh, Kubota, pymoo's test
  problems), tables and figures show the precision Δf = f - f_opt; else raw values.
- **ECDF.** Fixed-target runtimes to f_ref + 10^k for {n_targets} precisions (COCO style); f_ref
  is the known optimum, else the best value any run found. A runtime is the index of the first
  evaluation that reached the target (the engine records every improvement), not the end of
  its generation.
- **Export.** Every run is in `ioh/` in IOHprofiler's JSON format (IOHanalyzer, iohinspector),
  BBOB with its function and instance ids, counts capped at the budget.
- **Adapters depart from their libraries here.** pymoo's CMA-ES is restarted (IPOP, then
  further restarts) until the budget is spent instead of stopping on its own tolerances;
  pymoo's GA runs with duplicate elimination off (pymoo's default is on); DE with a variant
  string uses a fixed F = 0.5 unless F is given (pymoo's dither applies only without a variant
  string); DEAP's eaSimple searches the binary codec by default (`representation: binary`),
  the others the real box through the unit cube.
"""

BUDGET_TEXT = {
    "distinct": "the distinct genotypes evaluated (`cache.budget: distinct`: a cache hit is free)",
    "all": "every genotype asked for (`cache.budget: all`: cache hits are charged too)",
}

TEST_TEXT = {
    "signed_rank": "Wilcoxon signed-rank test on the differences paired by repetition (two-sided).",
    "rank_sum": "Mann-Whitney U (Wilcoxon rank-sum) test, unpaired (two-sided).",
}


def _fmt(x: Any) -> str:
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "-"
    if isinstance(x, (float, np.floating)):
        return f"{x:.3g}"
    return str(x)


def markdown_table(frame: pd.DataFrame) -> str:
    """A pipe table of ``frame`` (numbers to 3 significant digits)."""
    head = "| " + " | ".join(map(str, frame.columns)) + " |"
    rule = "|" + "|".join("---" for _ in frame.columns) + "|"
    body = ["| " + " | ".join(_fmt(v) for v in row) + " |" for row in frame.itertuples(index=False)]
    return "\n".join([head, rule, *body])


def _variant_column(frame: pd.DataFrame) -> pd.Series:
    return np.where(frame["factor"] == "", frame["algorithm"], frame["factor"] + "=" + frame["level"].astype(str))


def block_table(summary: pd.DataFrame, tests: pd.DataFrame) -> pd.DataFrame:
    """The summary rows of one problem with the test against the reference beside them."""
    t = tests.set_index(VARIANT)[["median_difference", "effect", "p_holm", "verdict"]] if len(tests) else None
    out = summary.assign(variant=_variant_column(summary))
    if t is not None:
        out = out.join(t, on=VARIANT)
    else:
        out = out.assign(median_difference=np.nan, effect=np.nan, p_holm=np.nan, verdict="")
    out["verdict"] = out["verdict"].fillna("(reference)")
    cols = ["variant", "runs", "failed", "median", "q1", "q3", "best", "mean_rank", "evaluations",
            "median_difference", "effect", "p_holm", "verdict"]
    return out[cols].rename(columns={"median_difference": "median diff vs ref", "effect": "r (rank-biserial)",
                                     "p_holm": "p (Holm)",
                                     "evaluations": "evals used"})


def overall_ranks(summary: pd.DataFrame, tests: pd.DataFrame) -> pd.DataFrame:
    """Mean of the per-problem mean ranks, and the better/same/worse counts against the reference."""
    s = summary.assign(variant=_variant_column(summary))
    table = s.groupby("variant", sort=False).agg(problems=("mean_rank", "size"), mean_rank=("mean_rank", "mean"),
                                                 median_wall_s=("wall_seconds", "median"))
    if len(tests):
        t = tests.assign(variant=_variant_column(tests))
        counts = pd.crosstab(t["variant"], t["verdict"])
        for v in ("better", "same", "worse"):
            table[v] = counts[v] if v in counts else 0
    return table.reset_index().sort_values("mean_rank")


def power_warnings(tests: pd.DataFrame, test: str, alpha: float) -> list[str]:
    """One line per test family whose runs are too few to ever reach ``alpha`` (after Holm)."""
    if not len(tests):
        return []
    out = []
    for (problem, dim, factor), fam in tests.groupby(["problem", "dimension", "factor"], sort=False):
        n = int(fam["n"].max())
        p_min = smallest_p(test, n, len(fam))
        if p_min >= alpha:
            where = f"{problem}, {dim}-D" + (f", {factor}" if factor else "")
            out.append(f"**Warning** ({where}): with n = {n} runs and {len(fam)} comparison(s) the smallest "
                       f"p-value the test can give is {p_min:.3g} >= alpha = {alpha}: no difference can be "
                       "significant here; add seeds.")
    return out


def render(name: str, meta: dict[str, Any], summary: pd.DataFrame, tests: pd.DataFrame, f_ref: pd.Series,
           known: pd.Series, figures: list[str], failures: pd.DataFrame, test: str, alpha: float,
           n_targets: int, extra: dict[str, Any] | None = None) -> str:
    """``report.md``. ``extra``: ``budget`` (``distinct``/``all``), ``rope``, the tables
    ``friedman`` and ``bayes`` when made, and ``hv_max`` (per problem) for a hypervolume study."""
    extra = extra or {}
    lines = [f"# Study `{name}`", ""]
    lines += [f"- {k}: {v}" for k, v in meta.items()]
    lines += [""] + [w + "\n" for w in power_warnings(tests, test, alpha)]
    lines += ["## Method", "", METHOD.format(test_text=TEST_TEXT[test], alpha=alpha, n_targets=n_targets,
                                             budget_text=BUDGET_TEXT[extra.get("budget", "distinct")],
                                             rope=extra.get("rope", 0.0))]
    lines += ["## Overall", "", markdown_table(overall_ranks(summary, tests)), ""]
    for (problem, dim), rows in summary.groupby(BLOCK, sort=False):
        ref = f_ref.loc[(problem, dim)]
        opt = known.loc[(problem, dim)]
        btests = tests[(tests["problem"] == problem) & (tests["dimension"] == dim)] if len(tests) else tests
        hv_max = extra.get("hv_max")
        if hv_max is not None:
            text = (f"HV_max = {hv_max.loc[(problem, dim)]:.6g} (the largest hypervolume of any run); values are "
                    "hypervolume deficits HV_max - HV (0: the best run), lower is better.")
        elif pd.notna(opt):
            text = f"f_opt = {opt:.6g} (known optimum); values are precisions Δf = f - f_opt."
            rows = rows.assign(**{c: rows[c] - opt for c in ("median", "q1", "q3", "best")})
        else:
            text = f"f_ref = {ref:.6g} (best value found; optimum unknown); values are final objective values."
        lines += [f"## {problem}, {dim}-D", "", text, ""]
        lines += [markdown_table(block_table(rows, btests)), ""]
    for key, title in (("friedman", "Friedman tests (three or more variants)"),
                       ("bayes", "Bayesian signed-rank test against the reference")):
        table = extra.get(key)
        if table is not None and len(table):
            lines += [f"## {title}", "", markdown_table(table), ""]
    if figures:
        lines += ["## Figures", ""] + [f"![{f}]({f})" for f in figures] + [""]
    if len(failures):
        lines += ["## Failed runs", "", markdown_table(failures[["key", "error"]]), ""]
    return "\n".join(lines)
