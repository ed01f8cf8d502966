"""BBOB through ioh, and the study files shipped in runs/ (validated and expanded, not run)."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from evoplan.problem_factory import make_problem
from evoplan.study.bbob import TARGET, resolve_problem_name
from evoplan.study.cell import optimum
from evoplan.study.config import load_study
from evoplan.study.grid import build_grid, cell_seed, reference_levels

from .conftest import ROOT


def test_bbob_names_resolve_to_the_ioh_wrapper_with_a_known_optimum():
    name, params = resolve_problem_name("bbob-f3-i2", {"n_var": 5})
    assert (name, params) == (TARGET, {"function": 3, "instance": 2, "n_var": 5})
    assert resolve_problem_name("rastrigin", {"n_var": 2}) == ("rastrigin", {"n_var": 2})
    problem = make_problem(name, params)
    import ioh

    direct = ioh.get_problem(3, instance=2, dimension=5, problem_class=ioh.ProblemClass.BBOB)
    x = np.random.default_rng(0).uniform(-5, 5, (4, 5))
    assert problem.evaluate(x)[:, 0] == pytest.approx([direct(list(row)) for row in x])
    assert optimum(problem) == pytest.approx(direct.optimum.y)
    again = pickle.loads(pickle.dumps(problem))  # ioh objects do not pickle; the wrapper does
    assert again.evaluate(x)[:, 0] == pytest.approx(problem.evaluate(x)[:, 0])


def test_a_bbob_function_number_out_of_range_is_refused():
    with pytest.raises(ValueError, match="1..24"):
        make_problem(TARGET, {"function": 25})


def test_compare_benchmarks_is_the_issue_grid():
    study = load_study(ROOT / "runs" / "compare_benchmarks.yaml")
    cells = build_grid(study)
    assert len(cells) == 7 * 11 * 30
    assert {c.algorithm for c in cells} == {"ga", "vega", "pymoo_ga", "pymoo_de", "pymoo_cmaes", "pymoo_pso",
                                            "deap_easimple"}
    assert {(c.problem, c.dimension) for c in cells} == {("kubota", 2)} | {
        (p, d) for p in ("rastrigin", "ackley", "griewank", "rosenbrock", "schwefel") for d in (2, 10)}
    assert {c.budget for c in cells if c.dimension == 2} == {2000} and {c.budget for c in cells if c.dimension == 10} == {10000}
    # common random numbers: repetition r on a problem has one seed whatever the algorithm
    seeds = {}
    for c in cells:
        seeds.setdefault((c.problem, c.dimension, c.repetition), set()).add(c.seed)
    assert all(len(s) == 1 for s in seeds.values()) and len({next(iter(s)) for s in seeds.values()}) == len(seeds)


def test_fountas_study_is_table_1_one_factor_at_a_time():
    study = load_study(ROOT / "runs" / "fountas_viral_parameters.yaml")
    cells = build_grid(study)
    assert len(cells) == 16 * 30
    levels = {}
    for c in cells:
        levels.setdefault(c.factor, set()).add(c.level)
        assert c.run["algorithm"]["population"] == 20 and c.run["termination"]["generations"] == 50
    assert levels == {"virus.count": {"2", "5", "7", "10"}, "virus.max_length": {"10", "20", "30", "40"},
                      "virus.infectivity_force": {"0.001", "0.01", "0.1", "1.0"},
                      "virus.infection_rate": {"0.1", "0.4", "0.7", "1.0"}}
    assert reference_levels(study) == {"virus.count": "7", "virus.max_length": "40",
                                       "virus.infectivity_force": "0.001", "virus.infection_rate": "0.7"}
    one = next(c for c in cells if c.factor == "virus.count" and c.level == "2")
    assert one.run["algorithm"]["virus"]["count"] == 2 and one.run["algorithm"]["virus"]["max_length"] == 40


def test_overhead_study_loads():
    cells = build_grid(load_study(ROOT / "runs" / "overhead.yaml"))
    assert {c.run["termination"]["generations"] for c in cells} == {200}


def test_seeds_depend_on_the_study_seed_problem_dimension_and_repetition_only():
    assert cell_seed(1, "kubota", 2, 0) == cell_seed(1, "kubota", 2, 0)
    assert len({cell_seed(1, "kubota", 2, 0), cell_seed(2, "kubota", 2, 0), cell_seed(1, "rastrigin", 2, 0),
                cell_seed(1, "kubota", 10, 0), cell_seed(1, "kubota", 2, 1)}) == 5
