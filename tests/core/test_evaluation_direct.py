"""Batches handed to a problem's ``_evaluate`` directly give what pymoo's ``evaluate`` gives."""

import numpy as np
import pytest
from pymoo.core.problem import ElementwiseProblem, Problem

from evoplan.evaluation import Evaluator, ObjectiveShapeError, direct_evaluation
from problems.benchmarks import Kubota


class Shaped(Problem):
    """One objective set as ``(n,)``, ``(n, 1)`` or a list of columns, and a cost."""

    def __init__(self, form):
        super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0)
        self.form = form

    def _evaluate(self, X, out, *args, **kwargs):
        f = np.sin(X[:, 0]) * X[:, 1] ** 2
        out["F"] = {"flat": f, "column": f[:, None], "list": [f], "int": np.floor(10 * f).astype(int)}[self.form]
        out["cost"] = (X[:, 0] > 0).astype(int)


class WrongShape(Shaped):
    def _evaluate(self, X, out, *args, **kwargs):
        out["F"] = np.zeros((len(X), 3))


class OwnEvaluate(Shaped):
    def evaluate(self, X, *args, **kwargs):
        return super().evaluate(X, *args, **kwargs)


class Elementwise(ElementwiseProblem):
    def __init__(self):
        super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0)

    def _evaluate(self, x, out, *args, **kwargs):
        out["F"] = x.sum()


class Constrained(Shaped):
    def __init__(self):
        super().__init__("flat")
        self.n_ieq_constr = 1


X = np.random.default_rng(0).uniform(-1, 1, (57, 2))


def _through_pymoo(problem):
    ev = Evaluator(problem)
    ev.direct = False
    return ev(X)


@pytest.mark.parametrize("problem", [Kubota(), Shaped("flat"), Shaped("column"), Shaped("list"), Shaped("int")],
                         ids=["kubota", "flat", "column", "list", "int"])
def test_direct_values_and_costs_equal_pymoos(problem):
    ev = Evaluator(problem)
    assert ev.direct
    got, expected = ev(X), _through_pymoo(problem)
    assert got.f.dtype == expected.f.dtype == float
    assert np.array_equal(got.f, expected.f) and np.array_equal(got.failed, expected.failed)
    assert (got.cost is None) == (expected.cost is None)
    if got.cost is not None:
        assert np.array_equal(got.cost, expected.cost)


def test_the_returned_values_do_not_alias_the_problems_array():
    class Buffer(Shaped):
        def _evaluate(self, X, out, *args, **kwargs):
            self.last = out["F"] = np.ones(len(X))

    p = Buffer("flat")
    result = Evaluator(p)(X)
    p.last[:] = 5.0
    assert (result.f == 1.0).all()


def test_a_wrong_shape_is_still_pymoos_one_line_error():
    with pytest.raises(ObjectiveShapeError, match=r"expected shape \(57, 1\) but provided \(57, 3\)"):
        Evaluator(WrongShape("flat"))(X)


def test_problems_that_change_pymoos_path_go_through_it():
    assert not direct_evaluation(OwnEvaluate("flat"))
    assert not direct_evaluation(Elementwise())
    assert not direct_evaluation(Constrained())
    p = Shaped("flat")
    p.callback = lambda X, out: None
    assert not direct_evaluation(p)
