"""Badly behaved black boxes for the fault tests (importable as ``tests.hardening.objectives``).

Each is a sphere on ``[-1, 1]^2`` that misbehaves on the rows whose first variable exceeds
``threshold``: a worker that dies, an evaluation that never returns, ``sys.exit`` in user
code. ``WrongShape`` returns three values per row where one is declared. ``Slow`` sleeps
``delay`` seconds per batch (a run that can be killed midway).
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from pymoo.core.problem import Problem


class _Sphere(Problem):
    def __init__(self, threshold: float = 0.5, delay: float = 0.0) -> None:
        super().__init__(n_var=2, n_obj=1, xl=-1.0, xu=1.0)
        self.threshold, self.delay = threshold, delay

    def bad(self, X) -> np.ndarray:
        return X[:, 0] > self.threshold

    def _evaluate(self, X, out, *args, **kwargs):
        if self.delay:
            time.sleep(self.delay)
        if self.bad(X).any():
            self.misbehave()
        out["F"] = (X**2).sum(axis=1)[:, None]

    def misbehave(self) -> None:
        pass


class Dies(_Sphere):
    def misbehave(self) -> None:
        os._exit(7)


class Hangs(_Sphere):
    def misbehave(self) -> None:
        time.sleep(600)


class Exits(_Sphere):
    def misbehave(self) -> None:
        sys.exit(1)


class Slow(_Sphere):
    """Well behaved, ``delay`` seconds per batch."""


class WrongShape(_Sphere):
    def _evaluate(self, X, out, *args, **kwargs):
        out["F"] = np.zeros((len(X), 3))


class Fails(_Sphere):
    """The reference for the others: the same rows fail, by returning NaN."""

    def _evaluate(self, X, out, *args, **kwargs):
        if self.delay:
            time.sleep(self.delay)
        out["F"] = np.where(self.bad(X), np.nan, (X**2).sum(axis=1))[:, None]
