"""Problems for the study tests and the speed-up measurement (importable as ``tests.study.blackboxes``)."""

from __future__ import annotations

import time

from pymoo.core.problem import Problem


class Sleepy(Problem):
    """A sphere on ``[-1, 1]^n_var`` that sleeps ``delay`` seconds per row: an expensive black box."""

    def __init__(self, n_var: int = 2, delay: float = 0.1) -> None:
        super().__init__(n_var=n_var, n_obj=1, xl=-1.0, xu=1.0)
        self.delay = delay

    def _evaluate(self, X, out, *args, **kwargs):
        time.sleep(self.delay * len(X))
        out["F"] = (X**2).sum(axis=1)[:, None]
