"""Evaluation of decoded batches with a pymoo problem: constraints, failures and counting.

A batch ``X: (n, d)`` is evaluated in one call. If that call raises, every row is evaluated on
its own so that one bad individual does not sink the others. A row that raises or returns a
non-finite value is a *failure*: it gets the objective value ``inf`` (ranked last by every
operator), is counted, and the run goes on. Constrained problems (pymoo ``G <= 0``, ``H = 0``)
are scalarized with a static penalty: ``f + penalty * (sum max(G, 0) + sum |H|)``; each row's
constraint violation as pymoo measures it (``CV``, feasible when 0) comes with the values.
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
    # a constrained problem's objective before the penalty and pymoo CV, (n,) each; NaN: raised
    raw: np.ndarray | None = None
    cv: np.ndarray | None = None
    # what each row cost the budget (a problem's ``out["cost"]``: a screened toolpath plan 0,
    # a simulated one 1); None: one evaluation each
    cost: np.ndarray | None = None


def stack_column(parts: list["Evaluation"], name: str) -> np.ndarray | None:
    """The ``raw`` or ``cv`` of consecutive evaluations joined in row order (NaN for a part without)."""
    if all(getattr(r, name) is None for r in parts):
        return None
    return np.concatenate([np.full(len(r.f), np.nan) if getattr(r, name) is None else getattr(r, name) for r in parts])


def violations(problem: Problem, out: dict, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``(penalized, cv)`` of ``n`` evaluated rows: the violation the penalty multiplies,
    ``sum max(G, 0) + sum |H|``, and pymoo's ``CV`` with pymoo's default tolerances
    (:func:`pymoo.core.individual.calc_cv`: ``sum max(0, G - eps) + sum max(0, |H| - eps)``)."""
    from pymoo.core.individual import default_config

    eps = default_config()
    penalized, cv = np.zeros(n), np.zeros(n)
    for key, n_constr, part in (("G", problem.n_ieq_constr, "cv_ieq"), ("H", problem.n_eq_constr, "cv_eq")):
        if out.get(key) is None or not n_constr or not np.size(out[key]):
            continue
        c = np.asarray(out[key], dtype=float).reshape(n, -1)
        c = np.maximum(c, 0) if key == "G" else np.abs(c)
        penalized += c.sum(axis=1)
        cv += np.maximum(0.0, c - eps[part]["eps"]).sum(axis=1)
    return penalized, cv


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


def direct_evaluation(problem: Problem) -> bool:
    """Whether a batch can be handed to ``problem._evaluate`` without pymoo's ``evaluate``
    around it: a vectorized problem of one objective and no constraints that keeps pymoo's own
    ``evaluate``, ``do`` and output formatting, with no callback, no NaN replacement and no
    keyword arguments. ``evaluate`` then adds nothing but its bookkeeping (about 4 us a batch
    of 200, as much as Kubota's function itself), and the values are the same."""
    P = type(problem)
    return (isinstance(problem, Problem) and not problem.elementwise and problem.n_obj == 1
            and not (problem.n_ieq_constr or problem.n_eq_constr) and problem.callback is None
            and problem.replace_nan_values_by is None and not problem.requires_kwargs
            and all(getattr(P, name) is getattr(Problem, name)
                    for name in ("evaluate", "do", "_evaluate_vectorized", "_format_dict")))


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
        self.direct = direct_evaluation(problem)

    def _outputs(self, X: np.ndarray) -> dict:
        """The problem's outputs for the batch ``X: (n, d)``, as pymoo's ``evaluate`` returns
        them; through ``_evaluate`` itself where :func:`direct_evaluation` allows."""
        if not self.direct:
            return self.problem.evaluate(X, return_as_dictionary=True)
        out = {"F": None}
        self.problem._evaluate(X, out)
        if not (isinstance(out["F"], np.ndarray) and out["F"].size == len(X)):  # pymoo's conversions
            out = self.problem._format_dict(out, len(X), ["F"])  # and shape error
        out["F"] = np.array(out["F"], dtype=float)  # (a copy, as pymoo's: the problem may reuse its array)
        if out.get("cost") is not None:
            out["cost"] = np.array(out["cost"], dtype=float)
        return out

    def _values(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
        """The objective values of ``X`` (penalized), and for a constrained problem the values
        before the penalty and pymoo's ``CV`` (else None, None). A problem that sets
        ``out["cost"]`` (n,) leaves it in ``self.cost`` (else None)."""
        if self.timeout is None:  # (no timer to arm: skip the context manager's cost)
            out = self._outputs(X)
        else:
            with time_limit(self.timeout * len(X)):
                out = self._outputs(X)
        cost = out.get("cost")
        self.cost = None if cost is None else np.asarray(cost, dtype=float).reshape(len(X))
        f = np.asarray(out["F"], dtype=float).reshape(len(X), -1)[:, 0]
        if not self.constrained:
            return f, None, None
        penalized, cv = violations(self.problem, out, len(X))
        return f + self.constraint_penalty * penalized, f, cv

    cost: np.ndarray | None = None

    def __call__(self, X: np.ndarray) -> Evaluation:
        errors: list[str] = []
        cost = None
        try:
            f, raw, cv = self._values(X)
            cost = self.cost
        except (Exception, SystemExit) as batch_error:  # isolate the failing rows (sys.exit too)
            if (shape := objective_shape_error(batch_error)) is not None:
                raise shape from None  # the problem is wrong, not the individuals: stop the run
            f = np.empty(len(X))
            raw, cv = (np.full(len(X), np.nan), np.full(len(X), np.nan)) if self.constrained else (None, None)
            costs = []
            for i, row in enumerate(X):
                self.cost = None
                try:
                    values = self._values(row[None, :])
                    f[i] = values[0][0]
                    if cv is not None:
                        raw[i], cv[i] = values[1][0], values[2][0]
                except (Exception, SystemExit) as e:  # noqa: BLE001 - a black box may raise anything
                    f[i] = np.nan
                    errors.append(f"{type(e).__name__}: {e}")
                costs.append(self.cost)
            if any(c is not None for c in costs):  # a row that raised cost one evaluation
                cost = np.array([1.0 if c is None else c[0] for c in costs])
            if not errors:  # the batch failed but no row did: report the batch error
                errors.append(f"{type(batch_error).__name__}: {batch_error}")
        failed = ~np.isfinite(f)
        if not failed.any():
            return Evaluation(f, failed, errors, raw=raw, cv=cv, cost=cost)
        if len(errors) < failed.sum():  # failures that raised nothing
            errors.append("the objective returned a non-finite value (NaN or inf)")
        return Evaluation(np.where(failed, np.inf, f), failed, errors, raw=raw, cv=cv, cost=cost)
