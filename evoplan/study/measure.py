"""What a study compares: each run's final best value or, for multi-objective runs, its hypervolume.

A multi-objective adapter's run (NSGA-II, NSGA-III, SMS-EMOA) measures its archive's
hypervolume after every generation (the history's ``hypervolume`` column; ``runs.csv`` holds
the last one). The statistics, ranks and figures of a study minimize one value per run
(``final_best``); for multi-objective runs that value becomes the **hypervolume deficit**
``HV_max - HV``, where ``HV_max`` is the largest hypervolume any run of the study reached on
that problem and ``HV`` the run's hypervolume at the last generation within the budget. The
deficit is 0 for the best run and plays the part of the precision ``f - f_opt`` (its "known
optimum" is 0), so the Wilcoxon/Holm tests, Friedman ranks, critical-difference diagram,
Bayesian test, boxes and ECDFs need no second code path. Its trajectory is generation by
generation (the archive is measured once a generation), not evaluation by evaluation.

Hypervolumes are comparable only against one reference point: a study should give
``ref_point`` to every multi-objective algorithm (otherwise each run fixes its own from its
first generation, and the report says so).
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import pandas as pd

HV_MAX = "HV_max"  # the name of the per-problem reference series of a hypervolume study
BLOCK = ["problem", "dimension"]


def multi_objective(runs: pd.DataFrame) -> bool:
    """Whether the runs are multi-objective: some finished run reported a hypervolume."""
    return "hypervolume" in runs and pd.to_numeric(runs["hypervolume"], errors="coerce").notna().any()


def hypervolume_within(history: pd.DataFrame, budget: float | None, final: float) -> float:
    """The run's hypervolume at its last generation within ``budget`` evaluations (the first
    generation if none is); ``final`` (the record's) when the history has no hypervolume."""
    if "hypervolume" not in history or not len(history):
        return final
    hv = history["hypervolume"].to_numpy(dtype=float)
    evals = history["evaluations"].to_numpy(dtype=float)
    inside = np.flatnonzero(evals <= budget) if budget is not None and np.isfinite(budget) else np.arange(hv.size)
    return float(hv[inside[-1] if inside.size else 0])


def deficit_runs(runs: pd.DataFrame, history: Callable[[str], pd.DataFrame]) -> tuple[pd.DataFrame, pd.Series]:
    """``runs`` with ``final_best`` and ``best_overall`` the hypervolume deficits and
    ``optimum`` 0, and ``HV_max`` per (problem, dimension)."""
    ok = runs["status"] == "ok"
    final = pd.to_numeric(runs["hypervolume"], errors="coerce")
    budget = pd.to_numeric(runs["budget"], errors="coerce")
    within = pd.Series([hypervolume_within(history(k), b, f) if good else np.nan
                        for k, b, f, good in zip(runs["key"], budget, final, ok)], index=runs.index)
    hv_max = within.groupby([runs[c] for c in BLOCK]).max().rename(HV_MAX)
    top = hv_max.reindex(pd.MultiIndex.from_frame(runs[BLOCK])).to_numpy()
    out = runs.assign(final_best=top - within.to_numpy(), best_overall=top - final.to_numpy(), optimum=0.0)
    return out, hv_max


def deficit_steps(history: pd.DataFrame, hv_max: float) -> pd.DataFrame:
    """A run's deficit ``HV_max - HV`` after each generation, as ``(evaluations, best)`` rows."""
    if "hypervolume" not in history:
        return pd.DataFrame({"evaluations": [], "best": []})
    return pd.DataFrame({"evaluations": history["evaluations"].to_numpy(dtype=float),
                         "best": hv_max - history["hypervolume"].to_numpy(dtype=float)})


def unfixed_reference_points(algorithms: list[dict]) -> list[str]:
    """The multi-objective algorithms of a study without a fixed ``ref_point``."""
    from ..adapters.pymoo_multi import MULTI_FACTORIES

    return [str(a.get("label", a["name"])) for a in algorithms
            if a["name"] in MULTI_FACTORIES and a.get("ref_point") is None]
