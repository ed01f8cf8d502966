"""BBOB functions (COCO's noiseless suite) through IOHprofiler's ``ioh``, as a pymoo problem.

A study names them ``bbob-f<k>`` or ``bbob-f<k>-i<instance>`` (``k`` in 1..24, instance 1 by
default); :func:`resolve_problem_name` turns such a name into ``evoplan.study.bbob:BBOB`` and
its parameters, so a run only ever needs the ``module:Class`` form that
:func:`evoplan.problem_factory.make_problem` knows. The domain is ``[-5, 5]^d``; the optimum
value of the instance is known, so precisions ``f - f_opt`` are exact.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np
from pymoo.core.problem import Problem

TARGET = "evoplan.study.bbob:BBOB"
_NAME = re.compile(r"^bbob-f(\d+)(?:-i(\d+))?$", re.IGNORECASE)


def resolve_problem_name(name: str, params: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    """``bbob-f3`` -> ``(TARGET, {function: 3, instance: 1, **params})``; other names unchanged."""
    m = _NAME.match(name)
    if not m:
        return name, dict(params)
    return TARGET, {"function": int(m.group(1)), "instance": int(m.group(2) or 1), **params}


class BBOB(Problem):
    """BBOB function ``function`` (1..24), ``instance``, in ``n_var`` dimensions (ioh's C++ code).

    The ioh object does not pickle; it is rebuilt on demand (after unpickling on a worker).
    """

    def __init__(self, function: int = 1, instance: int = 1, n_var: int = 2) -> None:
        if not 1 <= int(function) <= 24:
            raise ValueError(f"BBOB functions are numbered 1..24, got {function}")
        super().__init__(n_var=int(n_var), n_obj=1, xl=-5.0, xu=5.0, vtype=float)
        self.function, self.instance = int(function), int(instance)
        self._ioh = None
        self.optimum = float(self.ioh.optimum.y)

    @property
    def ioh(self):
        if self._ioh is None:
            from ..extras import require

            ioh = require("ioh", "bbob", "BBOB problems")

            self._ioh = ioh.get_problem(self.function, instance=self.instance, dimension=self.n_var,
                                        problem_class=ioh.ProblemClass.BBOB)
        return self._ioh

    def _evaluate(self, X, out, *args, **kwargs):
        out["F"] = np.asarray(self.ioh(np.asarray(X, dtype=float).tolist()), dtype=float).reshape(-1, 1)

    def _calc_pareto_front(self, *args, **kwargs):
        return np.array([[self.optimum]])

    def __getstate__(self):
        state = dict(super().__getstate__())  # pymoo may return __dict__ itself
        state["_ioh"] = None
        return state
