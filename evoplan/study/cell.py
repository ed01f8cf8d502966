"""One cell of a study, run where a worker runs it: settings in, a record and a history out.

:func:`run_cell` is what every backend executes. It builds the run as ``evoplan run`` does
(:func:`evoplan.runner.prepare`, :meth:`~evoplan.runner.Prepared.new_state`, for evoplan's
algorithms and the adapters alike) and runs it with :func:`evoplan.engine.run` (no checkpoint: a study resumes cell by
cell). It returns plain data and touches no file, so a remote worker needs no shared disk.
A run that raises is returned as a failed record with its error: the study goes on.

**Equal budgets.** Every algorithm, adapters included, is driven by the same engine loop, which
charges the budget (distinct genotypes evaluated, or every genotype asked for: the ``cache``
group, see :mod:`evoplan.cache`) and stops after the generation in which the budget is
reached (so a run may use up to one batch more). For an exactly equal comparison the engine's
trace of improvements, indexed by evaluation, gives ``final_best``: the best value among the
first ``budget`` evaluations, exactly ``budget`` for every algorithm; ``best_overall`` and
``evaluations`` report the whole run. The trace is returned too (first-hit runtimes at
evaluation granularity, the IOHprofiler export).
"""

from __future__ import annotations

import json
import pickle
import random
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

from ..config import parse_config
from ..engine import HISTORY_COLUMNS, RunState, run
from ..multiobjective import connect
from ..runner import Prepared, history_frame, prepare
from . import shared
from .folder import HISTORY_EXTRA
from .grid import Cell

def best_within(improvements: list[tuple[int, float]], budget: int | None) -> float:
    """The best value among the first ``budget`` evaluations, from a run's improvement trace."""
    inside = [f for e, f in improvements if budget is None or e <= budget]
    return inside[-1] if inside else np.inf


def optimum(problem) -> float | None:
    """The known optimum value of a problem: ``f(pareto_set)`` when pymoo knows the optimum's
    location (exact, e.g. Schwefel's 3.8e-5 per 3 variables), else its declared value, else None."""
    for attempt in (lambda: problem.evaluate(np.atleast_2d(problem.pareto_set()).astype(float)),
                    lambda: problem.pareto_front()):
        try:
            value = attempt()
        except Exception:  # noqa: BLE001 - unknown optimum
            continue
        if value is not None and np.size(value) and np.all(np.isfinite(value)):
            return float(np.min(value))
    return None


def build(run_settings: dict[str, Any]) -> tuple[Prepared, RunState, Any]:
    """The prepared run, its fresh state and the space its algorithm searches."""
    config = parse_config(run_settings, run_settings["name"])
    problem = shared.problem_for(config.problem.name, config.problem.params)  # built once a worker
    prepared = prepare(config, run_settings["name"], problem=problem)
    state = prepared.new_state()
    connect(prepared.evaluator, state.algorithm, prepared.search.decode)  # multi-objective: the vectors
    return prepared, state, prepared.search


def run_cell(cell: Cell) -> tuple[dict[str, Any], list[tuple], list[tuple[int, float]]]:
    """Run ``cell``; returns its record (one row of ``runs.csv``), its history rows and its
    improvement trace ``[(evaluation, new best value), ...]``.

    With ``timeout_s`` outside a main thread (a Dask worker's thread, where no timer can stop
    an evaluation) the cell runs in a child process of its own, whose main thread can."""
    if cell.timeout_s is not None and threading.current_thread() is not threading.main_thread():
        return _in_child(cell)
    return _run_cell(cell)


def _in_child(cell: Cell):
    """``run_cell(cell)`` in a new Python process (``python -m evoplan.study.cell IN OUT``)."""
    with tempfile.TemporaryDirectory(prefix="evoplan-cell-") as tmp:
        src, dst = Path(tmp) / "cell.pickle", Path(tmp) / "result.pickle"
        src.write_bytes(pickle.dumps(cell, protocol=pickle.HIGHEST_PROTOCOL))
        proc = subprocess.run([sys.executable, "-m", "evoplan.study.cell", str(src), str(dst)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if proc.returncode == 0 and dst.is_file():
            return pickle.loads(dst.read_bytes())  # written by our own child, from our own input
    last = (proc.stderr.decode(errors="replace").strip().splitlines() or [""])[-1][:300]
    record = {"key": cell.key, **cell.labels(), "budget": cell.budget, "status": "failed",
              "error": f"the process running this cell died (exit code {proc.returncode}) {last}".strip()}
    return record, [], []


def _run_cell(cell: Cell) -> tuple[dict[str, Any], list[tuple], list[tuple[int, float]]]:
    random.seed(cell.seed)  # libraries that draw from global generators (cma) start the same
    np.random.seed(cell.seed)
    t0 = time.perf_counter()
    record: dict[str, Any] = {"key": cell.key, **cell.labels(), "budget": cell.budget}
    history: list[tuple] = []
    trace: list[tuple[int, float]] = []
    try:
        prepared, state, space = build(cell.run)
        prepared.evaluator.timeout = cell.timeout_s  # a hanging evaluation fails its rows only
        record["optimum"] = optimum(prepared.evaluator.problem)
        run(state, space, prepared.evaluator, prepared.termination)
        frame = history_frame(state)  # the common columns, and a multi-objective run's hypervolume
        frame = frame[list(HISTORY_COLUMNS) + [c for c in HISTORY_EXTRA if c in frame]]
        history = [tuple(map(_plain, row)) for row in frame.itertuples(index=False)]
        trace = list(state.improvements)
        record.update(status="ok", error="", final_best=_finite(best_within(trace, cell.budget)),
                      best_overall=_finite(state.best_f), cache_hits=state.cache_hits,
                      evaluations=state.evaluations, generations=state.algorithm.generation,
                      failures=state.failures, stop_reason=state.stop_reason,
                      failure_messages=" | ".join(state.errors), best_variables=_variables(prepared, state))
        volumes = getattr(state.algorithm, "hypervolumes", None)
        if volumes:  # a multi-objective adapter: its archive's hypervolume at the end of the run
            record["hypervolume"] = float(volumes[-1])
    except Exception as e:  # noqa: BLE001 - a crashed run is a result, not the end of the study
        record.update(status="failed", error=f"{type(e).__name__}: {e}".splitlines()[0][:500])
    record["wall_seconds"] = round(time.perf_counter() - t0, 4)
    return record, history, trace


def _variables(prepared: Prepared, state: RunState) -> str:
    """The best solution decoded to named variables, as JSON (one ``runs.csv`` cell)."""
    if state.best_g is None:
        return ""
    return json.dumps(prepared.space.named(prepared.search.decode(state.best_g[None, :])[0]))


def _finite(x: float) -> float | None:
    return float(x) if np.isfinite(x) else None


def _plain(x):
    return x.item() if isinstance(x, np.generic) else x


if __name__ == "__main__":  # a cell in a child process (see _in_child)
    _cell = pickle.loads(Path(sys.argv[1]).read_bytes())
    Path(sys.argv[2]).write_bytes(pickle.dumps(_run_cell(_cell), protocol=pickle.HIGHEST_PROTOCOL))
