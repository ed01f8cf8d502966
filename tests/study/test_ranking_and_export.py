"""First hits at evaluation granularity, the power warning, Friedman / CD diagram, the Bayesian
test, Δf for BBOB, and the IOHprofiler export read back."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from evoplan.study.config import load_study
from evoplan.study.curves import runtimes, step_history
from evoplan.study.ioh_ids import functions
from evoplan.study.ranking import bayesian, friedman
from evoplan.study.report import power_warnings
from evoplan.study.runner import run_study
from evoplan.study.statistics import smallest_p


def test_first_hit_is_the_evaluation_that_reached_the_target_not_its_generation_end():
    trace = pd.DataFrame({"evaluation": [1, 7, 30], "best": [5.0, 2.0, 0.5]})
    history = pd.DataFrame({"evaluations": [20, 40, 60], "best": [2.0, 0.5, 0.5]})
    steps = step_history(trace, history)
    assert steps["evaluations"].tolist() == [1, 7, 30, 60] and steps["best"].iloc[-1] == 0.5
    targets = np.array([3.0, 2.0, 0.5, 0.1])
    assert runtimes(steps, 0.5, 60, targets).tolist() == [7, 7, 30, np.inf]
    assert runtimes(history, 0.5, 60, targets).tolist() == [20, 20, 40, np.inf]  # generation ends
    assert runtimes(steps, 2.0, 25, targets).tolist() == [7, 7, np.inf, np.inf]  # hit after the budget
    assert step_history(None, history) is history  # a folder without traces


def test_too_few_runs_to_reach_alpha_are_flagged():
    assert smallest_p("signed_rank", 3) == pytest.approx(0.25)
    assert smallest_p("signed_rank", 6) == pytest.approx(2 / 64)
    assert smallest_p("signed_rank", 6, m=2) == pytest.approx(4 / 64)
    assert smallest_p("rank_sum", 3) == pytest.approx(0.1)
    tests = pd.DataFrame({"problem": ["p", "p", "q"], "dimension": [2, 2, 2], "factor": ["", "", ""],
                          "n": [6, 6, 30]})
    warnings = power_warnings(tests, "signed_rank", 0.05)
    assert len(warnings) == 1 and "p, 2-D" in warnings[0] and "0.0625" in warnings[0]


def runs_frame(columns: dict[str, list[float]]) -> pd.DataFrame:
    rows = [{"problem": "p", "dimension": 2, "factor": "", "level": "", "algorithm": a, "repetition": r,
             "status": "ok", "final_best": v} for a, values in columns.items() for r, v in enumerate(values)]
    return pd.DataFrame(rows)


def test_friedman_and_bayes_see_a_variant_that_is_always_best():
    rng = np.random.default_rng(1)
    base = rng.uniform(1, 2, 12)
    runs = runs_frame({"ref": base, "good": base - 0.5, "same": base + rng.normal(0, 1e-3, 12)})
    table, pairs, diagrams = friedman(runs, "ref")
    assert table["variants"].tolist() == [3] and table["p_value"].iloc[0] < 0.01
    (title, ranks, p_matrix), = diagrams
    assert ranks["good"] == 1.0 and p_matrix.loc["good", "ref"] < 0.05
    assert set(pairs["a"] + pairs["b"]) == {"refgood", "refsame", "goodsame"}
    bayes = bayesian(runs, "ref", nsamples=2000).set_index("algorithm")
    assert bayes.loc["good", "p_better"] > 0.99 and bayes.loc["good", "p_worse"] < 0.01
    two = runs_frame({"ref": base, "good": base - 0.5})
    assert friedman(two, "ref")[0].empty  # two variants: the signed-rank test's job


STUDY = """
seed: 3
seeds: 3
budget: {evaluations: 150}
problems:
  - {name: kubota, bits: 12}
  - {name: bbob-f1, dimensions: [2], bits: 12}
algorithms:
  - {name: ga, population: 10}
  - {name: vega, population: 10, virus: {count: 3}}
  - {name: vega, label: vega_kubota, population: 10, virus: {count: 3, life_rule: kubota}}
output: {plots: true}
"""


def test_a_small_study_has_its_cd_diagram_delta_f_warning_and_ioh_files(tmp_path):
    path = tmp_path / "three.yaml"
    path.write_text(STUDY)
    out = tmp_path / "out"
    run_study(load_study(path), str(path), out, progress=False)
    assert (out / "figures" / "critical_difference.png").read_bytes()[:4] == b"\x89PNG"
    assert len(pd.read_csv(out / "friedman.csv")) == 2  # one family per problem
    report = (out / "report.md").read_text()
    assert "Δf = f - f_opt" in report and "n = 3 runs and 2 comparison(s)" in report and "0.5 >= alpha" in report
    runs = pd.read_csv(out / "runs.csv")
    # the BBOB table shows precisions: the best Δf equals the best raw value minus the optimum
    summary = pd.read_csv(out / "summary.csv")
    bbob = runs[runs["problem"] == "bbob-f1"]
    assert (bbob["final_best"] > bbob["optimum"]).all() and abs(bbob["optimum"].iloc[0]) > 1
    assert f"| {summary[summary['problem'] == 'bbob-f1']['best'].min() - bbob['optimum'].iloc[0]:.3g} |" in report
    ids = functions([("kubota", "kubota", {}), ("bbob-f1", "bbob-f1", {})])
    for variant, problem in (("ga", "kubota"), ("vega_kubota", "bbob-f1")):
        fn = ids[problem]
        folder = out / "ioh" / variant
        meta = json.loads((folder / f"IOHprofiler_f{fn.id}_{fn.name}.json").read_text())
        assert (meta["algorithm"]["name"], meta["function_id"], meta["suite"]) == (variant, fn.id, fn.suite)
        (scenario,) = meta["scenarios"]
        assert scenario["dimension"] == 2 and len(scenario["runs"]) == 3
        blocks = (folder / scenario["path"]).read_text().split("evaluations raw_y\n")[1:]
        mine = runs[(runs["algorithm"] == variant) & (runs["problem"] == problem)].sort_values("repetition")
        for text, entry, run in zip(blocks, scenario["runs"], mine.itertuples()):
            block = np.loadtxt(text.splitlines(), ndmin=2)
            trace = pd.read_csv(out / "traces" / f"{run.key}.csv")
            inside = trace[trace["evaluation"] <= 150]
            assert block[-1, 0] == entry["evals"] == min(run.evaluations, 150)  # capped at the budget
            assert block[: len(inside), 0].tolist() == inside["evaluation"].tolist()
            assert np.all(np.diff(block[:, 1]) <= 0)
            assert entry["best"]["y"] == pytest.approx(run.final_best - run.optimum, rel=1e-12, abs=1e-12)
