"""A study's fixed-target ECDFs (``runs.csv``, ``traces/``, ``histories/``) and critical-difference
diagrams (``nemenyi.csv``); each variant keeps one colour in every figure (not its rank's)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from .folder import read_csv

__all__ = ["ecdf_figure", "cd_figure", "variant_colours", "variant_of"]

PALETTE = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000",
           "#8c564b", "#7f7f7f", "#bcbd22", "#17becf"]


def variant_of(frame: pd.DataFrame) -> pd.Series:
    factor = frame["factor"].fillna("").astype(str)
    level = frame["level"].fillna("").astype(str)
    return pd.Series(np.where(factor == "", frame["algorithm"], factor + "=" + level), index=frame.index)


def variant_colours(variants) -> dict[str, str]:
    """One colour per variant, in the order the study lists them (not by rank)."""
    return {v: PALETTE[i % len(PALETTE)] for i, v in enumerate(dict.fromkeys(variants))}


def _frame(folder: Path, sub: str, key: str) -> pd.DataFrame | None:
    path = folder / sub / f"{key}.csv"
    return read_csv(path) if path.is_file() else None


def ecdf_figure(runs: pd.DataFrame, folder: Path, colours: dict):
    """Fixed-target ECDF per problem (COCO's 51 targets f_ref + 10^k, k in [-8, 2])."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    from ..study.curves import DEFAULT_TARGETS, ecdf, evaluation_grid, reference_values, runtimes, step_history

    f_ref = reference_values(runs)
    blocks = list(dict.fromkeys(zip(runs["problem"], runs["dimension"])))
    fig = make_subplots(rows=1, cols=len(blocks), subplot_titles=[f"{p} ({d}-D)" for p, d in blocks],
                        shared_yaxes=True)
    for col, (p, d) in enumerate(blocks, start=1):
        rows = runs[(runs["problem"] == p) & (runs["dimension"] == d)]
        top = float(np.nanmax(rows["evaluations"].astype(float)))
        grid = evaluation_grid(top if np.isfinite(top) and top > 1 else 2, 200)
        for v in colours:
            sel = rows[rows["variant"] == v]
            if sel.empty:
                continue
            times = []
            for r in sel.itertuples(index=False):
                hist = _frame(folder, "histories", r.key)
                if r.status != "ok" or hist is None:
                    times.append(np.full(DEFAULT_TARGETS.shape, np.inf))
                    continue
                steps = step_history(_frame(folder, "traces", r.key), hist)
                budget = float(r.budget) if pd.notna(r.budget) else None
                times.append(runtimes(steps, r.final_best, budget, f_ref.loc[(p, d)] + DEFAULT_TARGETS))
            fig.add_trace(go.Scatter(x=grid, y=ecdf(np.array(times), grid), mode="lines", line=dict(shape="hv",
                                     color=colours[v], width=2), name=v, legendgroup=v, showlegend=col == 1,
                                     hovertemplate=f"{v}<br>%{{x:.0f}} evaluations<br>%{{y:.2f}} solved<extra></extra>"),
                          row=1, col=col)
        fig.update_xaxes(type="log", title_text="evaluations", row=1, col=col)
    fig.update_yaxes(title_text="share of (run, target) pairs solved", range=[-0.02, 1.02], row=1, col=1)
    fig.update_layout(height=420, meta="ecdf", title="fixed-target ECDF (51 targets per problem)",
                      legend=dict(orientation="h", x=0, y=-0.25), margin=dict(l=70, r=20, t=70, b=90))
    return fig


def boxes_figure(runs: pd.DataFrame, colours: dict):
    """Final (in-budget) precision f - f_ref per variant and problem, every run as a point."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    from ..study.curves import reference_values

    f_ref = reference_values(runs)
    blocks = list(dict.fromkeys(zip(runs["problem"], runs["dimension"])))
    fig = make_subplots(rows=1, cols=len(blocks), subplot_titles=[f"{p} ({d}-D)" for p, d in blocks])
    floor = 1e-12
    for col, (p, d) in enumerate(blocks, start=1):
        rows = runs[(runs["problem"] == p) & (runs["dimension"] == d) & (runs["status"] == "ok")]
        for v in colours:
            vals = rows.loc[rows["variant"] == v, "final_best"].astype(float) - float(f_ref.loc[(p, d)])
            if vals.empty:
                continue
            fig.add_trace(go.Box(y=np.maximum(vals, floor), name=v, marker_color=colours[v], boxpoints="all",
                                 jitter=0.4, pointpos=0, legendgroup=v, showlegend=col == 1,
                                 hovertemplate=f"{v}<br>f - f_ref %{{y:.4g}}<extra></extra>"), row=1, col=col)
        fig.update_yaxes(type="log", row=1, col=col)
    fig.update_yaxes(title_text=f"final f − f_ref (floor {floor:g})", row=1, col=1)
    fig.update_layout(height=430, meta="boxes", title="final values per variant (every run a point)",
                      legend=dict(orientation="h", x=0, y=-0.2), margin=dict(l=70, r=20, t=70, b=80))
    return fig


def cd_figure(nemenyi: pd.DataFrame, colours: dict, alpha: float = 0.05):
    """Critical-difference diagrams: each variant at its mean rank (1 = best, left), joined by a
    bar to the variants Nemenyi's test does not tell apart (p > alpha); one row per problem."""
    import plotly.graph_objects as go

    fig = go.Figure()
    groups = list(nemenyi.groupby(["problem", "dimension", "factor"], sort=False, dropna=False))
    shown = set()
    for row, ((p, d, f), g) in enumerate(groups):
        y0 = -3.0 * row
        ranks = {}
        for r in g.itertuples(index=False):
            ranks[r.a], ranks[r.b] = r.mean_rank_a, r.mean_rank_b
        for k, (v, rank) in enumerate(sorted(ranks.items(), key=lambda t: t[1])):
            fig.add_trace(go.Scatter(x=[rank], y=[y0], mode="markers+text", text=[v],
                                     textposition="top center" if k % 2 == 0 else "bottom center",
                                     marker=dict(size=13, color=colours.get(v, "#333")), name=v, legendgroup=v,
                                     showlegend=v not in shown,
                                     hovertemplate=f"{v}: mean rank %{{x:.2f}}<extra>{p} {d}-D</extra>"))
            shown.add(v)
        same = g[g["p_nemenyi"] > alpha]
        for j, r in enumerate(same.itertuples(index=False)):
            lo, hi = sorted((r.mean_rank_a, r.mean_rank_b))
            fig.add_trace(go.Scatter(x=[lo, hi], y=[y0 - 0.9 - 0.25 * j] * 2, mode="lines", showlegend=False,
                                     line=dict(color="#424242", width=3), hoverinfo="text",
                                     text=f"{r.a} ~ {r.b}: Nemenyi p = {r.p_nemenyi:.3g}"))
        fig.add_annotation(x=0.5, y=y0, xref="paper", yref="y", text=f"<b>{p} ({d}-D){' ' + f if f else ''}</b>",
                           showarrow=False, yshift=28)
    fig.update_layout(height=180 + 150 * len(groups), meta="cd", title=f"critical-difference diagrams "
                      f"(bars: not significantly different, Nemenyi, alpha = {alpha:g})",
                      xaxis=dict(title="mean rank (1 = best)", zeroline=False),
                      yaxis=dict(visible=False), legend=dict(orientation="h", x=0, y=-0.2),
                      margin=dict(l=40, r=20, t=60, b=80))
    return fig


