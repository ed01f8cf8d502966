"""Black-box problems for the tests: failing, slow and counting objectives (importable by name)."""

from __future__ import annotations

import time

import numpy as np
from pymoo.core.problem import Problem


class Flaky(Problem):
    """Kubota's domain; rows with x < -0.5 return NaN, rows with x > 0.3 raise."""

    def __init__(self) -> None:
        super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0)

    def _evaluate(self, X, out, *args, **kwargs):
        if (X[:, 0] > 0.3).any():
            raise RuntimeError("solver diverged")
        f = (X**2).sum(axis=1)
        out["F"] = np.where(X[:, 0] < -0.5, np.nan, f)[:, None]


class Slow(Problem):
    """A sphere that sleeps ``delay`` seconds per batch (to be killed mid-run)."""

    def __init__(self, delay: float = 0.05) -> None:
        super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0)
        self.delay = delay

    def _evaluate(self, X, out, *args, **kwargs):
        time.sleep(self.delay)
        out["F"] = (X**2).sum(axis=1)[:, None]
