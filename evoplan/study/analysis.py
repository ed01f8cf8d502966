"""The analysis files of a study from its records: tables, tests, figures, report, IOH export."""

from __future__ import annotations

import hashlib
import shutil
from typing import Any, Callable

import pandas as pd

from .config import StudyConfig
from .curves import DEFAULT_TARGETS, reference_values, step_history
from .folder import StudyFolder, runs_frame
from .measure import HV_MAX, deficit_runs, deficit_steps, multi_objective, unfixed_reference_points
from .memo import AnalysisMemo
from .ranking import bayesian, cd_diagram, friedman
from .report import render
from .statistics import BLOCK, compare, summarize


def default_reference(study: StudyConfig) -> str:
    """The algorithm the others are tested against: the configured one, else the first entry."""
    if study.statistics.reference:
        return study.statistics.reference
    first = study.algorithms[0]
    return str(first.get("label", first["name"]))


VARIANT = ["algorithm", "factor", "level"]


def failed_variants(runs: pd.DataFrame) -> pd.DataFrame:
    """The variants (algorithm, factor, level) with a failed run: ``runs`` and ``failed`` counts.

    Their other runs are not comparable (a missing extra, a black box that kills its worker):
    the tests, ranks and figures leave the whole variant out, and the report says so."""
    g = runs.assign(bad=runs["status"] != "ok").groupby(VARIANT, sort=False)["bad"]
    out = pd.DataFrame({"runs": g.size(), "failed": g.sum()}).reset_index()
    return out[out["failed"] > 0]


def _without(runs: pd.DataFrame, variants: pd.DataFrame) -> pd.DataFrame:
    if not len(variants):
        return runs
    keys = set(map(tuple, variants[VARIANT].itertuples(index=False)))
    return runs[[k not in keys for k in map(tuple, runs[VARIANT].itertuples(index=False))]]


def _variant(r) -> str:
    return f"{r.algorithm} {r.factor}={r.level}" if r.factor else str(r.algorithm)


def _invocation(e: dict[str, Any]) -> str:
    return (f"{e['ran']} on {e['backend']} ({e['workers']} workers) in {e['wall_seconds']} s"
            f" (+{e.get('startup_seconds', 0)} s start-up), {e['reused']} reused, {e.get('finished', '')}")


def run_files(folder: StudyFolder, keys) -> str:
    """A digest of the history and trace files of the runs ``keys`` (what the curves are drawn from)."""
    h = hashlib.sha256()
    for key in keys:
        for path in (folder.histories / f"{key}.csv", folder.traces / f"{key}.csv"):
            h.update(path.read_bytes() if path.is_file() else b"-")
    return h.hexdigest()


def analyze(study: StudyConfig, folder: StudyFolder, records: list[dict[str, Any]],
            history: Callable[[str], pd.DataFrame], reference_levels: dict[str, str],
            executions: list[dict[str, Any]]) -> None:
    """Write ``runs.csv``, ``summary.csv``, ``tests.csv``, ``friedman.csv``, ``nemenyi.csv``,
    ``bayes.csv``, the figures, ``report.md`` and the ``ioh/`` export."""
    runs = runs_frame(records)
    for col in ("final_best", "best_overall", "optimum", "budget", "evaluations", "cache_hits", "wall_seconds"):
        runs[col] = pd.to_numeric(runs[col], errors="coerce")
    runs["factor"] = runs["factor"].fillna("")
    runs["level"] = runs["level"].fillna("").astype(str)
    folder.write_table("runs.csv", runs)
    hv_max = None
    if multi_objective(runs):  # the hypervolume deficit is what the statistics compare
        runs, hv_max = deficit_runs(runs, history)
    summary = summarize(runs)  # every variant, failed runs counted
    folder.write_table("summary.csv", summary)
    st = study.statistics
    reference = default_reference(study)
    left_out = failed_variants(runs)
    left_out = left_out[left_out["algorithm"] != reference]  # the reference stays: the others are tested against it
    runs_all, runs = runs, _without(runs, left_out)
    tests = compare(runs, reference, reference_levels, st.test, st.alpha)
    folder.write_table("tests.csv", tests)
    ok_runs = runs[runs["status"] == "ok"]
    ranks, pairs, diagrams = friedman(runs, reference, reference_levels)
    folder.write_table("friedman.csv", ranks)
    folder.write_table("nemenyi.csv", pairs)
    memo = AnalysisMemo(folder.out)
    values = runs.drop(columns=["wall_seconds"])  # what the costly outputs read of the runs
    bayes = None
    if len(ok_runs):
        if memo.fresh("bayes.csv", memo.key("bayes", values, reference, reference_levels, st.rope)):
            bayes = pd.read_csv(folder.out / "bayes.csv", dtype={"factor": str, "level": str})
            bayes[["factor", "level"]] = bayes[["factor", "level"]].fillna("")
        else:
            bayes = bayesian(runs, reference, reference_levels, st.rope)
            folder.write_table("bayes.csv", bayes)
    f_ref = reference_values(runs)
    known = runs.groupby(BLOCK)["optimum"].first()
    if hv_max is not None:
        known = known.rename(HV_MAX)  # figures label the values HV_max - HV
    targets = DEFAULT_TARGETS if st.targets is None else st.targets

    def steps(key: str) -> pd.DataFrame:  # best so far at evaluation granularity
        if hv_max is not None:  # the deficit after each generation
            block = runs.loc[runs["key"] == key, BLOCK].iloc[0]
            return deficit_steps(history(key), float(hv_max.loc[tuple(block)]))
        return step_history(folder.trace(key), history(key))

    left_out_text = "; ".join(f"{_variant(r)} ({r.failed} of {r.runs} runs failed)" for r in left_out.itertuples())
    traces = run_files(folder, runs["key"])  # what the curves and the export are drawn from
    if study.output.ioh and len(ok_runs) and hv_max is None:  # IOHprofiler's format is single-objective
        from .ioh_ids import functions

        ids = functions((spec.label or spec.name, spec.name, spec.params) for spec in study.problems)
        if not memo.fresh("ioh", memo.key("ioh", values, traces, known, repr(ids))):
            from .ioh_export import export

            shutil.rmtree(folder.out / "ioh", ignore_errors=True)  # no file of an earlier export stays
            export(folder.out, runs, folder.trace, known, ids)
    names = []
    if study.output.plots and len(ok_runs):
        def figures():  # matplotlib is imported only if a figure is drawn
            from . import figures as module

            return module

        def cd():
            colors = {name: style["color"] for name, style in figures().variant_styles(runs).items()}
            return cd_diagram(diagrams, st.alpha, colors, left_out_text)

        plots = {
            "figures/convergence.png": lambda: figures().convergence(runs, steps, known),
            "figures/final_values.png": lambda: figures().final_boxes(runs, known),
            "figures/ecdf.png": lambda: figures().ecdf_figure(runs, steps, f_ref, targets),
        }
        if diagrams:
            plots["figures/critical_difference.png"] = cd
        if (runs["factor"] != "").any():
            plots["figures/factor_effects.png"] = lambda: figures().factor_effects(runs, known)
            plots["figures/factor_generations.png"] = lambda: figures().factor_generations(runs, history, known)
        inputs = memo.key(values, runs_all.drop(columns=["wall_seconds"]), traces, known,
                          f_ref, known.name, left_out_text)
        settings = {"figures/ecdf.png": list(map(float, targets)),
                    "figures/critical_difference.png": [st.alpha, reference, reference_levels]}
        for name, draw in plots.items():
            if not memo.fresh(name, memo.key(name, inputs, settings.get(name))):
                folder.write_bytes(name, draw())
            names.append(name)
    memo.save()
    meta = {
        "grid": f"{runs_all['problem'].nunique()} problems, {runs_all.groupby(BLOCK).ngroups} problem x dimension, "
                f"{summary.groupby(['algorithm', 'factor', 'level']).ngroups} variants, {study.seeds} seeds "
                f"= {len(runs_all)} runs",
        "budget": ", ".join(f"{k}={v}" for k, v in study.budget.model_dump().items() if v not in (None, False)),
        "reference": reference,
        "runs made": "; ".join(_invocation(e) for e in executions if e["ran"]) or "none",
        "failed runs": int((runs_all["status"] != "ok").sum()),
    }
    if len(left_out):
        meta["left out of the tests, ranks and figures"] = left_out_text
    if hv_max is not None:
        meta["measure"] = ("the hypervolume deficit HV_max - HV of each run (its archive's hypervolume at the last "
                           "generation within the budget; HV_max: the largest of any run on the problem)")
        if unfixed := unfixed_reference_points(study.algorithms):
            meta["warning"] = (f"{', '.join(unfixed)} fixed no ref_point: each run measured its hypervolume "
                               "against a reference point of its own first generation, so the runs' hypervolumes "
                               "are not comparable; give ref_point to every multi-objective algorithm")
    failures = runs_all[runs_all["status"] != "ok"]
    extra = {"budget": study.cache.budget, "rope": st.rope, "friedman": ranks, "bayes": bayes, "hv_max": hv_max}
    text = render(study.name or "study", meta, summary, tests, f_ref, known, names, failures, st.test, st.alpha,
                  len(targets), extra)
    folder.write_text("report.md", text)
