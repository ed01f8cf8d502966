"""pymoo's conventions in the Python API, each checked against pymoo itself on the same call."""

from __future__ import annotations

import json

import numpy as np
import pytest
from pymoo.algorithms.moo.nsga2 import NSGA2
from pymoo.algorithms.soo.nonconvex.cmaes import CMAES
from pymoo.algorithms.soo.nonconvex.de import DE
from pymoo.algorithms.soo.nonconvex.ga import GA
from pymoo.algorithms.soo.nonconvex.nelder import NelderMead
from pymoo.algorithms.soo.nonconvex.pso import PSO
from pymoo.core.callback import Callback
from pymoo.operators.crossover.pntx import TwoPointCrossover
from pymoo.optimize import minimize as pymoo_minimize
from pymoo.problems import get_problem
from pymoo.termination.collection import TerminationCollection
from pymoo.termination.default import DefaultSingleObjectiveTermination
from pymoo.termination.max_eval import MaximumFunctionCallTermination
from pymoo.termination.max_gen import MaximumGenerationTermination
from pymoo.termination.max_time import TimeBasedTermination

import evoplan
from evoplan.api import run_config
from evoplan.config import parse_config
from evoplan.errors import ConfigError

RASTRIGIN = get_problem("rastrigin", n_var=5)


def pymoo_run(problem, algorithm, termination, **kwargs):
    return pymoo_minimize(problem, algorithm, termination, seed=1, **kwargs)


# --- termination ---------------------------------------------------------------------------

@pytest.mark.parametrize("termination", [("n_gen", 5), MaximumGenerationTermination(5)])
def test_n_gen_runs_as_many_generations_and_evaluations_as_pymoo(termination):
    ours = evoplan.minimize(RASTRIGIN, GA(pop_size=20), termination, seed=1, save_history=True)
    theirs = pymoo_run(RASTRIGIN, GA(pop_size=20), termination, save_history=True)
    assert len(ours.history) == len(ours.populations) == len(theirs.history) == 5
    assert ours.evaluations == theirs.algorithm.evaluator.n_eval == 100  # duplicates eliminated: all distinct
    assert [p.n_gen for p in ours.populations] == [a.n_gen for a in theirs.history]


@pytest.mark.parametrize("termination", [("n_evals", 600), MaximumFunctionCallTermination(600)])
def test_n_evals_stops_where_pymoo_stops(termination):
    ours = evoplan.minimize(RASTRIGIN, GA(pop_size=20), termination, seed=1)
    theirs = pymoo_run(RASTRIGIN, GA(pop_size=20), termination)
    assert ours.evaluations == theirs.algorithm.evaluator.n_eval == 600
    assert ours.stop_reason == "evaluations"


def test_time_fmin_and_collections_read_as_pymoo_defines_them():
    for spec in (("time", "00:01:05"), ("time", 65), TimeBasedTermination("00:01:05")):
        assert run_config("kubota", termination=spec)[0].termination.seconds == 65
    both = TerminationCollection(MaximumGenerationTermination(9), MaximumFunctionCallTermination(300),
                                 MaximumGenerationTermination(21))
    t = run_config("kubota", termination=both)[0].termination
    assert (t.generations, t.evaluations) == (8, 300)  # whichever first, as pymoo's collection
    t = run_config("kubota", termination=TerminationCollection(("n_gen", 5), ("fmin", 0.5)))[0].termination
    assert (t.generations, t.target) == (4, 0.5)


@pytest.mark.parametrize("spec, message", [
    (("n_gen", 1), r"give 2 or more"),
    (("n_gen", 2.5), r"whole number"),
    (("soo",), r"expected pymoo's \(name, value\)"),
    (("ftol", 1e-6), r"'ftol' has no evoplan equivalent"),
    (DefaultSingleObjectiveTermination(), r"DefaultSingleObjectiveTermination has no evoplan equivalent"),
    (MaximumFunctionCallTermination(), r"never stops"),
    (("fmin", 0.1), r"a target alone"),
    ("n_gen", r"expected a dict"),
])
def test_unsupported_terminations_are_one_line_errors(spec, message):
    with pytest.raises(ConfigError, match=message) as e:
        evoplan.minimize("kubota", "ga", spec)
    assert "\n" not in str(e.value) and str(e.value).startswith("<python>: termination")


# --- algorithm objects ---------------------------------------------------------------------

@pytest.mark.parametrize("obj, name, expected", [
    (GA(pop_size=16), "pymoo_ga", {"pop_size": 16, "eliminate_duplicates": True, "representation": "real"}),
    (DE(pop_size=15, CR=0.3, variant="DE/rand/1/bin"), "pymoo_de",
     {"pop_size": 15, "CR": 0.3, "variant": "DE/rand/1/bin"}),
    (CMAES(sigma=0.2), "pymoo_cmaes", {"sigma": 0.2, "pop_size": None, "restarts": 0}),
    (PSO(pop_size=12, w=0.7), "pymoo_pso", {"pop_size": 12, "w": 0.7, "c1": 2.0, "adaptive": True}),
])
def test_pymoo_algorithm_objects_run_through_their_adapter(obj, name, expected):
    config, _ = run_config(RASTRIGIN, obj)
    assert config.algorithm.name == name
    assert {k: getattr(config.algorithm, k) for k in expected} == expected
    r = evoplan.minimize(RASTRIGIN, obj, ("n_evals", 200), seed=2)
    assert r.algorithm == name and 200 <= r.evaluations and r.F[0] == r.f


def test_an_object_seed_is_the_run_seed_unless_one_is_given():
    assert run_config("kubota", GA(pop_size=10, seed=7))[0].seed == 7
    assert run_config("kubota", GA(pop_size=10, seed=7), seed=3)[0].seed == 3


def test_multi_objective_object_gives_pymoo_shaped_front():
    zdt = get_problem("zdt1", n_var=6)
    ours = evoplan.minimize(zdt, NSGA2(pop_size=20), ("n_gen", 6), seed=1)
    theirs = pymoo_run(zdt, NSGA2(pop_size=20), ("n_gen", 6))
    assert ours.algorithm == "nsga2" and ours.feasible
    assert ours.X.ndim == theirs.X.ndim == 2 and ours.X.shape[1] == theirs.X.shape[1] == 6
    assert ours.F.shape[1] == theirs.F.shape[1] == 2 and ours.CV.shape == (len(ours.F), 1)
    assert np.allclose(zdt.evaluate(ours.X), ours.F)


@pytest.mark.parametrize("obj, message", [
    (NelderMead(), r"pymoo's NelderMead has no evoplan adapter"),
    (GA(pop_size=10, crossover=TwoPointCrossover()), r"mating.crossover = TwoPointCrossover.*builds SBX"),
    (GA(pop_size=10, n_offsprings=4), r"n_offsprings = 4"),
])
def test_objects_the_adapters_cannot_reproduce_are_refused(obj, message):
    with pytest.raises(ConfigError, match=message) as e:
        evoplan.minimize(RASTRIGIN, obj, ("n_gen", 3))
    assert "\n" not in str(e.value)


# --- pop_size ------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["ga", "vega"])
def test_pop_size_is_population_for_ga_and_vega(name):
    a = evoplan.minimize("kubota", name, 4, seed=1, pop_size=12)
    b = evoplan.minimize("kubota", name, 4, seed=1, population=12)
    assert a.f == b.f and a.evaluations == b.evaluations
    yaml_like = {"problem": {"name": "kubota"}, "termination": {"generations": 2},
                 "algorithm": {"name": name, "pop_size": 9}}
    assert parse_config(yaml_like).algorithm.population == 9
    yaml_like["algorithm"]["population"] = 8
    with pytest.raises(ConfigError, match=r"algorithm: give population or pop_size, not both"):
        parse_config(yaml_like, "run.yaml")


# --- callback, verbose, save_history -------------------------------------------------------

class Count(Callback):
    def __init__(self):
        super().__init__()
        self.calls = []

    def notify(self, algorithm):
        self.calls.append(algorithm.n_gen)


def test_callback_runs_each_generation_as_pymoo_calls_its_own():
    seen = []
    r = evoplan.minimize(RASTRIGIN, GA(pop_size=20), ("n_gen", 6), seed=1,
                         callback=lambda state: seen.append((state.algorithm.generation + 1, state.evaluations)))
    count = Count()
    pymoo_run(RASTRIGIN, GA(pop_size=20), ("n_gen", 6), callback=count)
    assert [g for g, _ in seen] == count.calls == [1, 2, 3, 4, 5, 6]
    assert [e for _, e in seen] == list(r.history["evaluations"])


def test_verbose_prints_pymoo_columns_one_line_per_generation(capsys):
    evoplan.minimize(RASTRIGIN, GA(pop_size=20), ("n_gen", 4), seed=1, verbose=True)
    ours = capsys.readouterr().out.splitlines()
    pymoo_run(RASTRIGIN, GA(pop_size=20), ("n_gen", 4), verbose=True)
    theirs = capsys.readouterr().out.splitlines()
    assert len(ours) == len(theirs) == 3 + 4
    names = [c.strip() for c in ours[1].split("|")]
    assert names == ["n_gen", "n_eval", "f_avg", "f_min"]
    assert set(names) <= {c.strip() for c in theirs[1].split("|")}
    rows = [line.split("|") for line in ours[3:]]
    assert [int(r[0]) for r in rows] == [int(t.split("|")[0]) for t in theirs[3:]] == [1, 2, 3, 4]
    assert all(len(a) == len(b) for a, b in zip(ours[3], theirs[3]))  # same widths
    assert evoplan.minimize(RASTRIGIN, "ga", 2, pop_size=10).populations == []  # not saved by default


def test_save_history_keeps_decoded_populations():
    r = evoplan.minimize("kubota", "vega", 3, seed=2, pop_size=10, save_history=True)
    assert [p.n_gen for p in r.populations] == [1, 2, 3, 4]
    last = r.populations[-1]
    assert last.X.shape == (10, 2) and np.all(np.abs(last.X) <= 2.0)
    assert np.allclose(evoplan.make_problem("kubota").evaluate(last.X)[:, 0], last.F)
    assert last.n_eval == r.evaluations and last.F.min() >= r.f


# --- Result: X, F, CV, feasible, exec_time ---------------------------------------------------

def test_nothing_feasible_gives_none_as_pymoo():
    g1 = get_problem("g1")
    theirs = pymoo_run(g1, GA(pop_size=20), ("n_gen", 5))
    ours = evoplan.minimize(g1, GA(pop_size=20), ("n_gen", 5), seed=1)
    assert theirs.X is None and theirs.F is None and theirs.CV is None
    assert ours.X is None and ours.F is None and ours.CV is None and not ours.feasible
    assert ours.f > 1e3  # the engine's best is penalized: its x is not a solution


def test_feasible_result_has_pymoo_shapes_and_is_feasible(tmp_path):
    g1 = get_problem("g1")
    theirs = pymoo_run(g1, GA(pop_size=20), ("n_gen", 60))
    ours = evoplan.minimize(g1, GA(pop_size=20), ("n_gen", 60), seed=1, out=tmp_path / "run")
    assert ours.feasible and theirs.feas
    for name in ("X", "F", "CV"):
        assert getattr(ours, name).shape == getattr(theirs, name).shape
    out = g1.evaluate(ours.X[None, :], return_as_dictionary=True)
    assert (out["G"] <= 0).all() and ours.CV[0] == 0 == theirs.CV[0]
    assert out["F"][0, 0] == pytest.approx(ours.F[0], rel=1e-12)
    assert ours.F[0] >= ours.f - 1e-9  # the engine's penalized best is never worse
    best = json.loads((tmp_path / "run" / "best.json").read_text())
    assert ours.exec_time == pytest.approx(best["wall_seconds"], abs=1e-3) and ours.exec_time > 0


def test_unconstrained_result_is_the_best_point():
    r = evoplan.minimize(RASTRIGIN, "vega", ("n_gen", 4), seed=3, pop_size=10)
    assert r.X.shape == (5,) and r.F.shape == (1,) and r.CV.tolist() == [0.0] and r.feasible
    assert r.F[0] == r.f == pytest.approx(RASTRIGIN.evaluate(r.X[None, :])[0, 0])
    assert list(r.X) == pytest.approx(list(r.x.values()))


# --- AskTell and the cache -------------------------------------------------------------------

def own_loop(opt, problem, generations):
    told = 0
    while opt.generation < generations:
        X = opt.ask()
        told += len(X)
        opt.tell(problem.evaluate(X)[:, 0] if len(X) else [])
    return told


def test_ask_tell_counts_and_finds_what_minimize_does():
    kubota = evoplan.make_problem("kubota")
    opt = evoplan.AskTell("kubota", "vega", seed=1, pop_size=20)
    told = own_loop(opt, kubota, 30)
    r = evoplan.minimize("kubota", "vega", 30, seed=1, pop_size=20)
    assert opt.evaluations == told == r.evaluations
    assert opt.best_f == r.f and opt.best_x == r.x
    assert opt.history["evaluations"].tolist() == r.history["evaluations"].tolist()
    uncached = evoplan.AskTell("kubota", "vega", seed=1, pop_size=20, cache={"size": 0})
    assert own_loop(uncached, kubota, 30) == uncached.evaluations > r.evaluations


def test_ask_tell_takes_a_pymoo_object_and_pop_size():
    opt = evoplan.AskTell(RASTRIGIN, DE(pop_size=12, CR=0.5, variant="DE/rand/1/bin"), seed=4)
    assert opt.algorithm.config.name == "pymoo_de" and opt.algorithm.config.pop_size == 12
    own_loop(opt, RASTRIGIN, 3)
    r = evoplan.minimize(RASTRIGIN, DE(pop_size=12, CR=0.5, variant="DE/rand/1/bin"), 3, seed=4)
    assert opt.evaluations == r.evaluations and opt.best_f == r.f


def test_hooks_run_with_a_results_folder_too(tmp_path, capsys):
    count = Count()  # a pymoo Callback: notify() gets the state, read by evoplan's names
    count.notify = lambda state: count.calls.append(state.algorithm.generation + 1)
    r = evoplan.minimize("kubota", "ga", ("n_gen", 4), seed=1, pop_size=10, out=tmp_path / "run",
                         callback=count, verbose=True, save_history=True)
    assert count.calls == [1, 2, 3, 4] == [p.n_gen for p in r.populations]
    assert len(capsys.readouterr().out.splitlines()) == 3 + 4
    assert (tmp_path / "run" / "best.json").is_file() and r.feasible and r.X.shape == (2,)


def test_constrained_multi_objective_front_keeps_its_feasible_points_only():
    problem = get_problem("bnh")  # two objectives, two inequality constraints
    ours = evoplan.minimize(problem, NSGA2(pop_size=20), ("n_gen", 8), seed=1)
    theirs = pymoo_run(problem, NSGA2(pop_size=20), ("n_gen", 8))
    assert ours.feasible and theirs.X.shape[1] == ours.X.shape[1] == 2
    out = problem.evaluate(ours.X, return_as_dictionary=True)
    assert (out["G"] <= 0).all() and np.allclose(out["F"], ours.F) and ours.CV.shape == (len(ours.F), 1)
