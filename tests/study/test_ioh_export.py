"""The IOHprofiler export: real BBOB ids, stable ids elsewhere, counts capped at the budget, the
files ioh's own logger writes, read back by iohinspector."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pandas as pd
import pytest

from evoplan.study.ioh_export import export, run_rows
from evoplan.study.ioh_ids import NON_BBOB_IDS, functions, problem_key

ioh = pytest.importorskip("ioh")


def test_bbob_keeps_its_function_and_instance_and_other_ids_do_not_depend_on_the_study():
    one = functions([("kubota", "kubota", {}), ("bbob-rastrigin", "bbob-f3-i2", {})])
    other = functions([("bbob-f1", "bbob-f1", {}), ("rosen", "rosenbrock", {"n_var": 10}),
                       ("kubota", "kubota", {})])
    assert (one["bbob-rastrigin"].suite, one["bbob-rastrigin"].id, one["bbob-rastrigin"].instance) == ("BBOB", 3, 2)
    assert one["bbob-rastrigin"].name == ioh.get_problem(3, 2, 5, ioh.ProblemClass.BBOB).meta_data.name
    assert other["bbob-f1"].id == 1
    assert one["kubota"] == other["kubota"] and one["kubota"].suite == "evoplan"
    assert one["kubota"].id in NON_BBOB_IDS and other["rosen"].id in NON_BBOB_IDS
    assert problem_key("rosenbrock", {"n_var": 10}) == problem_key("rosenbrock", {"n_var": 2})  # DIM, not f
    assert problem_key("toolpath", {"a": 1}) != problem_key("toolpath", {"a": 2})


def test_two_problems_on_one_id_are_told_apart_in_study_order(monkeypatch):
    import evoplan.study.ioh_ids as ids

    monkeypatch.setattr(ids, "hashed_id", lambda key: NON_BBOB_IDS.stop - 1)  # every key collides
    f = ids.functions([("a", "a", {}), ("b", "b", {}), ("a2", "a", {})])
    assert (f["a"].id, f["b"].id, f["a2"].id) == (NON_BBOB_IDS.stop - 1, NON_BBOB_IDS.start, NON_BBOB_IDS.stop - 1)


def test_counts_stop_at_the_budget_and_every_run_starts_at_evaluation_one():
    trace = pd.DataFrame({"evaluation": [1, 40, 99, 104], "best": [9.0, 5.0, 4.0, 3.0]})
    e, f = run_rows(trace, evaluations=110, budget=100, f_opt=1.0)
    assert e.tolist() == [1, 40, 99, 100] and f.tolist() == [8.0, 4.0, 3.0, 3.0]
    late = pd.DataFrame({"evaluation": [3], "best": [2.0]})
    e, f = run_rows(late, evaluations=20, budget=np.inf, f_opt=np.nan)
    assert e.tolist() == [1, 3, 20] and math.isinf(f[0]) and f[1:].tolist() == [2.0, 2.0]


# two variants, BBOB f3 instance 2 and kubota, in 2-D; run r of a variant improves at these evaluations
TRACES = {"r0": [(1, 300.0), (7, 120.0), (95, 80.1), (120, 79.9)],
          "r1": [(1, 250.0), (30, 90.0)],
          "k0": [(1, 0.5), (12, 0.01), (130, 0.001)]}
F_OPT = 79.48


def study_runs() -> pd.DataFrame:
    rows = []
    for alg in ("ga", "vega"):
        for rep, key in enumerate(("r0", "r1")):
            rows.append({"key": f"{alg}.{key}", "trace": key, "algorithm": alg, "factor": "", "level": "",
                         "problem": "bbob-rastrigin", "dimension": 2, "repetition": rep, "status": "ok",
                         "budget": 100, "evaluations": 120 if key == "r0" else 104})
        rows.append({"key": f"{alg}.k0", "trace": "k0", "algorithm": alg, "factor": "", "level": "",
                     "problem": "kubota", "dimension": 2, "repetition": 0, "status": "ok",
                     "budget": 100, "evaluations": 140})
    return pd.DataFrame(rows)


def write_study(tmp_path):
    runs = study_runs()
    by_key = dict(zip(runs["key"], runs["trace"]))
    ids = functions([("kubota", "kubota", {}), ("bbob-rastrigin", "bbob-f3-i2", {})])
    f_opt = pd.Series({("bbob-rastrigin", 2): F_OPT, ("kubota", 2): np.nan})
    export(tmp_path, runs, lambda k: pd.DataFrame(TRACES[by_key[k]], columns=["evaluation", "best"]), f_opt, ids)
    return runs, ids


def test_iohinspector_reads_the_export_back_with_ids_names_and_capped_counts(tmp_path):
    iohinspector = pytest.importorskip("iohinspector")
    runs, ids = write_study(tmp_path)
    manager = iohinspector.DataManager()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a file iohinspector fails to parse only warns: make it fail
        manager.add_folder(str(tmp_path / "ioh"))
    overview = manager.overview.to_pandas()
    assert sorted(overview["algorithm_name"].unique()) == ["ga", "vega"]
    bbob = overview[overview["function_id"] == 3]
    assert set(bbob["function_name"]) == {ids["bbob-rastrigin"].name} and set(bbob["suite"]) == {"BBOB"}
    assert set(bbob["instance"]) == {2} and list(bbob["evals"]) == [100] * 4  # 120 and 104 made, 100 charged
    kub = overview[overview["function_id"] == ids["kubota"].id]
    assert set(kub["function_name"]) == {"kubota"} and set(kub["evals"]) == {100}
    assert manager.load(monotonic=False)["evaluations"].max() == 100  # nothing past the budget
    data = manager.load(monotonic=True, include_meta_data=True).to_pandas()
    ga0 = data[(data["algorithm_name"] == "ga") & (data["function_id"] == 3) & (data["run_id"] == 1)]
    assert ga0["evaluations"].tolist() == [1, 7, 95]
    assert ga0["raw_y"].to_numpy() == pytest.approx(np.array([300.0, 120.0, 80.1]) - F_OPT)  # f - f_opt
    assert bbob["best_y"].min() == pytest.approx(80.1 - F_OPT)
    kub0 = data[(data["algorithm_name"] == "vega") & (data["function_id"] == ids["kubota"].id)]
    assert kub0["raw_y"].tolist() == [0.5, 0.01]  # optimum unknown here: raw values


def test_the_files_are_those_ioh_s_own_logger_writes_from_the_same_trace(tmp_path):
    runs, ids = write_study(tmp_path / "mine")
    fn = ids["bbob-rastrigin"]
    logger = ioh.logger.Analyzer(root=str(tmp_path / "ioh"), folder_name="ga", algorithm_name="ga",
                                 algorithm_info="ga")
    logger.full_precision = True
    logger.add_experiment_attribute("budget", "100")
    logger.add_experiment_attribute("values", "f - f_opt")
    optimum = ioh.RealSolution([0.0, 0.0], F_OPT)
    for key in ("r0", "r1"):
        logger.attach_problem(ioh.MetaData(fn.id, fn.instance, fn.name, 2, ioh.OptimizationType.MIN))
        e, f = run_rows(pd.DataFrame(TRACES[key], columns=["evaluation", "best"]), 200, 100, F_OPT)
        for i, (a, b) in enumerate(zip(e, f)):  # the closing row at the budget is no improvement
            logger.call(ioh.LogInfo(int(a), b, b, b, b, b, b, [], [], [], optimum, bool(i == 0 or b < f[i - 1])))
        logger.reset()
    logger.close()
    name = f"IOHprofiler_f3_{fn.name}"
    theirs = tmp_path / "ioh" / "ga"
    mine = tmp_path / "mine" / "ioh" / "ga"
    dat = f"data_f3_{fn.name}/IOHprofiler_f3_DIM2.dat"
    assert (mine / dat).read_text() == (theirs / dat).read_text()
    a, b = json.loads((mine / f"{name}.json").read_text()), json.loads((theirs / f"{name}.json").read_text())
    for run in b["scenarios"][0]["runs"]:
        assert run["evals"] == 0  # what the logger cannot know without an ioh problem's state
    for run in a["scenarios"][0]["runs"]:
        run["evals"] = 0
    a["suite"] = b["suite"]  # the logger has no suite without an ioh suite object
    assert a == b
