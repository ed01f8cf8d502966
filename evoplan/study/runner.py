"""Run a study: the grid on a backend, with progress and resume, then its analysis.

Everything that can be checked is checked before the results folder is touched: the study file
(every name, dimension and level), the folder, and the backend (a Dask scheduler that does not
answer). Cells run as tasks of a :mod:`evoplan.parallel` pool; the driver writes each finished
cell (see ``folder.py``), so workers need no shared disk. A task lost to the infrastructure is
recorded as a failed run with its error, and is run again when the study is resumed.
"""

from __future__ import annotations

import json
import shutil
import sys
import time
from collections import deque
from functools import lru_cache
from pathlib import Path
from typing import Any

from tqdm import tqdm

from ..errors import EvoplanError
from ..parallel import open_pool
from .analysis import analyze
from .cell import run_cell
from .config import StudyConfig
from .folder import StudyFolder
from .grid import Cell, build_grid, reference_levels

EXECUTIONS = "execution.json"  # one entry per invocation: cells run and reused, backend, wall time


def _lost(cell: Cell, error: BaseException) -> dict[str, Any]:
    died = type(error).__name__ in DEATHS
    text = "the worker died running this cell (run alone, it died again)" if died else f"{type(error).__name__}: {error}"
    return {"key": cell.key, **cell.labels(), "budget": cell.budget, "status": "failed",
            "error": f"backend: {text}".splitlines()[0][:500]}


DEATHS = {"BrokenProcessPool", "KilledWorker", "CommClosedError", "FutureCancelledError", "CancelledError"}


def run_cells(todo: list[Cell], folder: StudyFolder, pool, progress: bool | None) -> int:
    """Run ``todo`` on ``pool``, saving each as it finishes; returns how many failed.

    At most one cell per worker is in flight. A cell whose task is lost (its worker died: a
    broken process pool fails every running task, Dask gives up with ``KilledWorker``) is run
    again *alone* once the others in flight are done; lost alone too, it is the one at fault and
    is recorded as failed. Cells are deterministic, so the others' numbers do not depend on who
    died where.
    """
    failed = 0
    bar = tqdm(total=len(todo), unit="run", file=sys.stderr, dynamic_ncols=True,
               disable=None if progress is None else not progress)
    queue, suspects, running = deque(todo), deque(), {}
    width = max(getattr(pool, "workers", 1), 1)
    try:
        while queue or suspects or running:
            if suspects and not running:
                cell = suspects.popleft()
                running[_submit(pool, cell)] = (cell, True)
            while queue and not suspects and len(running) < width:
                cell = queue.popleft()
                running[_submit(pool, cell)] = (cell, False)
            future = next(iter(pool.as_completed(list(running))))
            cell, alone = running.pop(future)
            try:
                record, history, trace = future.result()
            except Exception as e:  # noqa: BLE001 - a lost task: retried alone, then a failed run
                _recover(pool)
                if not alone:
                    suspects.append(cell)
                    continue
                record, history, trace = _lost(cell, e), [], []
            folder.save(cell, record, history, trace)
            failed += record["status"] != "ok"
            bar.update(1)
            bar.set_postfix(failed=failed, refresh=False)
    finally:
        bar.close()
    return failed


def _submit(pool, cell: Cell):
    try:
        return pool.submit(run_cell, cell)
    except Exception:  # noqa: BLE001 - a pool broken by a dead worker: rebuilt, then submitted
        _recover(pool)
        return pool.submit(run_cell, cell)


def _recover(pool) -> None:
    recover = getattr(pool, "recover", None)
    if recover is not None:
        recover()


def run_study(study: StudyConfig, source: str, out: str | Path, backend: str = "serial",
              workers: int | None = None, scheduler: str | None = None,
              progress: bool | None = None) -> dict[str, Any]:
    """Run the missing cells of ``study`` into ``out`` and (re)write its analysis; returns a summary."""
    cells = build_grid(study, source)
    levels = reference_levels(study, source)
    folder = StudyFolder(out, study.name)
    folder.check()
    stored = {c.key: r for c in cells if (r := folder.load(c)) is not None}
    todo = [c for c in cells if c.key not in stored]
    t_open = time.perf_counter()
    pool = open_pool(backend, workers, scheduler) if todo else None
    t0 = time.perf_counter()
    created = not Path(out).exists()
    try:
        folder.start(study.resolved())
        failed = run_cells(todo, folder, pool, progress) if todo else 0
    except OSError as e:
        _disk_error(folder, created, e)
    finally:
        if pool is not None:
            pool.close()
    wall = time.perf_counter() - t0
    records = [_stored_any(folder, c) for c in cells]
    execution = {"study": source, "out": str(out), "cells": len(cells), "ran": len(todo),
                 "reused": len(stored), "failed": failed, "backend": backend if todo else "-",
                 "workers": pool.workers if pool is not None else 0, "wall_seconds": round(wall, 2),
                 "startup_seconds": round(t0 - t_open, 2)}
    log = _executions(folder) + [{**execution, "finished": time.strftime("%Y-%m-%d %H:%M:%S")}]
    history = lru_cache(maxsize=None)(folder.history)
    try:
        folder.write_text(EXECUTIONS, json.dumps(log, indent=1) + "\n")
        analyze(study, folder, records, history, levels, log)
    except OSError as e:
        _disk_error(folder, False, e)
    return execution


def _disk_error(folder: StudyFolder, created: bool, e: OSError) -> None:
    """A full (or read-only) disk: one line; a folder this call created with no cell in it goes."""
    if created and not any(folder.cells.glob("*.json")):
        shutil.rmtree(folder.out, ignore_errors=True)
        raise EvoplanError(f"{folder.out}: cannot write ({e.strerror or type(e).__name__}); nothing was kept") from None
    raise EvoplanError(f"{folder.out}: cannot write ({e.strerror or type(e).__name__}); the finished cells are "
                       "kept: free space and run the same command again to resume") from None


def _executions(folder: StudyFolder) -> list[dict[str, Any]]:
    """Earlier invocations on this folder (each: what ran where, and its wall time)."""
    try:
        log = json.loads((folder.out / EXECUTIONS).read_text())
    except (OSError, ValueError):
        return []
    return log if isinstance(log, list) else [log]


def _stored_any(folder: StudyFolder, cell: Cell) -> dict[str, Any]:
    """The record of a cell whatever its status (failed runs are rows of ``runs.csv`` too)."""
    try:
        return json.loads((folder.cells / f"{cell.key}.json").read_text())["record"]
    except (OSError, ValueError, KeyError):
        return {"key": cell.key, **cell.labels(), "budget": cell.budget, "status": "missing", "error": ""}
