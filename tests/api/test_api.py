"""The Python API: minimize on a pymoo Problem, a name and a config dict; Result; ask/tell."""

from __future__ import annotations

import json

import numpy as np
import pytest
from pymoo.core.mixed import MixedVariableGA
from pymoo.core.problem import Problem
from pymoo.optimize import minimize as pymoo_minimize
from pymoo.problems import get_problem

import evoplan
from evoplan.errors import ConfigError


def test_public_names():
    names = dir(evoplan)
    for name in ("minimize", "Result", "AskTell", "GA", "VEGA", "Space", "ToolpathProblem"):
        assert name in names
        assert getattr(evoplan, name) is not None


def test_minimize_pymoo_problem_result_fields_and_best_json(tmp_path):
    problem = get_problem("sphere", n_var=3)
    r = evoplan.minimize(problem, "ga", termination={"evaluations": 400}, seed=4, bits=16,
                         population=20, out=tmp_path / "run")
    assert set(r.x) == {"x1", "x2", "x3"}
    f_x = problem.evaluate(np.array([list(r.x.values())]))[0, 0]
    assert r.f == pytest.approx(f_x, rel=1e-9, abs=1e-12)  # f is the objective of x
    assert r.f < 0.5  # sphere on [-5.12, 5.12]^3: the start averages ~26
    assert r.genotype.dtype == bool and r.genotype.shape == (48,)
    assert list(r.history.columns[:3]) == ["generation", "evaluations", "best"]
    assert r.history["evaluations"].iloc[-1] == r.evaluations and 400 <= r.evaluations < 420
    assert r.failures == 0
    best = json.loads((tmp_path / "run" / "best.json").read_text())
    assert best["problem"] == "pymoo.problems.single.sphere:Sphere"  # the real problem, not a placeholder
    assert best["variables"] == r.x and best["evaluations"] == r.evaluations


def test_minimize_by_name_equals_the_config_dict_run():
    a = evoplan.minimize("kubota", "vega", termination=8, seed=3, population=12, virus={"count": 3})
    cfg = {"seed": 3, "problem": {"name": "kubota"}, "termination": {"generations": 8},
           "algorithm": {"name": "vega", "population": 12, "virus": {"count": 3}}}
    b = evoplan.minimize(cfg)
    assert a.algorithm == b.algorithm == "vega" and a.problem == b.problem == "kubota"
    assert a.f == b.f and a.x == b.x and a.evaluations == b.evaluations
    assert a.generations == 8 and len(a.history) == 9
    c = evoplan.minimize(cfg, "ga", population=12)  # arguments override the dict
    assert c.algorithm == "ga"


def test_failures_are_counted():
    class Flaky(Problem):
        def __init__(self):
            super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0)

        def _evaluate(self, X, out, *args, **kwargs):
            f = (X**2).sum(axis=1)
            out["F"] = np.where(X[:, 0] > 0.5, np.nan, f)

    r = evoplan.minimize(Flaky(), "ga", termination=5, seed=1, bits=8, population=10)
    assert r.failures > 0 and r.failure_messages and r.x["x1"] <= 0.5


def test_bad_settings_are_one_line_errors():
    with pytest.raises(ConfigError, match=r"<python>: algorithm.population"):
        evoplan.minimize("kubota", "ga", population=1)
    with pytest.raises(ConfigError, match="unknown problem"):
        evoplan.minimize("no_such_problem")


def test_ask_tell_vega_own_loop():
    opt = evoplan.AskTell("kubota", "vega", seed=2, population=10, virus={"count": 3})
    kubota = evoplan.make_problem("kubota")
    told = 0
    while opt.generation < 6:
        X = opt.ask()
        assert X.shape[1] == 2 and np.all(np.abs(X) <= 2.0)
        f = kubota.evaluate(X)[:, 0]
        told += len(f)
        opt.tell(f)
    assert opt.evaluations == told and opt.best_f < np.inf
    x = np.array([[opt.best_x["x"], opt.best_x["y"]]])
    assert kubota.evaluate(x)[0, 0] == pytest.approx(opt.best_f, abs=1e-6)


def test_ask_tell_on_a_space():
    space = evoplan.Space([evoplan.Real("a", 0.0, 1.0, 12), evoplan.Categorical("c", ("p", "q", "r"))])
    opt = evoplan.AskTell(space, "ga", seed=0, population=8)
    for _ in range(10):
        X = opt.ask()
        opt.tell((X[:, 0] - 0.3) ** 2 + (X[:, 1] != 2))
    assert opt.best_x["c"] == "r" and abs(opt.best_x["a"] - 0.3) < 0.1


def test_toolpath_vars_run_under_pymoo_mixed_variable_ga():
    problem = evoplan.ToolpathProblem(normalization={"machining_error": [0, 1], "cc_count": [0, 2000]})
    assert list(problem.vars) == ["tool", "stepover", "lead", "tilt", "step"]
    assert problem.vars["tool"].options == list(range(1, 10))  # tool ids, as the CLI and APT use
    res = pymoo_minimize(problem, MixedVariableGA(pop_size=6), ("n_gen", 2), seed=1, verbose=False)
    assert res.X["tool"] in range(1, 10)
    by_id = problem.evaluate_params(dict(res.X))["objective"]
    assert res.F[0] == pytest.approx(by_id)  # the dict row with tool id = the named evaluation


def test_zoned_problem_declares_vars():
    from tests.choi_zoning import choi_zoning

    problem = evoplan.ToolpathProblem(**choi_zoning(mesh=(12, 12), gene_range=(1, 2)))
    assert list(problem.vars) == ["tool", "zones"]
    row = problem.criteria([{"tool": 4, "zones": 1}])
    assert row["eq4_total"][0] == problem.criteria([[3, 1]])["eq4_total"][0]
