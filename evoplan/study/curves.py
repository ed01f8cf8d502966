"""Performance curves from run traces: best-so-far on a grid, runtimes to targets, ECDFs.

A run's best-so-far is a step function of the evaluations. The engine records it exactly: the
trace of improvements (``evaluation``, ``best``: the index of each evaluation that found a new
best, and that value), see :func:`step_history`; its value at ``e`` is the ``best`` of the last
row with ``evaluations <= e`` (undefined before the first evaluation). A study folder from
before traces were kept falls back to the history (one row per generation), where the value
is only known at generation ends.

**Fixed-target runtimes** (COCO/IOHprofiler style). For a reference value ``f_ref`` (the known
optimum, else the best final value of any run on that problem) and a precision ``t``, the
runtime of a run is the index of the first evaluation whose value is ``<= f_ref + t`` (with a
generation history: the evaluation count at the end of that generation, which overstates it);
a hit after the budget does not count; a run that never reaches the target has runtime
``inf``. The ECDF at ``e`` is the share of (run, target) pairs solved within ``e`` evaluations.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

DEFAULT_TARGETS = np.logspace(2, -8, 51)  # COCO's 51 precisions, 10^2 .. 10^-8


def best_on_grid(history: pd.DataFrame, grid: np.ndarray) -> np.ndarray:
    """Best-so-far of one run at each evaluation count in ``grid``, NaN before its first row."""
    evals = history["evaluations"].to_numpy(dtype=float)
    best = history["best"].to_numpy(dtype=float)
    if evals.size == 0:
        return np.full(grid.shape, np.nan)
    i = np.searchsorted(evals, grid, side="right") - 1
    return np.where(i >= 0, best[np.maximum(i, 0)], np.nan)


def band(curves: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Median and quartiles across runs (rows) at each grid point (columns), NaN-aware."""
    if curves.size == 0 or np.all(np.isnan(curves)):
        nan = np.full(curves.shape[1:], np.nan)
        return nan, nan, nan
    with warnings.catch_warnings():  # grid points before any run's first generation: all NaN
        warnings.simplefilter("ignore", RuntimeWarning)
        q1, med, q3 = np.nanquantile(curves, [0.25, 0.5, 0.75], axis=0)
    return med, q1, q3


def evaluation_grid(budget: float, points: int = 120) -> np.ndarray:
    """Evaluation counts from 1 to ``budget``, evenly spaced on a log scale."""
    return np.unique(np.round(np.geomspace(1, max(budget, 1), points)))


def runtimes(history: pd.DataFrame, final_best: float, budget: float | None, absolute_targets: np.ndarray) -> np.ndarray:
    """Evaluations to reach each absolute target (see the module docstring), ``inf`` if never."""
    evals = history["evaluations"].to_numpy(dtype=float)
    best = history["best"].to_numpy(dtype=float)
    out = np.full(absolute_targets.shape, np.inf)
    if evals.size:
        hit = best[:, None] <= absolute_targets[None, :]
        first = np.where(hit.any(axis=0), hit.argmax(axis=0), -1)
        out = np.where(first >= 0, evals[np.maximum(first, 0)], np.inf)
    if budget is not None and np.isfinite(budget):
        fb = np.nan if final_best is None else float(final_best)
        out = np.where(fb <= absolute_targets, np.minimum(out, budget), np.inf)
    return out


def step_history(trace: pd.DataFrame | None, history: pd.DataFrame) -> pd.DataFrame:
    """The best-so-far of a run at evaluation granularity, as ``(evaluations, best)`` rows.

    One row per improvement of the ``trace`` (``evaluation``, ``best``), then one at the run's
    last evaluation count (from ``history``) so the curve reaches the end of the run. Without
    a trace (``None``), the generation ``history`` itself.
    """
    if trace is None:
        return history
    rows = pd.DataFrame({"evaluations": trace["evaluation"].to_numpy(dtype=float),
                         "best": trace["best"].to_numpy(dtype=float)})
    if len(history) and len(rows) and history["evaluations"].iloc[-1] > rows["evaluations"].iloc[-1]:
        end = {"evaluations": float(history["evaluations"].iloc[-1]), "best": rows["best"].iloc[-1]}
        rows = pd.concat([rows, pd.DataFrame([end])], ignore_index=True)
    return rows


def ecdf(times: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Share of the entries of ``times`` (runs x targets, any shape) that are ``<= grid[k]``."""
    flat = np.sort(np.ravel(times))
    if flat.size == 0:
        return np.full(grid.shape, np.nan)
    return np.searchsorted(flat, grid, side="right") / flat.size


def reference_values(runs: pd.DataFrame) -> pd.Series:
    """``f_ref`` per (problem, dimension): the known optimum, else the best final value of any run."""
    keys = ["problem", "dimension"]
    known = runs.groupby(keys)["optimum"].first()
    found = runs.groupby(keys)["final_best"].min()
    return known.where(known.notna(), found).rename("f_ref")
