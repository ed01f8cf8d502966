"""Statistics of a study from its runs table: summaries, mean ranks, tests against a reference.

All values are the runs' ``final_best`` (the best objective within the exact budget), minimized.
Failed runs are counted in the summary but have no value; they rank last.

**Ranks.** Within each problem, dimension and repetition every variant (algorithm, factor,
level) is ranked by its final value (1 = best, ties share the average rank); ``mean_rank``
averages over repetitions (Friedman-style ranks, meaningful because repetitions share seeds).

**Tests.** Repetition ``r`` of every variant on a problem ran with the same seed (see
``grid.py``), so results are paired by repetition and the default test is the Wilcoxon
signed-rank test on the paired differences (``scipy.stats.wilcoxon``, two-sided, zero
differences dropped; all differences zero gives p = 1). SciPy's p-value is exact for up to 50
pairs without ties or zeros (the exact null distribution), and also exact for up to 13 pairs
with ties or zeros (a permutation test over all 2^n sign assignments); with ties or zeros and
more than 13 pairs, or beyond 50 pairs, it is the normal approximation. ``test: rank_sum`` uses the Mann-Whitney U test
instead (``scipy.stats.mannwhitneyu``), which ignores the pairing. The effect size is the
rank-biserial correlation (paired or unpaired form); its sign gives the direction of a
significant difference (the median difference is often 0 when most runs reach the same value). p-values are adjusted with
Holm's step-down method (statsmodels) within each family: the comparisons against one reference on one
problem and dimension (for a factor study: the levels of one factor against its base level).
"""

from __future__ import annotations

from math import comb

import numpy as np
import pandas as pd
from scipy import stats
from statsmodels.stats.multitest import multipletests

BLOCK = ["problem", "dimension"]
VARIANT = ["algorithm", "factor", "level"]


def holm(p: np.ndarray) -> np.ndarray:
    """Holm's step-down adjustment (``statsmodels.stats.multitest.multipletests``, ``holm``):
    the k-th smallest of m p-values (k from 0) times m - k, running maximum, capped at 1.
    NaN stays NaN and does not count in m."""
    p = np.asarray(p, dtype=float)
    out = np.full(p.shape, np.nan)
    ok = np.isfinite(p)
    if ok.any():
        out[ok] = multipletests(p[ok], method="holm")[1]
    return out


def mean_ranks(runs: pd.DataFrame) -> pd.Series:
    """Mean rank of each variant within its problem and dimension (see the module docstring)."""
    values = runs["final_best"].where(runs["status"] == "ok")
    rank = values.groupby([runs[c] for c in BLOCK + ["repetition"]]).rank(method="average", na_option="bottom")
    return rank.groupby([runs[c] for c in BLOCK + VARIANT], sort=False).mean().rename("mean_rank")


def summarize(runs: pd.DataFrame) -> pd.DataFrame:
    """``summary.csv``: per problem, dimension and variant, the distribution of final values."""
    ok = runs["status"] == "ok"
    value = runs["final_best"].where(ok).astype(float)
    keys = [runs[c] for c in BLOCK + VARIANT]
    g = value.groupby(keys, sort=False)
    table = pd.DataFrame({
        "runs": runs.groupby(keys, sort=False).size(),
        "failed": (~ok).groupby(keys, sort=False).sum(),
        "median": g.median(),
        "q1": g.quantile(0.25),
        "q3": g.quantile(0.75),
        "best": g.min(),
        "mean": g.mean(),
        "worst": g.max(),
        "evaluations": runs["evaluations"].where(ok).groupby(keys, sort=False).median(),
        "wall_seconds": runs["wall_seconds"].groupby(keys, sort=False).median(),
    })
    table = table.join(mean_ranks(runs))
    return table.reset_index()


def paired(x: np.ndarray, y: np.ndarray) -> tuple[int, float, float, float, float]:
    """Signed-rank test of ``x`` against ``y`` paired by position.

    Returns ``(n pairs, median of x - y, W, p, r)`` with ``r = (W+ - W-) / (W+ + W-)`` the
    matched-pairs rank-biserial correlation (in [-1, 1]; negative: ``x`` mostly lower).
    """
    keep = np.isfinite(x) & np.isfinite(y)
    d = x[keep] - y[keep]
    if d.size == 0:
        return 0, np.nan, np.nan, np.nan, np.nan
    nz = d[d != 0]
    if nz.size == 0:
        return d.size, 0.0, 0.0, 1.0, 0.0
    ranks = stats.rankdata(np.abs(nz))
    r = float((ranks[nz > 0].sum() - ranks[nz < 0].sum()) / ranks.sum())
    res = stats.wilcoxon(d, zero_method="wilcox", alternative="two-sided")
    return d.size, float(np.median(d)), float(res.statistic), float(res.pvalue), r


def unpaired(x: np.ndarray, y: np.ndarray) -> tuple[int, float, float, float, float]:
    """Mann-Whitney U test of ``x`` against ``y``.

    Returns ``(min n, median x - median y, U of x, p, r)`` with ``r = 2 U / (n_x n_y) - 1``
    the rank-biserial correlation ``P(x > y) - P(x < y)`` (negative: ``x`` mostly lower).
    """
    x, y = x[np.isfinite(x)], y[np.isfinite(y)]
    if x.size == 0 or y.size == 0:
        return 0, np.nan, np.nan, np.nan, np.nan
    n = min(x.size, y.size)
    if np.all(np.concatenate([x, y]) == x[0]):
        return n, 0.0, x.size * y.size / 2, 1.0, 0.0
    res = stats.mannwhitneyu(x, y, alternative="two-sided")
    r = 2 * float(res.statistic) / (x.size * y.size) - 1
    return n, float(np.median(x) - np.median(y)), float(res.statistic), float(res.pvalue), r


TESTS = {"signed_rank": paired, "rank_sum": unpaired}


def _by_repetition(runs: pd.DataFrame, reps: np.ndarray) -> np.ndarray:
    values = runs["final_best"].where(runs["status"] == "ok").astype(float)
    return values.set_axis(runs["repetition"]).groupby(level=0).first().reindex(reps).to_numpy()


def value_matrix(variants: list[tuple[tuple[str, str], pd.DataFrame]]) -> np.ndarray:
    """``(repetitions, variants)`` final values paired by repetition: failed runs ``inf`` (last),
    a repetition a variant lacks NaN."""
    reps = np.unique(np.concatenate([rows["repetition"].to_numpy() for _, rows in variants]))
    cols = []
    for _, rows in variants:
        values = rows["final_best"].astype(float).where(rows["status"] == "ok", np.inf)
        cols.append(values.set_axis(rows["repetition"]).groupby(level=0).first().reindex(reps).to_numpy())
    return np.column_stack(cols)


def smallest_p(test: str, n: int, m: int = 1) -> float:
    """The smallest Holm-adjusted p-value ``test`` can give with ``n`` runs a side and ``m``
    comparisons in the family: ``2 / 2**n`` (signed-rank: every difference of one sign) or
    ``2 / C(2n, n)`` (rank-sum: complete separation), times ``m``. If it is not below alpha,
    no difference can be declared, whatever the data."""
    if n < 1:
        return 1.0
    p = 2.0 / 2.0**n if test == "signed_rank" else 2.0 / float(comb(2 * n, n))
    return min(1.0, m * p)


def families(runs: pd.DataFrame, reference: str, reference_levels: dict[str, str]):
    """Yield ``(block, factor, reference variant rows, [(variant, rows), ...])`` per test family."""
    for block, rows in runs.groupby(BLOCK, sort=False):
        for factor, frows in rows.groupby("factor", sort=False):
            variants = list(frows.groupby(["algorithm", "level"], sort=False))
            if factor == "":
                ref_key = (reference, "")
            else:
                ref_key = (frows["algorithm"].iloc[0], reference_levels.get(factor, variants[0][0][1]))
            ref = [v for v in variants if v[0] == ref_key]
            if not ref:
                continue
            yield block, factor, ref[0], [v for v in variants if v[0] != ref_key]


def compare(runs: pd.DataFrame, reference: str, reference_levels: dict[str, str] | None = None,
            test: str = "signed_rank", alpha: float = 0.05) -> pd.DataFrame:
    """``tests.csv``: every variant against the reference of its family, Holm-adjusted."""
    fn = TESTS[test]
    out = []
    for (problem, dimension), factor, (ref_key, ref_rows), others in families(runs, reference, reference_levels or {}):
        reps = np.unique(np.concatenate([ref_rows["repetition"].to_numpy()] +
                                        [rows["repetition"].to_numpy() for _, rows in others]))
        y = _by_repetition(ref_rows, reps)
        family = []
        for (algorithm, level), rows in others:
            n, diff, statistic, p, effect = fn(_by_repetition(rows, reps), y)
            family.append({"problem": problem, "dimension": dimension, "factor": factor,
                           "reference": f"{ref_key[0]}" + (f" [{ref_key[1]}]" if factor else ""),
                           "algorithm": algorithm, "level": level, "test": test, "n": n,
                           "median_difference": diff, "effect": effect, "statistic": statistic, "p_value": p})
        if not family:
            continue
        adjusted = holm(np.array([r["p_value"] for r in family]))
        for r, p_holm in zip(family, adjusted):
            r["p_holm"] = p_holm
            r["verdict"] = verdict(r["effect"], p_holm, alpha)
        out.extend(family)
    columns = ["problem", "dimension", "factor", "reference", "algorithm", "level", "test", "n",
               "median_difference", "effect", "statistic", "p_value", "p_holm", "verdict"]
    return pd.DataFrame(out, columns=columns)


def verdict(effect: float, p_holm: float, alpha: float) -> str:
    """``better`` / ``worse`` than the reference (minimizing: a negative rank-biserial ``effect``
    means lower values) when the Holm-adjusted p-value is below ``alpha``, else ``same``."""
    if not (np.isfinite(p_holm) and np.isfinite(effect)) or p_holm >= alpha or effect == 0:
        return "same"
    return "better" if effect < 0 else "worse"
