"""Multi-fidelity screening (``simulation.screening``): the analytic criteria choose which
plans of a batch the cut simulation judges; the best plan is always a simulated one, the
budget counts simulations, and a screen that simulates everything is the plain run."""

from types import SimpleNamespace

import numpy as np
import pytest

import evoplan
from evoplan.config import parse_config
from evoplan.errors import ConfigError
from evoplan.problems.toolpath.criteria.screening import Screening
from evoplan.problems.toolpath.problem import ToolpathProblem
from evoplan.runner import prepare

NORM = {"machining_error": [0, 0.5], "cc_count": [0, 1000]}
GRID = 2.0  # mm: a coarse simulation keeps each run to a few seconds


def problem(screening=None, grid=GRID):
    sim = {"grid_mm": grid} | ({} if screening is None else {"screening": screening})
    return ToolpathProblem(criteria="simulated", simulation=sim, normalization=NORM)


def ga(pr, evaluations, seed=3):
    return evoplan.minimize(pr, "ga", {"evaluations": evaluations}, seed=seed, population=12)


class FakeProblem:
    """Genes (tool, stepover, row): analytic objective stepover / 100, simulated objective
    given per row; records the rows simulated."""

    def __init__(self, simulated):
        self.simulated_values = np.asarray(simulated, float)
        self.objectives = None
        self.genes = SimpleNamespace(free=("tool", "stepover", "row"))
        self.xl, self.xu = np.array([0.0, 0.0, 0.0]), np.array([1.0, 100.0, 10.0])
        self.weights, self.norm_bounds = {"machining_error": 1.0}, {"machining_error": (0.0, 1.0)}
        self.asked = []

    def analytic(self, X):
        return {"machining_error": X[:, 1] / 100.0, "cc_count": np.zeros(len(X))}, {"row": X[:, 2]}

    def simulate_rows(self, genes, rows):
        rows = list(rows)
        self.asked += [int(genes["row"][i]) for i in rows]
        return {"machining_error": self.simulated_values[genes["row"][rows].astype(int)]}


def fake_batch(stepover):
    return np.column_stack([np.zeros(len(stepover)), stepover, np.arange(len(stepover))])


def test_the_fraction_and_the_elite_are_simulated_and_the_rest_is_predicted_above_the_best():
    # analytic 0.1 .. 0.8 ranks rows 0..7; the simulation finds row 6 best (0.05) and rows 0, 1 at 0.3
    sim = np.array([0.30, 0.30, 0.90, 0.90, 0.90, 0.90, 0.05, 0.90])
    fake = FakeProblem(sim)
    X = fake_batch(np.arange(1, 9) * 10.0)
    screen = Screening({"fraction": 0.25, "correction": "offset"})
    F, cost = screen.evaluate(fake, X)
    # round 1: rows 0, 1 (the best quarter by the analytic value); residuals 0.2 and 0.1 ->
    # offset 0.15, best 0.3: rows with 0.1 k + 0.15 <= 0.3 are none of the others
    assert fake.asked == [0, 1]
    assert cost.tolist() == [1, 1, 0, 0, 0, 0, 0, 0]
    assert F[:2, 0].tolist() == [0.3, 0.3]
    np.testing.assert_allclose(F[2:, 0], np.arange(3, 9) / 10 + 0.15)
    assert (F[cost == 0, 0] > screen.best).all()
    assert (screen.simulations, screen.screened) == (2, 6)
    # a batch predicted under the best: its best third is simulated (0.5: residual 0.49, the
    # offset becomes 0.2), then the other two are still predicted under 0.3 (0.22, 0.23): the
    # elite, simulated in a second round, which finds 0.01
    fake.simulated_values = np.array([0.5, 0.2, 0.01])
    fake.asked = []
    F, cost = screen.evaluate(fake, fake_batch(np.array([1.0, 2.0, 3.0])))
    assert fake.asked == [0, 1, 2] and cost.tolist() == [1, 1, 1]
    assert F[:, 0].tolist() == [0.5, 0.2, 0.01] and screen.best == 0.01


def learned(correction, X, analytic, simulated):
    """A screen of ``correction`` (one neighbour) that has learned the simulated rows X of a
    FakeProblem, and the problem."""
    fake = FakeProblem(simulated)
    screen = Screening({"correction": correction, "neighbours": 1})
    zeros = np.zeros(len(X))
    screen.learn(fake, X, {"machining_error": np.asarray(analytic, float), "cc_count": zeros},
                 {"machining_error": np.asarray(simulated, float)})
    return screen, fake


def predicted(screen, fake, X, analytic):
    crit = {"machining_error": np.asarray(analytic, float), "cc_count": np.zeros(len(X))}
    return screen.predicted(fake, X, crit)


def test_nearest_correction_uses_the_residual_of_the_nearest_plan_with_the_same_tool():
    # tool 0 at step-over 10: analytic 0.1, simulated 0.6 (+0.5); tool 1 at 90: 0.9 -> 0.4 (-0.5)
    screen, fake = learned("nearest", np.array([[0.0, 10.0, 0.0], [1.0, 90.0, 1.0]]), [0.1, 0.9], [0.6, 0.4])
    X = np.array([[0.0, 85.0, 0.0], [1.0, 85.0, 0.0], [2.0, 50.0, 0.0]])
    # tool 0: its one pair (+0.5) however far; tool 1: -0.5; tool 2: no pair, the median 0
    np.testing.assert_allclose(predicted(screen, fake, X, [1.0, 1.0, 1.0]), [1.5, 0.5, 1.0])


def test_ratio_correction_scales_the_simulated_criteria_by_the_nearest_plans_ratio():
    from evoplan.problems.toolpath.criteria.screening import RATIO_FLOOR as e
    # tool 0: the simulation finds half the analytic deviation (0.1 of 0.2)
    screen, fake = learned("ratio", np.array([[0.0, 20.0, 0.0]]), [0.2], [0.1])
    X = np.array([[0.0, 40.0, 0.0], [1.0, 40.0, 0.0]])
    scale = (0.1 + e) / (0.2 + e)
    # a tool-0 plan of analytic 0.4 is predicted at 0.2 (a residual would give 0.3); tool 1
    # has no pair yet and takes the median ratio of every pair, the same one here
    expect = (0.4 + e) * scale - e
    np.testing.assert_allclose(predicted(screen, fake, X, [0.4, 0.4]), [expect, expect])
    assert abs(expect - 0.2) < 2e-3
    # a tool-1 pair that the analytic model got right: tool 1 is now predicted as analytic
    screen.learn(fake, np.array([[1.0, 30.0, 1.0]]),
                 {"machining_error": np.array([0.3]), "cc_count": np.zeros(1)},
                 {"machining_error": np.array([0.3])})
    np.testing.assert_allclose(predicted(screen, fake, X, [0.4, 0.4]), [expect, 0.4])


def test_ratio_correction_predicts_the_analytic_value_before_the_first_pair():
    fake = FakeProblem(np.zeros(2))
    screen = Screening({"correction": "ratio"})
    X = fake_batch(np.array([30.0, 70.0]))
    np.testing.assert_array_equal(predicted(screen, fake, X, [0.3, 0.7]), [0.3, 0.7])


def test_a_screened_run_returns_a_simulated_best_and_counts_simulations():
    pr = problem({"fraction": 0.25})
    r = ga(pr, 30)
    screen = pr.simulated.screening
    assert screen.screened > screen.simulations > 0  # most plans were only predicted
    assert r.evaluations == screen.simulations  # the budget counts simulations
    assert 30 <= r.evaluations < 30 + 12
    assert r.history["evaluations"].iloc[-1] == r.evaluations
    # the best is the simulated objective of its plan, as a plain simulated problem gives it
    check = problem().evaluate_params(r.x)
    assert r.f == check["objective"]
    assert r.f == screen.best


def test_a_screen_that_simulates_every_plan_is_the_plain_simulated_run_bit_for_bit():
    plain, full = ga(problem(), 24), ga(problem({"fraction": 1.0}), 24)
    assert plain.evaluations == full.evaluations
    assert plain.f == full.f and plain.x == full.x
    cols = ["generation", "evaluations", "best", "mean", "worst", "std", "failures", "cache_hits"]
    assert plain.history[cols].equals(full.history[cols])


RUN = {"problem": {"name": "toolpath", "params": {"criteria": "simulated", "normalization": NORM,
                                                   "simulation": {"grid_mm": GRID, "screening": {}}}},
       "algorithm": {"name": "ga", "population": 4}, "termination": {"generations": 1}}


@pytest.mark.parametrize("screening, message", [
    ({"fraction": 0}, r"simulation.screening.fraction: expected a number in \(0, 1\], got 0"),
    ({"fraction": 1.5}, r"simulation.screening.fraction: expected a number in \(0, 1\]"),
    ({"correction": "gp"}, "simulation.screening.correction: expected ratio, nearest or offset, got 'gp'"),
    ({"neighbours": 0}, "simulation.screening.neighbours: expected a whole number >= 1"),
    ({"share": 0.2}, "simulation.screening.share: unknown setting"),
    (0.25, "simulation.screening: expected a mapping"),
])
def test_bad_screening_settings_are_one_line_errors(screening, message):
    run = {**RUN, "problem": {"name": "toolpath", "params": {
        "criteria": "simulated", "normalization": NORM,
        "simulation": {"grid_mm": GRID, "screening": screening}}}}
    with pytest.raises(ConfigError, match=message) as e:
        prepare(parse_config(run), "run.yaml")
    assert "\n" not in str(e.value)


def test_screening_needs_the_serial_backend_and_one_objective():
    parallel = {**RUN, "evaluation": {"backend": "processes", "workers": 2}}
    with pytest.raises(ConfigError, match="screening: needs evaluation.backend: serial"):
        prepare(parse_config(parallel), "run.yaml")
    multi = {**RUN, "problem": {"name": "toolpath", "params": {
        **RUN["problem"]["params"], "objectives": ["machining_error", "cc_count"]}},
        "algorithm": {"name": "nsga2", "pop_size": 4}}
    with pytest.raises(ConfigError, match="screening: ranks plans by one objective"):
        prepare(parse_config(multi), "run.yaml")


@pytest.mark.parametrize("correction", ["ratio", "nearest"])
def test_a_local_correction_simulates_the_best_plan_of_a_tool_not_simulated_yet(correction):
    # analytic ranks the tool-1 plans last; with no tool-1 pair their correction is a guess,
    # so the best-predicted tool-1 plan is simulated beside the best quarter
    fake = FakeProblem(np.full(8, 0.5))
    X = fake_batch(np.arange(1, 9) * 10.0)
    X[5:, 0] = 1.0  # rows 5, 6, 7 use tool 1
    screen = Screening({"fraction": 0.25, "correction": correction})
    _, cost = screen.evaluate(fake, X)
    assert fake.asked == [0, 1, 5] and cost.sum() == 3
    fake.asked = []
    _, cost = screen.evaluate(fake, X)  # both tools known now: the best quarter alone
    assert len(fake.asked) == 2 and cost.sum() == 2


def test_ratio_correction_of_an_objective_that_weighs_no_simulated_criterion_is_the_analytic_value():
    fake = FakeProblem(np.array([0.3, 0.3]))
    fake.weights, fake.norm_bounds = {"cc_count": 1.0}, {"cc_count": (0.0, 1.0)}
    screen = Screening({"correction": "ratio"})
    X = fake_batch(np.array([30.0, 70.0]))
    crit = {"machining_error": np.array([0.3, 0.7]), "cc_count": np.array([0.2, 0.4])}
    screen.learn(fake, X[:1], {k: v[:1] for k, v in crit.items()}, {"machining_error": np.array([0.1])})
    np.testing.assert_array_equal(screen.predicted(fake, X, crit), [0.2, 0.4])


@pytest.mark.parametrize("quantile", [0.5, None])
def test_a_batch_with_nothing_predicted_near_the_best_costs_no_simulation(quantile):
    # the simulation finds what the analytic model says: every prediction error is 0, so once
    # ten errors are known the margin is 0 and only plans predicted at the best are simulated
    fake = FakeProblem((np.arange(8) + 1) / 10)
    screen = Screening({"fraction": 0.25, "correction": "offset", "error_quantile": quantile})
    X = fake_batch((np.arange(8) + 1) * 10.0)
    for _ in range(5):  # two simulations a batch: ten errors
        screen.evaluate(fake, X)
    assert screen.best == 0.1 and len(fake.asked) == 10
    fake.asked = []
    F, cost = screen.evaluate(fake, fake_batch((np.arange(8) + 2) * 10.0))  # predicted 0.2 .. 0.9
    if quantile is None:  # the whole fraction, as before
        assert fake.asked == [0, 1] and cost.sum() == 2
    else:
        assert fake.asked == [] and cost.sum() == 0
        np.testing.assert_allclose(F[:, 0], (np.arange(8) + 2) / 10)
        assert screen.margin() == 0.0
    fake.asked = []
    _, cost = screen.evaluate(fake, fake_batch(np.array([5.0, 60.0])))  # 0.05: under the best
    assert fake.asked[0] == 0 and cost[0] == 1


@pytest.mark.parametrize("value", [0, 1.5, True, "half"])
def test_bad_error_quantiles_are_one_line_errors(value):
    run = {**RUN, "problem": {"name": "toolpath", "params": {
        "criteria": "simulated", "normalization": NORM,
        "simulation": {"grid_mm": GRID, "screening": {"error_quantile": value}}}}}
    with pytest.raises(ConfigError, match=r"simulation.screening.error_quantile: expected a number in \(0, 1\] or null") as e:
        prepare(parse_config(run), "run.yaml")
    assert "\n" not in str(e.value)
