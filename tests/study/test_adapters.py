"""Adapters: every objective call counted by the engine, stopping at the budget, and the same
numbers as the library's own loop (DEAP eaSimple, pymoo minimize) from the same seed."""

from __future__ import annotations

import random

import numpy as np
import pytest
from pymoo.core.problem import Problem

from evoplan.adapters import ADAPTERS, UnitCube, search_space
from evoplan.adapters.base import child_seed
from evoplan.adapters.deap_easimple import DeapEaSimpleConfig, make_toolbox
from evoplan.engine import RunState, Termination, run
from evoplan.evaluation import Evaluator
from evoplan.problem_factory import build_space, make_problem
from evoplan.space import Categorical, Integer, Real, Space


class Counted(Problem):
    """Rastrigin in 3-D that counts the rows it evaluates."""

    def __init__(self) -> None:
        super().__init__(n_var=3, n_obj=1, xl=-5.12, xu=5.12)
        self.rows = 0

    def _evaluate(self, X, out, *args, **kwargs):
        self.rows += len(X)
        out["F"] = (10 * X.shape[1] + (X**2 - 10 * np.cos(2 * np.pi * X)).sum(axis=1))[:, None]


def adapted(name: str, settings: dict, problem: Problem, seed: int = 5):
    cls, model = ADAPTERS[name]
    config = model.model_validate({"name": name, **settings})
    space = search_space(config, build_space(problem, 16))
    rng = np.random.default_rng(seed)
    return RunState(algorithm=cls(config, space.n_bits, rng), rng=rng), space


CASES = [("pymoo_ga", {"pop_size": 12}), ("pymoo_ga", {"pop_size": 12, "representation": "binary"}),
         ("pymoo_de", {"pop_size": 12}), ("pymoo_cmaes", {}), ("pymoo_pso", {"pop_size": 12}),
         ("deap_easimple", {"population": 12}), ("deap_easimple", {"population": 12, "representation": "real"})]


@pytest.mark.parametrize("name,settings", CASES)
def test_every_objective_call_is_counted_and_the_budget_stops_the_run(name, settings):
    problem = Counted()
    state, space = adapted(name, settings, problem)
    run(state, space, Evaluator(problem), Termination(evaluations=300))
    assert state.evaluations == problem.rows  # the engine's count is the objective's
    assert 300 <= state.evaluations < 300 + 20  # at most one batch over (CMA-ES starts with 20 samples)
    assert state.best_f == pytest.approx(min(row[2] for row in state.history))
    assert len(state.history) == state.algorithm.generation + 1


def test_cma_es_is_restarted_until_the_budget_is_spent():
    problem = make_problem("sphere", {"n_var": 2})
    state, space = adapted("pymoo_cmaes", {}, problem)
    run(state, space, Evaluator(problem), Termination(evaluations=4000))
    assert state.algorithm.restarts >= 1 and state.evaluations >= 4000


def test_deap_adapter_makes_the_populations_of_ea_simple():
    from deap import algorithms, tools

    problem = make_problem("kubota")
    space = build_space(problem, 16)  # the bits adapted() uses
    evaluator = Evaluator(problem)
    config = DeapEaSimpleConfig(population=16, cxpb=0.7, mutpb=0.3)
    state, _ = adapted("deap_easimple", config.model_dump(exclude={"name"}), problem, seed=9)
    run(state, space, evaluator, Termination(generations=6))

    tb = make_toolbox(config, space.n_bits)
    tb.register("evaluate", lambda ind: (float(evaluator(space.decode(np.array([ind], bool))).f[0]),))
    random.seed(child_seed(np.random.default_rng(9)))
    population = tb.population(n=16)
    hof = tools.HallOfFame(1)
    algorithms.eaSimple(population, tb, cxpb=0.7, mutpb=0.3, ngen=6, halloffame=hof, verbose=False)
    assert [list(ind) for ind in state.algorithm.population_] == [list(ind) for ind in population]
    assert state.best_f == hof[0].fitness.values[0]


def test_pymoo_adapter_matches_pymoo_minimize():
    from pymoo.algorithms.soo.nonconvex.de import DE
    from pymoo.optimize import minimize

    problem = make_problem("rastrigin", {"n_var": 3})
    space = build_space(problem, 16)
    cube = UnitCube(space)

    class OnCube(Problem):
        def __init__(self):
            super().__init__(n_var=3, n_obj=1, xl=0.0, xu=1.0)

        def _evaluate(self, U, out, *args, **kwargs):
            out["F"] = problem.evaluate(cube.decode(U))

    state, search = adapted("pymoo_de", {"pop_size": 10, "CR": 0.9, "F": 0.8}, problem, seed=4)
    run(state, search, Evaluator(problem), Termination(generations=7))
    seed = child_seed(np.random.default_rng(4))
    res = minimize(OnCube(), DE(pop_size=10, variant="DE/rand/1/bin", CR=0.9, F=0.8, seed=seed), ("n_gen", 8))
    assert state.best_f == pytest.approx(float(res.F[0]), rel=0, abs=0)
    assert state.evaluations == res.algorithm.evaluator.n_eval


def test_unit_cube_maps_reals_integers_and_choices_like_the_codec():
    space = Space([Real("x", -2.0, 2.0, 8), Integer("k", 1, 4), Categorical("c", ("a", "b", "c"))])
    X = UnitCube(space).decode(np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.5, 0.49, 0.5], [1.5, -1, 0.34]]))
    assert X.tolist() == [[-2.0, 1.0, 0.0], [2.0, 4.0, 2.0], [0.0, 2.0, 1.0], [2.0, 1.0, 1.0]]


def test_deap_settings_that_never_change_anything_are_refused():
    with pytest.raises(ValueError, match="cxpb and mutpb"):
        DeapEaSimpleConfig(cxpb=0, mutpb=0)


def test_deap_adapter_ignores_other_draws_from_the_global_generator():
    import sys
    import threading

    problem = make_problem("kubota")
    space = build_space(problem, 16)
    results = []
    switch = sys.getswitchinterval()
    sys.setswitchinterval(1e-5)  # let the other thread interleave with DEAP's own calls
    try:
        for noise in (False, True):
            stop = threading.Event()

            def draw():  # another thread of a worker (Dask's event loop) using the global generator
                while not stop.is_set():
                    random.random()

            thread = threading.Thread(target=draw) if noise else None
            if thread:
                thread.start()
            try:
                state, _ = adapted("deap_easimple", {"population": 30}, problem, seed=5)
                run(state, space, Evaluator(problem), Termination(generations=60))
            finally:
                stop.set()
                if thread:
                    thread.join()
            results.append([list(ind) for ind in state.algorithm.population_])
    finally:
        sys.setswitchinterval(switch)
    assert results[0] == results[1]


def test_deap_takes_pymoos_pop_size_through_minimize():
    import evoplan
    from evoplan.errors import ConfigError

    run_ = lambda **kw: evoplan.minimize("sphere", "deap_easimple", termination={"generations": 3}, seed=4, **kw)  # noqa: E731
    by_alias, by_name = run_(pop_size=9), run_(population=9)
    assert by_alias.history["evaluations"].iloc[0] == 9                  # the first population: 9 rows
    assert by_alias.history["evaluations"].tolist() == by_name.history["evaluations"].tolist()
    assert by_alias.F.tolist() == by_name.F.tolist() and by_alias.X.tolist() == by_name.X.tolist()
    assert run_(pop_size=9, population=9).history["evaluations"].iloc[0] == 9    # the same value twice: fine
    with pytest.raises(ConfigError) as bad:
        run_(pop_size=8, population=10)
    msg = str(bad.value)
    assert "\n" not in msg and "pop_size 8" in msg and "population 10" in msg
