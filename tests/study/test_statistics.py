"""Statistics on hand-made tables: medians and quartiles, ranks, Wilcoxon p-values, Holm."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from evoplan.study.statistics import compare, holm, mean_ranks, paired, summarize, unpaired, verdict


def table(values: dict[str, list[float]], problem: str = "p", status=None) -> pd.DataFrame:
    rows = []
    for algorithm, vals in values.items():
        for r, v in enumerate(vals):
            rows.append({"problem": problem, "dimension": 2, "algorithm": algorithm, "factor": "", "level": "",
                         "repetition": r, "final_best": v, "status": "ok", "evaluations": 100, "wall_seconds": 0.1})
    frame = pd.DataFrame(rows)
    if status:
        for (algorithm, r), s in status.items():
            frame.loc[(frame.algorithm == algorithm) & (frame.repetition == r), "status"] = s
    return frame


def test_summary_medians_and_quartiles_of_a_known_sample():
    s = summarize(table({"a": [5.0, 1.0, 4.0, 2.0, 3.0], "b": [10.0, 10.0, 30.0, 20.0, 20.0]})).set_index("algorithm")
    assert s.loc["a", ["median", "q1", "q3", "best", "mean", "worst"]].tolist() == [3.0, 2.0, 4.0, 1.0, 3.0, 5.0]
    assert s.loc["b", ["median", "q1", "q3", "best"]].tolist() == [20.0, 10.0, 20.0, 10.0]
    assert s.loc["a", "runs"] == 5 and s.loc["a", "failed"] == 0


def test_failed_runs_are_counted_have_no_value_and_rank_last():
    runs = table({"a": [1.0, 1.0, 1.0], "b": [2.0, 2.0, 0.5]}, status={("a", 2): "failed"})
    s = summarize(runs).set_index("algorithm")
    assert s.loc["a", "failed"] == 1 and s.loc["a", "median"] == 1.0 and s.loc["a", "runs"] == 3
    # ranks per repetition: r0 a=1 b=2; r1 a=1 b=2; r2 a failed -> last, b=1
    assert mean_ranks(runs).droplevel([0, 1]).xs("", level="factor").xs("", level="level").to_dict() == {
        "a": pytest.approx(4 / 3), "b": pytest.approx(5 / 3)}


def test_ties_share_the_average_rank():
    ranks = mean_ranks(table({"a": [1.0, 3.0], "b": [1.0, 2.0], "c": [0.0, 2.0]}))
    by_algo = {k[2]: v for k, v in ranks.items()}
    # r0: c=1, a=b=2.5 ; r1: b=c=1.5, a=3
    assert by_algo == {"a": 2.75, "b": 2.0, "c": 1.25}


def test_holm_on_known_p_values():
    # sorted 0.005, 0.01, 0.03, 0.04 times 4, 3, 2, 1 = 0.02, 0.03, 0.06, 0.04 -> running max
    assert holm(np.array([0.01, 0.04, 0.03, 0.005])) == pytest.approx([0.03, 0.06, 0.06, 0.02])
    # m = 2 (NaN left out): 0.5 * 2 = 1.0, then max(1.0, 0.9 * 1) = 1.0
    assert holm(np.array([0.5, np.nan, 0.9])) == pytest.approx([1.0, np.nan, 1.0], nan_ok=True)
    assert holm(np.array([0.01, 0.02])) == pytest.approx([0.02, 0.02])
    assert holm(np.array([0.2])) == pytest.approx([0.2])


def test_signed_rank_exact_p_values_counted_by_hand():
    # all 6 differences positive: W- = 0, P = 2 * (1 / 2^6)
    n, diff, w, p, r = paired(np.array([2.0, 3, 4, 5, 6, 7]), np.array([1.0, 1, 1, 1, 1, 1]))
    assert (n, w, r) == (6, 0.0, 1.0) and p == pytest.approx(2 / 64) and diff == 3.5
    # differences 1, 2, 3, 4, -5: W- = 5; subsets of {1..5} summing to <= 5: 10 of 32 -> p = 20/32
    n, diff, w, p, r = paired(np.array([1.0, 2, 3, 4, -5]), np.zeros(5))
    assert w == 5.0 and p == pytest.approx(20 / 32) and r == pytest.approx((10 - 5) / 15)


def test_signed_rank_drops_failed_pairs_and_all_zero_differences_give_p_one():
    n, diff, w, p, r = paired(np.array([1.0, np.nan, 3.0]), np.array([1.0, 2.0, 3.0]))
    assert (n, diff, p, r) == (2, 0.0, 1.0, 0.0)


def test_rank_sum_exact_p_value():
    # complete separation of 3 vs 3: U = 0, P = 2 / C(6, 3)
    n, diff, u, p, r = unpaired(np.array([1.0, 2, 3]), np.array([4.0, 5, 6]))
    assert u == 0.0 and p == pytest.approx(0.1) and diff == -3.0 and r == -1.0


def test_compare_tests_every_algorithm_against_the_reference_with_holm():
    ref = [5.0, 6, 7, 8, 9, 10, 11]
    runs = table({"ref": ref, "good": [1.0, 2, 3, 4, 5, 6, 7], "same": ref})
    t = compare(runs, "ref").set_index("algorithm")
    assert set(t.index) == {"good", "same"}
    assert t.loc["good", "p_value"] == pytest.approx(2 / 128)  # 7 pairs, all one way
    assert t.loc["good", "p_holm"] == pytest.approx(2 * 2 / 128)
    assert t.loc["good", "verdict"] == "better" and t.loc["same", "verdict"] == "same"
    assert t.loc["same", "p_value"] == 1.0


def test_factor_levels_are_compared_with_their_base_level():
    rows = []
    for level, vals in {"2": [9.0] * 6, "7": [5.0, 6, 7, 8, 9, 10]}.items():
        for r, v in enumerate(vals):
            rows.append({"problem": "k", "dimension": 2, "algorithm": "vega", "factor": "virus.count", "level": level,
                         "repetition": r, "final_best": v, "status": "ok"})
    t = compare(pd.DataFrame(rows), "vega", {"virus.count": "7"})
    assert t["level"].tolist() == ["2"] and t["reference"].iloc[0] == "vega [7]"


def test_verdict_reads_the_direction_of_minimization():
    assert verdict(-0.4, 0.01, 0.05) == "better"
    assert verdict(0.4, 0.01, 0.05) == "worse"
    assert verdict(-0.4, 0.2, 0.05) == "same"


def test_direction_comes_from_ranks_when_the_median_difference_is_zero():
    # most runs tie at the optimum; the level is worse in 9 of 30 runs and never better
    ref = np.zeros(30)
    level = np.where(np.arange(30) < 9, np.arange(1.0, 31.0), 0.0)
    n, diff, w, p, r = paired(level, ref)
    assert diff == 0.0 and r == 1.0 and verdict(r, p, 0.05) == "worse"
