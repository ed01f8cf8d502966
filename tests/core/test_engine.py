import numpy as np
import pytest

from evoplan.config import parse_config
from evoplan.engine import Checkpointer, run
from evoplan.runner import prepare


class Stop(Exception):
    pass


def prepared(algorithm="vega", problem="kubota", **termination):
    cfg = parse_config({
        "seed": 7,
        "problem": {"name": problem},
        "algorithm": {"name": algorithm, "population": 12},
        "termination": termination or {"generations": 15},
    })
    return prepare(cfg)


def history(state):
    return [row[:-1] for row in state.history]  # all but wall seconds


@pytest.mark.parametrize("algorithm", ["ga", "vega"])
def test_same_seed_same_history_other_seed_other_history(algorithm):
    p = prepared(algorithm)
    a = run(p.new_state(), p.space, p.evaluator, p.termination)
    b = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert history(a) == history(b) and a.best_f == b.best_f
    q = prepare(p.config.model_copy(update={"seed": 8}))
    c = run(q.new_state(), q.space, q.evaluator, q.termination)
    assert history(c) != history(a)


@pytest.mark.parametrize("algorithm", ["ga", "vega"])
def test_resume_after_interruption_gives_the_identical_result(tmp_path, algorithm):
    p = prepared(algorithm, generations=20)
    full = run(p.new_state(), p.space, p.evaluator, p.termination)

    path = tmp_path / "checkpoint.npz"

    def crash_at_9(state):
        if state.algorithm.generation == 9:
            raise Stop

    with pytest.raises(Stop):
        run(p.new_state(), p.space, p.evaluator, p.termination, Checkpointer(path, every_generations=4), crash_at_9)
    state = Checkpointer.load(path, p.new_state())  # data loaded into a fresh state
    assert state.algorithm.generation == 8  # the last checkpoint before the crash
    resumed = run(state, p.space, p.evaluator, p.termination, Checkpointer(path, every_generations=4))
    assert history(resumed) == history(full)
    assert resumed.best_f == full.best_f and np.array_equal(resumed.best_g, full.best_g)
    assert resumed.evaluations == full.evaluations


def test_every_evaluation_is_counted_including_infections():
    p = prepared("vega", generations=10)
    calls = []
    inner = p.evaluator

    def counting(X):
        calls.append(len(X))
        return inner(X)

    state = run(p.new_state(), p.space, counting, p.termination)
    assert state.evaluations == sum(calls)
    assert len(calls) > 11  # infections are evaluated in batches of their own
    assert state.history[-1][1] == state.evaluations


def test_termination_by_evaluations_target_and_seconds():
    p = prepared("vega", evaluations=500)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert state.stop_reason == "evaluations" and state.evaluations >= 500
    per_gen = np.diff([row[1] for row in state.history])
    assert state.evaluations - 500 < per_gen.max()  # stops within one generation of the budget

    p = prepared("ga", generations=10_000, target=0.05)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert state.stop_reason == "target" and state.best_f <= 0.05

    p = prepared("ga", seconds=0.2)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert state.stop_reason == "seconds" and 0.2 <= state.elapsed < 2


def test_failures_are_penalized_counted_and_the_run_goes_on():
    p = prepared("ga", problem="tests.blackboxes:Flaky", generations=10)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert state.algorithm.generation == 10
    assert state.failures > 0 and np.isfinite(state.best_f)
    assert any("solver diverged" in e for e in state.errors)
    assert any("non-finite" in e for e in state.errors)
    assert np.isinf(state.algorithm.f).sum() <= state.failures


def test_history_rows_are_consistent():
    p = prepared("ga", generations=12)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    rows = np.array([r[:-1] for r in state.history], dtype=float)
    gen, evals, best, mean, worst, std, failures, hits = rows.T
    assert gen.tolist() == list(range(13))
    # population 12, one elite not asked again; a repeated genotype is a cache hit, not evaluated
    assert (np.diff(evals + hits) == 11).all() and hits[-1] > 0
    assert (np.diff(best) <= 0).all() and (best <= mean).all() and (mean <= worst).all()


@pytest.mark.parametrize("name, params", [("rastrigin", {"n_var": 10}), ("ackley", {}), ("griewank", {}),
                                          ("rosenbrock", {}), ("schwefel", {}), ("sphere", {"n_var": 3})])
def test_pymoo_test_problems_run_by_name(name, params):
    cfg = parse_config({"problem": {"name": name, "params": params, "bits": 16},
                        "algorithm": {"name": "ga", "population": 30}, "termination": {"generations": 30}})
    p = prepare(cfg)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    first_mean = state.history[0][3]
    assert p.space.n_var == p.evaluator.problem.n_var
    assert state.best_f < first_mean  # it optimizes


def test_constrained_pymoo_problem_is_penalized():
    cfg = parse_config({"problem": {"name": "g1", "bits": 12}, "algorithm": {"name": "ga", "population": 40},
                        "termination": {"generations": 40}})
    p = prepare(cfg)
    X = np.zeros((1, 13))
    X[0, 9:12] = 100.0  # 2 x1 + 2 x2 + x10 + x11 - 10 = 190 > 0: infeasible
    raw = p.evaluator.problem.evaluate(X, return_as_dictionary=True)
    violation = np.maximum(raw["G"], 0).sum()
    assert violation > 0
    assert p.evaluator(X).f[0] == pytest.approx(raw["F"][0, 0] + 1e6 * violation)
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert np.isfinite(state.best_f)


def test_gray_coding_and_per_variable_bits():
    cfg = parse_config({"problem": {"name": "kubota", "gray": True, "variables": {"x": {"bits": 10, "low": -0.5}}},
                        "algorithm": {"name": "vega"}, "termination": {"generations": 5}})
    p = prepare(cfg)
    assert p.space.n_bits == 33 and p.space.gray
    assert p.space.variables[0].low == -0.5 and p.space.variables[0].high == 1.0
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert np.isfinite(state.best_f)


def test_evaluation_backend_gives_the_serial_numbers(tmp_path):
    from evoplan.runner import execute

    base = {"seed": 4, "problem": {"name": "tests.blackboxes:Slow", "params": {"delay": 0.0}},
            "algorithm": {"name": "ga", "population": 10}, "termination": {"generations": 4}}
    serial = execute(prepare(parse_config(base)), tmp_path / "serial", progress=False)
    parallel_cfg = parse_config({**base, "evaluation": {"backend": "processes", "workers": 2}})
    parallel = execute(prepare(parallel_cfg), tmp_path / "processes", progress=False)
    assert history(parallel) == history(serial) and parallel.best_f == serial.best_f


def test_adapters_run_through_the_same_engine(tmp_path):
    from evoplan.runner import best_record, execute

    cfg = parse_config({"seed": 3, "problem": {"name": "kubota"}, "algorithm": {"name": "pymoo_de", "pop_size": 10},
                        "termination": {"evaluations": 300}})
    p = prepare(cfg)
    state = execute(p, tmp_path / "de", progress=False)
    assert 300 <= state.evaluations < 310 and state.stop_reason == "evaluations"
    record = best_record(p, state)
    assert record["genotype"] is None and set(record["variables"]) == {"x", "y"}
    assert abs(record["variables"]["x"]) <= 1 and record["objective"] == state.best_f
