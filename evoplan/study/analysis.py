"""The analysis files of a study from its records: tables, tests, figures, report."""

from __future__ import annotations

from typing import Any, Callable

import pandas as pd

from .config import StudyConfig
from .curves import DEFAULT_TARGETS, reference_values
from .folder import StudyFolder, runs_frame
from .report import render
from .statistics import BLOCK, compare, summarize


def default_reference(study: StudyConfig) -> str:
    """The algorithm the others are tested against: the configured one, else the first entry."""
    if study.statistics.reference:
        return study.statistics.reference
    first = study.algorithms[0]
    return str(first.get("label", first["name"]))


def _invocation(e: dict[str, Any]) -> str:
    return (f"{e['ran']} on {e['backend']} ({e['workers']} workers) in {e['wall_seconds']} s"
            f" (+{e.get('startup_seconds', 0)} s start-up), {e['reused']} reused, {e.get('finished', '')}")


def analyze(study: StudyConfig, folder: StudyFolder, records: list[dict[str, Any]],
            history: Callable[[str], pd.DataFrame], reference_levels: dict[str, str],
            executions: list[dict[str, Any]]) -> None:
    """Write ``runs.csv``, ``summary.csv``, ``tests.csv``, the figures and ``report.md``."""
    runs = runs_frame(records)
    for col in ("final_best", "best_overall", "optimum", "budget", "evaluations", "wall_seconds"):
        runs[col] = pd.to_numeric(runs[col], errors="coerce")
    runs["factor"] = runs["factor"].fillna("")
    runs["level"] = runs["level"].fillna("").astype(str)
    folder.write_table("runs.csv", runs)
    summary = summarize(runs)
    folder.write_table("summary.csv", summary)
    st = study.statistics
    tests = compare(runs, default_reference(study), reference_levels, st.test, st.alpha)
    folder.write_table("tests.csv", tests)
    f_ref = reference_values(runs)
    known = runs.groupby(BLOCK)["optimum"].first()
    targets = DEFAULT_TARGETS if st.targets is None else st.targets
    names = []
    if study.output.plots and (runs["status"] == "ok").any():
        from . import figures

        plots = {
            "figures/convergence.png": lambda: figures.convergence(runs, history, f_ref),
            "figures/final_values.png": lambda: figures.final_boxes(runs, f_ref),
            "figures/ecdf.png": lambda: figures.ecdf_figure(runs, history, f_ref, targets),
        }
        if (runs["factor"] != "").any():
            plots["figures/factor_effects.png"] = lambda: figures.factor_effects(runs, f_ref)
            plots["figures/factor_generations.png"] = lambda: figures.factor_generations(runs, history, f_ref)
        for name, draw in plots.items():
            folder.write_bytes(name, draw())
            names.append(name)
    meta = {
        "grid": f"{runs['problem'].nunique()} problems, {runs.groupby(BLOCK).ngroups} problem x dimension, "
                f"{summary.groupby(['algorithm', 'factor', 'level']).ngroups} variants, {study.seeds} seeds "
                f"= {len(runs)} runs",
        "budget": ", ".join(f"{k}={v}" for k, v in study.budget.model_dump().items() if v not in (None, False)),
        "reference": default_reference(study),
        "runs made": "; ".join(_invocation(e) for e in executions if e["ran"]) or "none",
        "failed runs": int((runs["status"] != "ok").sum()),
    }
    failures = runs[runs["status"] != "ok"]
    text = render(study.name or "study", meta, summary, tests, f_ref, known, names, failures, st.test, st.alpha,
                  len(targets))
    folder.write_text("report.md", text)
