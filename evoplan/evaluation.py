"""Evaluation of decoded batches with a pymoo problem: constraints, failures and counting.

A batch ``X: (n, d)`` is evaluated in one call. If that call raises, every row is evaluated on
its own so that one bad individual does not sink the others. A row that raises or returns a
non-finite value is a *failure*: it gets the objective value ``inf`` (ranked last by every
operator), is counted, and the run goes on. Constrained problems (pymoo ``G <= 0``, ``H = 0``)
are scalarized with a static penalty: ``f + penalty * (sum max(G, 0) + sum |H|)``.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
from pymoo.core.problem import Problem

from .errors import EvoplanError


@dataclass
class Evaluation:
    """The outcome of one batch: objective values ``f: (n,)`` and the failures among them."""

    f: np.ndarray
    failed: np.ndarray
    errors: list[str] = field(default_factory=list)
    F: np.ndarray | None = None  # a multi-objective evaluator's vectors (n, k), inf where failed


def stack_vectors(parts: list["Evaluation"]) -> np.ndarray | None:
    """The vectors of consecutive evaluations joined in row order (NaN rows, "not evaluated",
    for a part without them, e.g. a chunk lost to the backend); ``None`` when no part has any."""
    given = [r.F for r in parts if r.F is not None]
    if not given:
        return None
    k = given[0].shape[1]
    return np.concatenate([r.F if r.F is not None else np.full((len(r.f), k), np.nan) for r in parts])


class ObjectiveShapeError(EvoplanError):
    """The objective returned an array of the wrong shape: a bug of the problem, not of a row."""


def objective_shape_error(e: BaseException) -> ObjectiveShapeError | None:
    """pymoo's shape check (a bare ``Exception('Problem Error: F can not be set, expected shape
    (n, k) but provided (...)')``) as a one-line error naming both shapes; else ``None``."""
    text = str(e.args[0]) if type(e) is Exception and e.args else ""
    if not (text.startswith("Problem Error:") and "can not be set" in text):
        return None
    return ObjectiveShapeError(f"problem: the objective returned {text.removeprefix('Problem Error:').strip()}")


class EvaluationTimeout(Exception):
    """An evaluation ran past its time (``evaluation.timeout_s``): a failure of its rows."""


@contextmanager
def time_limit(seconds: float | None):
    """Raise :class:`EvaluationTimeout` in the block after ``seconds`` (a SIGALRM timer).

    Only the main thread of a process receives signals: elsewhere (a Dask worker's thread) the
    block runs unbounded, and the caller must bound it another way (a process it can kill).
    """
    if seconds is None or threading.current_thread() is not threading.main_thread():
        yield
        return

    def expire(signum, frame):
        raise EvaluationTimeout(f"no result within timeout_s = {seconds:g} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


class Evaluator:
    """Turns a pymoo problem into ``X: (n, d) -> Evaluation`` for single-objective search.

    ``timeout`` (seconds per row; a study's ``evaluation.timeout_s``) bounds the evaluation in
    this process's main thread: a batch gets ``timeout`` per row, and when it runs late its rows
    are evaluated one by one, each with ``timeout``, so only the rows that hang fail.
    """

    timeout: float | None = None

    def __init__(self, problem: Problem, constraint_penalty: float = 1e6) -> None:
        if problem.n_obj != 1:
            raise ValueError(
                f"problem has {problem.n_obj} objectives; evoplan run optimizes one "
                "(use a weighted single-objective problem)"
            )
        self.problem = problem
        self.constraint_penalty = float(constraint_penalty)
        self.constrained = bool(problem.n_ieq_constr or problem.n_eq_constr)

    def _scalar(self, X: np.ndarray) -> np.ndarray:
        with time_limit(None if self.timeout is None else self.timeout * len(X)):
            out = self.problem.evaluate(X, return_as_dictionary=True)
        f = np.asarray(out["F"], dtype=float).reshape(len(X), -1)[:, 0]
        if self.constrained:
            violation = np.zeros(len(X))
            if out.get("G") is not None and self.problem.n_ieq_constr:
                violation += np.maximum(np.asarray(out["G"]).reshape(len(X), -1), 0).sum(axis=1)
            if out.get("H") is not None and self.problem.n_eq_constr:
                violation += np.abs(np.asarray(out["H"]).reshape(len(X), -1)).sum(axis=1)
            f = f + self.constraint_penalty * violation
        return f

    def __call__(self, X: np.ndarray) -> Evaluation:
        errors: list[str] = []
        try:
            f = self._scalar(X)
        except (Exception, SystemExit) as batch_error:  # isolate the failing rows (sys.exit too)
            if (shape := objective_shape_error(batch_error)) is not None:
                raise shape from None  # the problem is wrong, not the individuals: stop the run
            f = np.empty(len(X))
            for i, row in enumerate(X):
                try:
                    f[i] = self._scalar(row[None, :])[0]
                except (Exception, SystemExit) as e:  # noqa: BLE001 - a black box may raise anything
                    f[i] = np.nan
                    errors.append(f"{type(e).__name__}: {e}")
            if not errors:  # the batch failed but no row did: report the batch error
                errors.append(f"{type(batch_error).__name__}: {batch_error}")
        failed = ~np.isfinite(f)
        if not failed.any():
            return Evaluation(f, failed, errors)
        if len(errors) < failed.sum():  # failures that raised nothing
            errors.append("the objective returned a non-finite value (NaN or inf)")
        return Evaluation(np.where(failed, np.inf, f), failed, errors)
