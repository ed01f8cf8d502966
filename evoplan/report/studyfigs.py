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


#: the CD diagrams' vertical layout, in pixels (the y axis counts pixels from the top)
CD_LINE = 16     # one label line: tied labels stack this far apart
CD_BAR = 7       # one crossbar under the next
CD_TITLE = 30    # a row's title above its labels


def label_levels(ranks: list[float], span: float, gap: float = 0.08) -> list[tuple[int, int]]:
    """``(side, level)`` of each label, ``ranks`` ascending: side +1 above the marker, -1 below,
    level the line on that side (0 nearest). A variant within ``gap`` of the rank axis' ``span``
    of the previous one joins its cluster (ties, or near enough for their labels to collide);
    a cluster's labels alternate above and below and stack one line further out each pair, so
    no two share a place; successive clusters start on alternate sides."""
    out, start, cluster = [], 0, 0
    for k, rank in enumerate(ranks):
        if k and rank - ranks[k - 1] > gap * span:
            start, cluster = k, cluster + 1
        m = k - start
        out.append((1 if (m + cluster) % 2 == 0 else -1, m // 2))
    return out


def cd_figure(nemenyi: pd.DataFrame, colours: dict, alpha: float = 0.05):
    """Critical-difference diagrams: each variant at its mean rank (1 = best, left), joined by a
    bar to the variants Nemenyi's test does not tell apart (p > alpha); one row per problem.

    Labels are annotations placed in pixels (:func:`label_levels`): tied variants' labels
    stack above and below their common marker instead of lying on one another."""
    import plotly.graph_objects as go

    fig = go.Figure()
    groups = list(nemenyi.groupby(["problem", "dimension", "factor"], sort=False, dropna=False))
    n_max = max((len(set(g["a"]) | set(g["b"])) for _, g in groups), default=2)
    span = max(n_max - 1, 1)
    y = 0.0
    for (p, d, f), g in groups:
        ranks = {}
        for r in g.itertuples(index=False):
            ranks[r.a], ranks[r.b] = r.mean_rank_a, r.mean_rank_b
        order = sorted(ranks.items(), key=lambda t: t[1])
        levels = label_levels([rank for _, rank in order], span)
        up = 1 + max((lv for side, lv in levels if side > 0), default=-1)
        down = 1 + max((lv for side, lv in levels if side < 0), default=-1)
        fig.add_annotation(x=0.5, y=y + 4, xref="paper", yref="y", yanchor="top", showarrow=False,
                           text=f"<b>{p} ({d}-D){' ' + f if f else ''}</b>")
        y0 = y + CD_TITLE + up * CD_LINE + 6                              # the row's markers
        for (v, rank), (side, level) in zip(order, levels):
            fig.add_trace(go.Scatter(x=[rank], y=[y0], mode="markers",
                                     marker=dict(size=13, color=colours.get(v, "#333")), name=v,
                                     showlegend=False,
                                     hovertemplate=f"{v}: mean rank %{{x:.2f}}<extra>{p} {d}-D</extra>"))
            fig.add_annotation(x=rank, y=y0 - side * (9 + CD_LINE * level), yref="y", showarrow=False,
                               yanchor="bottom" if side > 0 else "top", text=v, name=f"cd label {p} {d} {f}",
                               font=dict(size=12, color=colours.get(v, "#333")))
        same = g[g["p_nemenyi"] > alpha]
        bar_y = y0 + 9 + down * CD_LINE + 6
        for j, r in enumerate(same.itertuples(index=False)):
            lo, hi = sorted((r.mean_rank_a, r.mean_rank_b))
            fig.add_trace(go.Scatter(x=[lo, hi], y=[bar_y + CD_BAR * j] * 2, mode="lines", showlegend=False,
                                     line=dict(color="#424242", width=3), hoverinfo="text",
                                     text=f"{r.a} ~ {r.b}: Nemenyi p = {r.p_nemenyi:.3g}"))
        y = bar_y + CD_BAR * len(same) + 16
    # the plot area is y pixels tall (height less the margins), so the y axis counts pixels;
    # no legend (it would widen the bottom margin): each marker's label names its variant
    fig.update_layout(height=int(np.ceil(y)) + 140, meta="cd", showlegend=False, title=f"critical-difference diagrams "
                      f"(bars: not significantly different, Nemenyi, alpha = {alpha:g})",
                      xaxis=dict(title="mean rank (1 = best)", zeroline=False, range=[0.7, n_max + 0.3]),
                      yaxis=dict(visible=False, range=[int(np.ceil(y)), 0], fixedrange=True),
                      margin=dict(l=40, r=20, t=60, b=80, autoexpand=False))
    return fig


