"""Every run of a study in IOHprofiler format: the ``ioh/`` folder IOHanalyzer loads.

Layout (IOHanalyzer's "IOHprofiler" format with two-column raw data)::

    ioh/<variant>/IOHprofiler_f<id>_<problem>.info            meta-data, one section per dimension
    ioh/<variant>/data_f<id>_<problem>/IOHprofiler_f<id>_DIM<d>.dat   raw data, one block per run

A meta-data section is three lines: ``suite = 'evoplan', funcId = <id>, DIM = <d>, algId =
'<variant>'`` (plus the problem name and ``maximization = False``), a ``%`` comment line, then
the relative path of the raw-data file followed by ``instance:evaluations|best`` for each run.
A raw-data block starts with the line ``"function evaluation" "best-so-far f(x)"`` and has one
row per improvement of the run (the engine's trace: the index of the evaluation that found a
new best, and that value), ending with the run's last evaluation. Where the optimum is known
(BBOB through ``ioh``, Kubota, pymoo's test problems) the values are precisions
``f - f_opt``, as IOHanalyzer and COCO show them; otherwise raw values. ``funcId`` numbers the
problems in the study's order (from 1); BBOB instances keep their instance number.

``ioh.logger.Analyzer`` is not used: it logs the evaluations made through an ``ioh`` problem
object while they happen (and writes the JSON meta-data variant), whereas evoplan's engine
evaluates batches of any problem and skips the genotypes it has seen; the files are written
afterwards from the recorded traces instead.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from ..engine import write_atomic

HEADER = '"function evaluation" "best-so-far f(x)"'


def _safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.+=-]+", "_", str(text))


def _variant(row) -> str:
    return row.algorithm if not row.factor else f"{row.algorithm}_{row.factor}={row.level}"


def _instance(run_problem: str) -> int:
    m = re.search(r"-i(\d+)$", str(run_problem))
    return int(m.group(1)) if m else 1


def run_block(trace: pd.DataFrame, evaluations: int, f_opt: float) -> tuple[str, float]:
    """The raw-data block of one run and its final best value (both as precisions if ``f_opt``)."""
    shift = 0.0 if not np.isfinite(f_opt) else f_opt
    e = trace["evaluation"].to_numpy(dtype=np.int64)
    f = trace["best"].to_numpy(dtype=float) - shift
    if e.size and evaluations > e[-1]:
        e, f = np.append(e, evaluations), np.append(f, f[-1])
    lines = [HEADER] + [f"{a} {b:.10e}" for a, b in zip(e, f)]
    return "\n".join(lines) + "\n", (float(f[-1]) if f.size else np.inf)


def export(out: str | Path, runs: pd.DataFrame, trace, f_opt: pd.Series) -> list[Path]:
    """Write ``out/ioh``; ``trace(key)`` gives a run's improvement trace (None: skipped),
    ``f_opt`` the known optimum per (problem, dimension) (NaN where unknown). Returns the files."""
    root = Path(out) / "ioh"
    ok = runs[runs["status"] == "ok"].copy()
    ok["variant"] = [_variant(r) for r in ok.itertuples(index=False)]
    fid = {p: i + 1 for i, p in enumerate(dict.fromkeys(runs["problem"]))}
    written = []
    for (variant, problem), rows in ok.groupby(["variant", "problem"], sort=False):
        folder = root / _safe(variant)
        data_dir = f"data_f{fid[problem]}_{_safe(problem)}"
        (folder / data_dir).mkdir(parents=True, exist_ok=True)
        info = []
        for dimension, drows in rows.groupby("dimension", sort=True):
            opt = f_opt.get((problem, dimension), np.nan)
            opt = float(opt) if pd.notna(opt) else np.nan
            blocks, entries = [], []
            for r in drows.sort_values("repetition").itertuples(index=False):
                steps = trace(r.key)
                if steps is None or not len(steps):
                    continue
                block, best = run_block(steps, int(r.evaluations), opt)
                blocks.append(block)
                entries.append(f"{_instance(problem)}:{int(r.evaluations)}|{best:.5e}")
            if not blocks:
                continue
            dat = f"{data_dir}/IOHprofiler_f{fid[problem]}_DIM{int(dimension)}.dat"
            write_atomic(folder / dat, "".join(blocks).encode())
            written.append(folder / dat)
            values = "f - f_opt" if np.isfinite(opt) else "f (optimum unknown)"
            info += [f"suite = 'evoplan', funcId = {fid[problem]}, DIM = {int(dimension)}, algId = '{variant}', "
                     f"problem = '{problem}', maximization = False",
                     f"% values: {values}; evaluations as charged by the study's budget",
                     f"{dat}, " + ", ".join(entries)]
        if info:
            path = folder / f"IOHprofiler_f{fid[problem]}_{_safe(problem)}.info"
            write_atomic(path, ("\n".join(info) + "\n").encode())
            written.append(path)
    return written


def read_info(path: str | Path) -> list[dict]:
    """The sections of a ``.info`` file: their ``key = value`` pairs, data file and runs."""
    lines = Path(path).read_text().splitlines()
    out = []
    for head, _comment, data in zip(lines[0::3], lines[1::3], lines[2::3]):
        pairs = dict((k.strip(), v.strip().strip("'")) for k, v in (p.split("=", 1) for p in head.split(",")))
        file, *runs = [x.strip() for x in data.split(",")]
        pairs["file"] = file
        pairs["runs"] = [(int(r.split(":")[0]), int(r.split(":")[1].split("|")[0]), float(r.split("|")[1]))
                         for r in runs]
        out.append(pairs)
    return out


def read_dat(path: str | Path) -> list[pd.DataFrame]:
    """The blocks of a raw-data file, one frame (``evaluation``, ``best``) per run."""
    blocks, rows = [], None
    for line in Path(path).read_text().splitlines():
        if line.startswith('"function evaluation"'):
            rows = []
            blocks.append(rows)
        elif line.strip():
            e, f = line.split()
            rows.append((int(e), float(f)))
    return [pd.DataFrame(b, columns=["evaluation", "best"]) for b in blocks]
