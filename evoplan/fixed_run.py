"""A run whose every decision is fixed: the one plan it names, evaluated once.

A problem with no free variable (the toolpath problem with every gene under ``fixed:``) has a
search space of one point (:class:`~evoplan.space.Space` of no variables). There is nothing
to search, so the run evaluates that point once and writes its folder as any finished run
does: ``config.yaml``, ``history.csv`` (one row), the problem's files of the plan
(``toolpath.apt``, the zone map, ...), ``convergence.png`` when plots are on, and
``best.json`` last, with the plan's criteria beside its objective. No checkpoint is kept: a
killed fixed run is simply run again.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import yaml

from .engine import RunState, write_atomic
from .errors import ConfigError, EvoplanError
from .evaluation import ObjectiveShapeError
from .results_folder import claim

STOP_REASON = "fixed"  # best.json's stop_reason: every decision fixed, evaluated once


class OnePoint:
    """What the results writers read of an algorithm, for a run of one evaluation."""

    generation = 1

    def __init__(self, f: np.ndarray) -> None:
        self.f = np.asarray(f, dtype=float)


def is_fixed(prepared) -> bool:
    """True when the problem leaves nothing to search (no variable)."""
    return prepared.space.n_var == 0


def execute_fixed(prepared, out: Path) -> RunState:
    """Evaluate the one point of ``prepared`` and write the results folder ``out``.

    The evaluation happens before the folder is claimed, so a plan that cannot be evaluated
    leaves no folder; its files are then written each completely or not at all.
    """
    from .runner import recorded_config, write_results

    X = np.zeros((1, 0))
    clock = time.perf_counter()
    try:
        result = prepared.evaluator(X)
    except ObjectiveShapeError as err:
        raise EvoplanError(f"{prepared.source}: {err}") from None
    state = RunState(algorithm=OnePoint(result.f), rng=np.random.default_rng(prepared.config.seed),
                     fingerprint=prepared.fingerprint)
    state.evaluations = 1
    state.elapsed = time.perf_counter() - clock
    state.best_f = float(result.f[0])
    state.best_g = np.zeros(0, dtype=bool)
    if result.failed.any():
        state.failures = 1
        state.errors = list(dict.fromkeys(result.errors))[:5]
    state.improvements = [(1, state.best_f)] if np.isfinite(state.best_f) else []
    state.stop_reason = STOP_REASON
    state.record()
    extra = _plan_report(prepared, X, result)
    folder = claim(out, new=True)
    try:
        write_atomic(out / "config.yaml", yaml.safe_dump(recorded_config(prepared), sort_keys=False).encode())
        write_results(prepared, state, out, extra=extra)
    except OSError as e:
        folder.abandon()  # one evaluation, nothing worth keeping: no partial folder
        raise ConfigError(f"{out}: cannot write the results folder ({e.strerror or e})") from None
    folder.release()
    return state


def _plan_report(prepared, X: np.ndarray, result) -> dict:
    """``best.json``'s extra keys: the fixed decisions, the criteria, the objective vector."""
    problem = prepared.evaluator.problem
    extra: dict = {}
    named = getattr(getattr(problem, "genes", None), "named", None)
    if callable(named):  # the toolpath problem: every gene by name, the tool by its id
        extra["plan"] = named(X[0])
    if result.F is not None:
        extra["objectives"] = [_plain(v) for v in np.asarray(result.F[0]).reshape(-1)]
    criteria = getattr(problem, "criteria", None)
    if callable(criteria) and not result.failed.any():
        try:
            extra["criteria"] = {k: _plain(np.asarray(v).reshape(-1)[0]) for k, v in criteria(X).items()}
        except ValueError as e:
            raise ConfigError(f"{prepared.source}: {e}") from None
    return extra


def _plain(value):
    value = float(value)
    return value if np.isfinite(value) else None

