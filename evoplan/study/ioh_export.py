"""Every run of a study in IOHprofiler's current format: the ``ioh/`` folder that IOHanalyzer
and iohinspector load.

Layout (what ``ioh.logger.Analyzer`` writes, one folder per algorithm variant)::

    ioh/<variant>/IOHprofiler_f<id>_<name>.json                    meta-data of one function
    ioh/<variant>/data_f<id>_<name>/IOHprofiler_f<id>_DIM<d>.dat   raw data, one block per run

The JSON file holds ``version``, ``suite``, ``function_id``, ``function_name``,
``maximization`` (false), ``precision`` (``%.17g``: values are written with round-trip
precision), ``algorithm`` (``name``: the variant, ``info``: the algorithm and factor level),
``experiment_attributes`` (``budget``: the evaluations each run is charged, and ``values``:
``f - f_opt`` or ``f``), ``attributes`` (the data columns) and one scenario per dimension
whose ``runs`` give each run's ``instance``, ``evals`` and ``best`` (``evals``, ``y``; ``x``
is not kept). A raw-data block starts with the header line ``evaluations raw_y`` and has one
row per improvement of the run (the engine's trace: the index of the evaluation that found a
new best, and that value), then one at the run's last evaluation. Suites, function ids and
instances are the real ones for BBOB and stable ids elsewhere (:mod:`evoplan.study.ioh_ids`).

**Budget.** Every count is capped at the run's budget: the rows after it (the engine finishes
the generation in which the budget is reached, so a run overshoots by up to one batch) are
dropped and the run ends at ``min(evaluations, budget)``, as the study's ``final_best`` does.

**Values.** Where the optimum is known (BBOB, whose ``raw_y`` ioh itself writes as ``f -
f_opt``; Kubota; pymoo's test problems) they are precisions ``f - f_opt``, else raw values.
Each block starts at evaluation 1 (iohinspector tells runs apart there); a run whose first
evaluations had no finite value starts with ``1 inf``, and a best without a finite value is
written as ``null``.

Why ``ioh.logger.Analyzer`` does not write these files itself: it takes each run's evaluation
count from the state of an ``ioh`` problem object as the run evaluates it, while evoplan's
engine evaluates batches of any problem (BBOB or not), skips genotypes it has seen, and keeps
the trace; replaying a trace into the logger (``ioh.MetaData`` and ``ioh.LogInfo``) writes the
same raw data but ``"evals": 0`` for every run. The test suite replays a trace into the
logger and checks that this module writes the same files otherwise.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..engine import write_atomic
from .ioh_ids import Function

HEADER = "evaluations raw_y"
LAYOUT_VERSION = "0.3.22"  # the oldest ioh (the bbob extra's floor) writing this layout


def _safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.+=-]+", "_", str(text))


def _variant(row) -> str:
    return row.algorithm if not row.factor else f"{row.algorithm}_{row.factor}={row.level}"


def _number(v: float) -> str:
    return f"{v:.17g}" if np.isfinite(v) else "inf"


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("ioh")
    except PackageNotFoundError:
        return LAYOUT_VERSION


def run_rows(trace: pd.DataFrame, evaluations: int, budget: float, f_opt: float) -> tuple[np.ndarray, np.ndarray]:
    """The ``(evaluation, value)`` rows of one run: the trace inside the budget, from evaluation
    1, ending at ``min(evaluations, budget)``; values as precisions if ``f_opt`` is finite."""
    end = int(evaluations if not np.isfinite(budget) else min(evaluations, budget))
    e = trace["evaluation"].to_numpy(dtype=np.int64)
    f = trace["best"].to_numpy(dtype=float) - (f_opt if np.isfinite(f_opt) else 0.0)
    inside = e <= end
    e, f = e[inside], f[inside]
    if not e.size or e[0] > 1:
        e, f = np.insert(e, 0, 1), np.insert(f, 0, np.inf)
    if end > e[-1]:
        e, f = np.append(e, end), np.append(f, f[-1])
    return e, f


def scenario_run(e: np.ndarray, f: np.ndarray, instance: int) -> dict:
    """A run's entry in the JSON meta-data: its instance, evaluations and best value."""
    i = int(np.argmin(f)) if np.isfinite(f).any() else len(f) - 1
    y = float(f[i]) if np.isfinite(f[i]) else None
    return {"instance": int(instance), "evals": int(e[-1]), "best": {"evals": int(e[i]), "y": y, "x": []}}


def block(e: np.ndarray, f: np.ndarray) -> str:
    return "\n".join([HEADER] + [f"{a} {_number(b)}" for a, b in zip(e, f)]) + "\n"


def meta_json(fn: Function, variant: str, info: str, budget: str, values: str, scenarios: list[dict]) -> str:
    """The JSON meta-data file, in the order and spacing ``ioh.logger.Analyzer`` writes."""
    head = {"version": _version(), "suite": fn.suite, "function_id": fn.id, "function_name": fn.name,
            "maximization": False, "precision": "%.17g"}
    lines = ["{"] + [f"\t{json.dumps(k)}: {json.dumps(v)}, " for k, v in head.items()]
    lines += [f'\t"algorithm": {json.dumps({"name": variant, "info": info})},',
              f'\t"experiment_attributes": {json.dumps([{"budget": budget}, {"values": values}])},',
              f'\t"attributes": {json.dumps(HEADER.split())},',
              '\t"scenarios": [']
    parts = []
    for s in scenarios:
        runs = ",\n".join(f"\t\t\t{json.dumps(r)}" for r in s["runs"])
        parts.append(f'\t\t{{"dimension": {s["dimension"]},\n\t\t"path": {json.dumps(s["path"])},\n'
                     f'\t\t"runs": [\n{runs}\n\t\t]}}')
    lines += [",\n".join(parts), "\t]", "}"]
    return "\n".join(lines) + "\n"


def export(out: str | Path, runs: pd.DataFrame, trace, f_opt: pd.Series,
           functions: dict[str, Function]) -> list[Path]:
    """Write ``out/ioh``; ``trace(key)`` gives a run's improvement trace (None: skipped),
    ``f_opt`` the known optimum per (problem, dimension) (NaN where unknown), ``functions``
    each problem label's IOH identity. Returns the files written."""
    root = Path(out) / "ioh"
    ok = runs[runs["status"] == "ok"].copy()
    ok["variant"] = [_variant(r) for r in ok.itertuples(index=False)]
    ok["fid"] = [functions[p].id for p in ok["problem"]]
    written = []
    for (variant, fid), rows in ok.groupby(["variant", "fid"], sort=False):
        first = rows.iloc[0]
        fn = functions[first["problem"]]
        folder = root / _safe(variant)
        data_dir = f"data_f{fid}_{_safe(fn.name)}"
        info = str(first["algorithm"]) + (f", {first['factor']} = {first['level']}" if first["factor"] else "")
        scenarios, budgets, values = [], set(), set()
        for dimension, drows in rows.groupby("dimension", sort=True):
            blocks, entries = [], []
            for r in drows.sort_values(["problem", "repetition"]).itertuples(index=False):
                steps = trace(r.key)
                if steps is None or not len(steps):
                    continue
                opt = f_opt.get((r.problem, dimension), np.nan)
                opt = float(opt) if pd.notna(opt) else np.nan
                budget = float(r.budget) if pd.notna(r.budget) else np.inf
                e, f = run_rows(steps, int(r.evaluations), budget, opt)
                blocks.append(block(e, f))
                entries.append(scenario_run(e, f, functions[r.problem].instance))
                budgets.add(f"{budget:.0f}" if np.isfinite(budget) else "none")
                values.add("f - f_opt" if np.isfinite(opt) else "f")
            if not blocks:
                continue
            dat = f"{data_dir}/IOHprofiler_f{fid}_DIM{int(dimension)}.dat"
            (folder / data_dir).mkdir(parents=True, exist_ok=True)
            write_atomic(folder / dat, "".join(blocks).encode())
            written.append(folder / dat)
            scenarios.append({"dimension": int(dimension), "path": dat, "runs": entries})
        if scenarios:
            path = folder / f"IOHprofiler_f{fid}_{_safe(fn.name)}.json"
            text = meta_json(fn, variant, info, " ".join(sorted(budgets)), " / ".join(sorted(values)), scenarios)
            write_atomic(path, text.encode())
            written.append(path)
    return written
