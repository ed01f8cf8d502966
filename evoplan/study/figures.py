"""Figures of a study (PNG bytes): convergence bands, final-value boxes, fixed-target ECDFs,
and for one-factor-at-a-time studies the effect of each factor (Fountas Fig. 6 analogs).

Where the optimum ``f_opt`` of a problem is known (BBOB, Kubota, pymoo's test problems) values
are precisions ``f - f_opt`` on log axes, floored at ``FLOOR`` so that an exact hit stays on
the plot; elsewhere (a toolpath problem) they are the raw objective values, on a log axis when
all are positive: a precision against the best value found would send that run to the floor
and stretch the axis over 16 decades. The ECDFs need a target for every problem and use
``f_ref`` (the known optimum, else the best value any run found; ``curves.reference_values``).
A panel is one problem and dimension (and one factor, in a factor study);
a line or a box is one variant (an algorithm, or a factor's level), with the same colour and
marker in every panel (:mod:`evoplan.figure_style`), the legend outside the panels, and a
caption saying what lines and bands are and how many values the floor holds.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import pandas as pd
from matplotlib.ticker import NullFormatter

from ..figure_style import boxes, figure, figure_legend, mark_floor, png, variant_style
from .curves import DEFAULT_TARGETS, band, best_on_grid, ecdf, evaluation_grid, runtimes
from .measure import HV_MAX

FLOOR = 1e-16
History = Callable[[str], pd.DataFrame]
BANDS = ("Lines: median over the runs of a variant; shaded bands: the interquartile range "
         "(25th to 75th percentile) of the same runs.")


def _axes(n: int):
    return figure(n, width=4.2, height=3.3, cols=4)


def _png(fig, caption: str = "") -> bytes:
    """PNG of a study figure: one legend for all panels (outside), and the caption below."""
    figure_legend(fig)
    if caption:
        fig.text(0.01, -0.01, caption, ha="left", va="top", fontsize=7, wrap=True)
    return png(fig)


def variant_styles(runs: pd.DataFrame) -> dict[str, dict]:
    """One style per variant name (an algorithm, or ``factor=level``), the same in every panel
    and every figure of a study (the critical-difference diagram takes its colours)."""
    names = dict.fromkeys(_variant(a, f, lv) for a, f, lv in zip(runs["algorithm"], runs["factor"], runs["level"]))
    return {name: variant_style(i) for i, name in enumerate(names)}


def _floor_note(clamped: int) -> str:
    return f" {clamped} value(s) at or below {FLOOR:g} are drawn at {FLOOR:g} (dotted line)." if clamped else ""


def _title(problem, dimension, factor="") -> str:
    return f"{problem} ({dimension}-D)" + (f"\n{factor}" if factor else "")


def _variant(algorithm: str, factor: str, level: str) -> str:
    return f"{factor}={level}" if factor else algorithm


def optimum(f_opt: pd.Series, problem: str, dimension: int) -> float:
    """The known optimum of a panel, NaN where unknown."""
    value = f_opt.get((problem, dimension), np.nan)
    return float(value) if pd.notna(value) else np.nan


def _shown(values, opt: float) -> np.ndarray:
    """What a panel plots: ``max(f - f_opt, FLOOR)`` with a known optimum, else ``f``."""
    values = np.asarray(values, dtype=float)
    return np.maximum(values - opt, FLOOR) if np.isfinite(opt) else values


def _clamped(values, opt: float) -> int:
    """How many finite values ``values - f_opt`` fall at or below the floor (none without f_opt)."""
    if not np.isfinite(opt):
        return 0
    d = np.asarray(values, dtype=float) - opt
    return int((np.isfinite(d) & (d <= FLOOR)).sum())


def _what(text: str, opt: float, f_opt: pd.Series) -> str:
    """The y label: ``f - f_opt (best so far)`` or, optimum unknown, ``f (best so far)``; for a
    hypervolume study (``f_opt`` named ``HV_max``, :mod:`evoplan.study.measure`) the deficit."""
    if f_opt.name == HV_MAX:
        return f"HV_max - HV ({text})"
    return f"{'f - f_opt' if np.isfinite(opt) else 'f'} ({text})"


def _yscale(ax) -> None:
    """Log y axis when every plotted value is positive (always so for floored precisions)."""
    data = [np.asarray(ln.get_ydata(), dtype=float) for ln in ax.get_lines()]  # medians, box points
    values = np.concatenate([d[np.isfinite(d)] for d in data]) if data else np.empty(0)
    ax.set_yscale("log" if values.size and (values > 0).all() else "linear")


def panels(runs: pd.DataFrame):
    """``((problem, dimension, factor), rows)`` in the order of the grid."""
    return list(runs.groupby(["problem", "dimension", "factor"], sort=False))


def convergence(runs: pd.DataFrame, history: History, f_opt: pd.Series) -> bytes:
    """Median best-so-far value against evaluations, with the quartile band, per variant."""
    groups = panels(runs)
    styles = variant_styles(runs)
    fig, axes = _axes(len(groups))
    clamped_all = 0
    for ax, ((problem, dim, factor), rows) in zip(axes, groups):
        ref = optimum(f_opt, problem, dim)
        top = np.nanmax(rows["budget"].astype(float).fillna(rows["evaluations"].astype(float)).to_numpy())
        grid = evaluation_grid(top if np.isfinite(top) else 1)
        clamped = 0
        for (algorithm, level), vrows in rows.groupby(["algorithm", "level"], sort=False):
            ok = vrows[vrows["status"] == "ok"]
            curves = np.array([best_on_grid(history(k), grid) for k in ok["key"]]).reshape(len(ok), grid.size)
            clamped += _clamped(curves, ref)
            med, q1, q3 = band(_shown(curves, ref) if curves.size else curves)
            style = styles[_variant(algorithm, factor, level)]
            ax.plot(grid, med, lw=1.6, markevery=max(1, grid.size // 8), ms=4,
                    label=_variant(algorithm, factor, level), **style)
            ax.fill_between(grid, q1, q3, color=style["color"], alpha=0.15, lw=0)
        mark_floor(ax, FLOOR, clamped)
        clamped_all += clamped
        ax.set(xscale="log", xlabel="evaluations",
               ylabel=_what("best so far", ref, f_opt), title=_title(problem, dim, factor))
        _yscale(ax)
        ax.xaxis.set_minor_formatter(NullFormatter())
    return _png(fig, BANDS + _floor_note(clamped_all))


def final_boxes(runs: pd.DataFrame, f_opt: pd.Series) -> bytes:
    """Box plots of the final (in-budget) precision of every variant, per panel; the points too
    when a box holds few."""
    groups = panels(runs)
    fig, axes = _axes(len(groups))
    clamped_all = 0
    for ax, ((problem, dim, factor), rows) in zip(axes, groups):
        ref = optimum(f_opt, problem, dim)
        data, names = [], []
        for (algorithm, level), vrows in rows.groupby(["algorithm", "level"], sort=False):
            values = vrows.loc[vrows["status"] == "ok", "final_best"].astype(float).dropna()
            clamped_all += _clamped(values, ref)
            data.append(_shown(values, ref))
            names.append(level if factor else algorithm)
        boxes(ax, data, names)
        ax.set(ylabel=_what("final", ref, f_opt), title=_title(problem, dim, factor))
        _yscale(ax)
        ax.tick_params(axis="x", labelrotation=45, labelsize=7)
    note = ("Boxes: quartiles and median; whiskers: 1.5 x IQR; dots: every run when a box holds "
            "30 or fewer." + _floor_note(clamped_all))
    return _png(fig, note)


def _runtime_table(runs: pd.DataFrame, history: History, f_ref: pd.Series, targets: np.ndarray) -> list:
    """``(problem, dimension, factor, variant, runtimes: (targets,))`` per run (failed: all inf)."""
    out = []
    for row in runs.itertuples(index=False):
        ref = f_ref.loc[(row.problem, row.dimension)]
        if row.status == "ok":
            budget = float(row.budget) if pd.notna(row.budget) else None
            t = runtimes(history(row.key), row.final_best, budget, ref + targets)
        else:
            t = np.full(targets.shape, np.inf)
        out.append((row.problem, row.dimension, row.factor, _variant(row.algorithm, row.factor, row.level), t))
    return out


def ecdf_figure(runs: pd.DataFrame, history: History, f_ref: pd.Series, targets=None) -> bytes:
    """Fixed-target ECDFs: one panel over all problems (evaluations / dimension), then one per problem."""
    targets = DEFAULT_TARGETS if targets is None else np.asarray(targets, dtype=float)
    table = _runtime_table(runs, history, f_ref, targets)
    blocks = list(dict.fromkeys((p, d) for p, d, *_ in table))
    fig, axes = _axes(1 + len(blocks))
    top = np.nanmax(runs["budget"].astype(float).fillna(runs["evaluations"].astype(float)) / runs["dimension"])
    variants = list(dict.fromkeys(v for *_, v, _ in table))
    grid = evaluation_grid(top, 200)
    styles = {v: variant_style(i) for i, v in enumerate(variants)}
    for v in variants:
        times = np.array([t / d for p, d, f, vv, t in table if vv == v])
        axes[0].step(grid, ecdf(times, grid), where="post", label=v, markevery=20, ms=4, **styles[v])
    axes[0].set(title=f"all problems ({len(targets)} targets each)", xlabel="evaluations / dimension")
    for ax, (p, d) in zip(axes[1:], blocks):
        rows = [(vv, t) for pp, dd, f, vv, t in table if (pp, dd) == (p, d)]
        top = np.nanmax(runs.loc[(runs["problem"] == p) & (runs["dimension"] == d), "evaluations"].astype(float))
        grid = evaluation_grid(top if np.isfinite(top) else 1, 200)
        for v in variants:
            times = np.array([t for vv, t in rows if vv == v])
            ax.step(grid, ecdf(times, grid), where="post", markevery=20, ms=4, **styles[v])
        ax.set(title=_title(p, d), xlabel="evaluations")
    for ax in axes:
        ax.set(xscale="log", ylim=(-0.02, 1.02), ylabel="share of (run, target) pairs solved")
    return _png(fig, f"Fixed-target ECDF: the share of (run, target) pairs reached within the evaluations, "
                     f"{len(targets)} targets f_ref + 10^k per problem.")


def factor_effects(runs: pd.DataFrame, f_opt: pd.Series) -> bytes:
    """Fig. 6 analog (a): final value against each factor's levels (median, quartiles, runs)."""
    rows = runs[runs["factor"] != ""]
    groups = list(rows.groupby(["problem", "dimension", "factor"], sort=False))
    fig, axes = _axes(len(groups))
    for ax, ((problem, dim, factor), frows) in zip(axes, groups):
        levels = list(dict.fromkeys(frows["level"]))
        ref = optimum(f_opt, problem, dim)
        data = [_shown(frows.loc[(frows["level"] == lv) & (frows["status"] == "ok"), "final_best"].dropna(), ref)
                for lv in levels]
        boxes(ax, data, levels)
        med = [np.median(d) if len(d) else np.nan for d in data]
        ax.plot(range(1, len(levels) + 1), med, lw=1.5, label="median", **variant_style(0))
        ax.set(xlabel=factor, ylabel=_what("final", ref, f_opt), title=_title(problem, dim, factor))
        _yscale(ax)
    return _png(fig, "Boxes: quartiles of the final values at each level; line: their medians; "
                     "dots: every run when a box holds 30 or fewer.")


def factor_generations(runs: pd.DataFrame, history: History, f_opt: pd.Series) -> bytes:
    """Fig. 6 analog (b): median best-so-far by generation for each level of each factor."""
    rows = runs[(runs["factor"] != "") & (runs["status"] == "ok")]
    groups = list(rows.groupby(["problem", "dimension", "factor"], sort=False))
    fig, axes = _axes(len(groups))
    for ax, ((problem, dim, factor), frows) in zip(axes, groups):
        ref = optimum(f_opt, problem, dim)
        for i, (level, lrows) in enumerate(frows.groupby("level", sort=False)):
            frames = [history(k) for k in lrows["key"]]
            n = max((len(f) for f in frames), default=0)
            curves = np.full((len(frames), n), np.nan)
            for j, f in enumerate(frames):
                curves[j, : len(f)] = f["best"].to_numpy(dtype=float)
            med, q1, q3 = band(_shown(curves, ref))
            style = variant_style(i)
            ax.plot(np.arange(n), med, lw=1.6, label=f"{factor}={level}", markevery=max(1, n // 8), ms=4, **style)
            ax.fill_between(np.arange(n), q1, q3, color=style["color"], alpha=0.12, lw=0)
        ax.set(xlabel="generation", ylabel=_what("best so far", ref, f_opt),
               title=_title(problem, dim, factor))
        _yscale(ax)
    return _png(fig, BANDS)
