"""Benchmark functions as batched pymoo problems.

Only Kubota's function is written here: the classic suite (sphere, Rastrigin, Ackley,
Griewank, Rosenbrock, Schwefel, Zakharov, ...) is pymoo's own, reached by name through
``pymoo.problems.get_problem`` (see ``evoplan.problem_factory``).
"""

from __future__ import annotations

import numpy as np
from pymoo.core.problem import Problem
from pymoo.core.variable import Real


class Kubota(Problem):
    """Fountas Eq. 13 (after Kubota et al. 1996), a multimodal function on ``[-1, 1]^2``.

    ``f(x, y) = x^2 + y^2 - 0.3 cos(3 pi x) - 0.4 cos(4 pi y) + 0.7``, minimum ``f(0, 0) = 0``.
    """

    def __init__(self) -> None:
        super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0, vtype=float)
        self.variables = {"x": Real(bounds=(-1.0, 1.0)), "y": Real(bounds=(-1.0, 1.0))}

    def _evaluate(self, X, out, *args, **kwargs):
        x, y = X[:, 0], X[:, 1]
        out["F"] = (
            x**2 + y**2 - 0.3 * np.cos(3 * np.pi * x) - 0.4 * np.cos(4 * np.pi * y) + 0.7
        )[:, None]

    def _calc_pareto_front(self):
        return 0.0

    def _calc_pareto_set(self):
        return np.zeros(2)
