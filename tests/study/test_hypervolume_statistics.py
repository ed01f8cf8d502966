"""A multi-objective study's statistics are on the hypervolume: the deficit HV_max - HV of each
run (its hypervolume at the last generation within the budget) is what the tables, tests,
ranks and figures compare."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from evoplan.study.config import load_study
from evoplan.study.measure import deficit_runs, deficit_steps, hypervolume_within
from evoplan.study.runner import run_study

STUDY = """
seed: 3
seeds: 3
budget: {{evaluations: 24}}
problems:
  - name: toolpath
    label: fountas_mo
    params:
      objectives: [machining_error, machining_time]
      weights: {{machining_error: 0.5, machining_time: 0.5}}
      normalization: {{machining_error: [0.0, 0.2], machining_time: [0.0, 10.0]}}
algorithms:
  - {{name: nsga2, pop_size: 8{ref}}}
  - {{name: sms_emoa, pop_size: 8{ref}}}
output: {{plots: {plots}}}
"""


def test_deficits_take_the_hypervolume_within_the_budget_and_the_best_of_the_problem():
    histories = {"a": pd.DataFrame({"evaluations": [8, 16, 24, 32], "hypervolume": [1.0, 2.0, 2.5, 4.0]}),
                 "b": pd.DataFrame({"evaluations": [8, 16, 24], "hypervolume": [0.5, 3.0, 3.0]}),
                 "c": pd.DataFrame({"evaluations": [10], "hypervolume": [7.0]})}
    runs = pd.DataFrame({"key": ["a", "b", "c"], "problem": ["p", "p", "q"], "dimension": [2, 2, 2],
                         "status": ["ok", "ok", "ok"], "budget": [24, 24, 5], "hypervolume": [4.0, 3.0, 7.0],
                         "final_best": [0.1, 0.2, 0.3], "optimum": [np.nan] * 3})
    out, hv_max = deficit_runs(runs, histories.__getitem__)
    # a: 2.5 at 24 evaluations (4.0 came after the budget); b: 3.0; c: no generation within 5, its first
    assert hv_max.loc[("p", 2)] == 3.0 and hv_max.loc[("q", 2)] == 7.0
    assert out["final_best"].tolist() == [0.5, 0.0, 0.0] and (out["optimum"] == 0).all()
    assert out["best_overall"].tolist() == [-1.0, 0.0, 0.0]  # a's final 4.0 beats HV_max within budget
    assert hypervolume_within(pd.DataFrame({"evaluations": [1]}), 10, 9.5) == 9.5  # no column: the record's
    steps = deficit_steps(histories["a"], 3.0)
    assert steps["best"].tolist() == [2.0, 1.0, 0.5, -1.0] and steps["evaluations"].tolist() == [8, 16, 24, 32]


@pytest.fixture(scope="module")
def study_out(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("hv")
    path = tmp / "mo.yaml"
    path.write_text(STUDY.format(ref=", ref_point: [3.0, 3.0]", plots="true"))
    run_study(load_study(path), str(path), tmp / "out", "serial", progress=False)
    return tmp / "out"


def test_tables_and_tests_compare_the_hypervolume_deficits(study_out):
    runs = pd.read_csv(study_out / "runs.csv")
    assert (runs["status"] == "ok").all(), runs["error"].tolist()
    within = {}
    for r in runs.itertuples():  # the oracle: each run's history, read back
        h = pd.read_csv(study_out / "histories" / f"{r.key}.csv")
        within[r.key] = h.loc[h["evaluations"] <= r.budget, "hypervolume"].iloc[-1]
    deficit = runs["key"].map(within).max() - runs["key"].map(within)
    summary = pd.read_csv(study_out / "summary.csv").set_index("algorithm")
    for name, rows in runs.assign(deficit=deficit).groupby("algorithm"):
        assert summary.loc[name, "median"] == pytest.approx(rows["deficit"].median(), abs=1e-12)
        assert summary.loc[name, "best"] >= 0
    assert min(summary["best"]) == 0  # the best run's deficit
    tests = pd.read_csv(study_out / "tests.csv")
    assert len(tests) == 1 and tests["n"].iloc[0] == 3 and tests["reference"].iloc[0] == "nsga2"
    d = deficit[runs["algorithm"] == "sms_emoa"].to_numpy() - deficit[runs["algorithm"] == "nsga2"].to_numpy()
    assert tests["median_difference"].iloc[0] == pytest.approx(np.median(d), abs=1e-12)
    report = (study_out / "report.md").read_text()
    assert "hypervolume deficit" in report and "HV_max = " in report and "not comparable" not in report
    for name in ("ecdf", "final_values", "convergence"):
        assert (study_out / "figures" / f"{name}.png").stat().st_size > 5000


def test_without_a_fixed_reference_point_the_report_warns(tmp_path):
    path = tmp_path / "mo.yaml"
    path.write_text(STUDY.format(ref="", plots="false").replace("seeds: 3", "seeds: 1"))
    run_study(load_study(path), str(path), tmp_path / "out", "serial", progress=False)
    assert "nsga2, sms_emoa fixed no ref_point" in (tmp_path / "out" / "report.md").read_text()
