"""A study's report: per-variant boxes of the final values, the summary and the tests tables."""

from __future__ import annotations

from pathlib import Path

from .folder import read_csv
from .page import Section, note, table

SUMMARY = ["variant", "runs", "failed", "median", "q1", "q3", "best", "mean", "worst",
           "evaluations", "wall_seconds", "mean_rank"]


def variant(frame) -> "object":
    """``algorithm`` plus ``factor=level`` where the study varies a factor."""
    name = frame["algorithm"].astype(str)
    if "factor" in frame and "level" in frame:
        has = frame["factor"].notna() & (frame["factor"].astype(str) != "")
        name = name.where(~has, name + " " + frame["factor"].astype(str) + "=" + frame["level"].astype(str))
    return name


def sections(folder: Path) -> list[Section]:
    import plotly.graph_objects as go

    runs = read_csv(folder / "runs.csv", ("algorithm", "problem", "dimension", "status", "final_best"))
    runs = runs.assign(variant=variant(runs))
    out = []
    for (problem, dim), block in runs.groupby(["problem", "dimension"], sort=False):
        ok = block[block["status"] == "ok"]
        fig = go.Figure()
        for name, rows in ok.groupby("variant", sort=False):
            fig.add_trace(go.Box(y=rows["final_best"], name=name, boxpoints="all", jitter=0.4,
                                 pointpos=0, customdata=rows[["seed", "key"]].to_numpy()
                                 if {"seed", "key"} <= set(rows) else None,
                                 hovertemplate="%{y:.6g}<br>seed %{customdata[0]}<br>"
                                               "%{customdata[1]}<extra>%{x}</extra>"))
        values = ok["final_best"].astype(float)
        log = bool(len(values)) and values.min() > 0 and values.max() / values.min() > 100
        fig.update_layout(yaxis_title="final best objective (minimized)", showlegend=False,
                          yaxis_type="log" if log else "linear", height=440,
                          yaxis_dtick="D2" if log else None,
                          margin=dict(l=60, r=20, t=30, b=60))
        failed = len(block) - len(ok)
        items = [fig]
        if failed:
            items.insert(0, note(f"{failed} run(s) failed and are not drawn (see runs.csv)."))
        out.append(Section(f"{problem} (dimension {dim}): final values per variant, every run a point", items))
    if (folder / "summary.csv").is_file():
        s = read_csv(folder / "summary.csv", ("algorithm", "problem", "dimension"))
        s = s.assign(variant=variant(s))
        rows = []
        for (problem, dim), block in s.groupby(["problem", "dimension"], sort=False):
            for _, r in block.iterrows():
                rows.append([problem, int(dim)] + [_value(r.get(c)) for c in SUMMARY])
        out.append(Section("Summary (summary.csv)", [table(["problem", "dimension"] + SUMMARY, rows)]))
    if (folder / "tests.csv").is_file():
        t = read_csv(folder / "tests.csv")
        cols = [c for c in ("problem", "dimension", "reference", "algorithm", "factor", "level", "test",
                            "n", "median_difference", "effect", "p_value", "p_holm", "verdict")
                if c in t and t[c].notna().any()]
        out.append(Section("Tests against the reference (tests.csv)",
                           [table(cols, [[_value(r[c]) for c in cols] for _, r in t.iterrows()])]))
    out.extend(_ecdf_and_cd(folder))
    return out


def _ecdf_and_cd(folder: Path) -> list[Section]:
    """The fixed-target ECDFs and the critical-difference diagrams (``studyfigs.py``)."""
    from .studyfigs import cd_figure, ecdf_figure, variant_colours, variant_of

    runs = read_csv(folder / "runs.csv")
    if not {"key", "optimum", "budget", "evaluations"} <= set(runs.columns):  # not the runner's runs.csv
        return []
    for col in ("factor", "level"):
        runs[col] = runs[col].astype(object).fillna("") if col in runs else ""  # all-empty: read as float
    runs["variant"] = variant_of(runs)
    colours = variant_colours(runs["variant"])
    out = [Section("Fixed-target ECDF", [ecdf_figure(runs, folder, colours), note(
        "Share of (run, target) pairs reached within the evaluations, 51 targets f_ref + 10^k; f_ref is the "
        "known optimum, else the best value any run found; runtimes at evaluation granularity (traces/).")])]
    if (folder / "nemenyi.csv").is_file():
        nem = read_csv(folder / "nemenyi.csv")
        nem["factor"] = nem["factor"].astype(object).fillna("")
        out.append(Section("Critical-difference diagram", [cd_figure(nem, colours), note(
            "Mean ranks over the repetitions; colours are the variants' (the same in every figure), not their "
            "ranks.")]))
    return out


def _value(v):
    """A table cell: NaN as empty, whole floats of counts kept as numbers."""
    if v is None or (isinstance(v, float) and v != v):
        return ""
    if hasattr(v, "item"):
        v = v.item()
    return v
