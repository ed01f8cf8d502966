"""Figures of a study (PNG bytes): convergence bands, final-value boxes, fixed-target ECDFs,
and for one-factor-at-a-time studies the effect of each factor (Fountas Fig. 6 analogs).

Values are precisions ``f - f_ref`` (``f_ref``: the known optimum, else the best value any run
found; see ``curves.reference_values``) on log axes, floored at ``FLOOR`` so that an exact hit
stays on the plot. A panel is one problem and dimension (and one factor, in a factor study);
a line or a box is one variant (an algorithm, or a factor's level).
"""

from __future__ import annotations

import io
from typing import Callable

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from .curves import DEFAULT_TARGETS, band, best_on_grid, ecdf, evaluation_grid, runtimes  # noqa: E402

FLOOR = 1e-16
History = Callable[[str], pd.DataFrame]


def _axes(n: int, width: float = 4.2, height: float = 3.3):
    cols = min(n, 4)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), dpi=100, squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def _png(fig) -> bytes:
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    return buf.getvalue()


def _title(problem, dimension, factor="") -> str:
    return f"{problem} ({dimension}-D)" + (f"\n{factor}" if factor else "")


def _variant(algorithm: str, factor: str, level: str) -> str:
    return f"{factor}={level}" if factor else algorithm


def _precision(values, f_ref: float) -> np.ndarray:
    return np.maximum(np.asarray(values, dtype=float) - f_ref, FLOOR)


def panels(runs: pd.DataFrame):
    """``((problem, dimension, factor), rows)`` in the order of the grid."""
    return list(runs.groupby(["problem", "dimension", "factor"], sort=False))


def convergence(runs: pd.DataFrame, history: History, f_ref: pd.Series) -> bytes:
    """Median best-so-far precision against evaluations, with the quartile band, per variant."""
    groups = panels(runs)
    fig, axes = _axes(len(groups))
    for ax, ((problem, dim, factor), rows) in zip(axes, groups):
        ref = f_ref.loc[(problem, dim)]
        top = np.nanmax(rows["budget"].astype(float).fillna(rows["evaluations"].astype(float)).to_numpy())
        grid = evaluation_grid(top if np.isfinite(top) else 1)
        for (algorithm, level), vrows in rows.groupby(["algorithm", "level"], sort=False):
            ok = vrows[vrows["status"] == "ok"]
            curves = np.array([best_on_grid(history(k), grid) for k in ok["key"]]).reshape(len(ok), grid.size)
            med, q1, q3 = band(_precision(curves, ref) if curves.size else curves)
            line, = ax.plot(grid, med, lw=1.6, label=_variant(algorithm, factor, level))
            ax.fill_between(grid, q1, q3, color=line.get_color(), alpha=0.15, lw=0)
        ax.set(xscale="log", yscale="log", xlabel="evaluations", ylabel="f - f_ref (best so far)",
               title=_title(problem, dim, factor))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.grid(True, which="major", alpha=0.3)
    axes[0].legend(fontsize=7)
    return _png(fig)


def final_boxes(runs: pd.DataFrame, f_ref: pd.Series) -> bytes:
    """Box plots of the final (in-budget) precision of every variant, per panel."""
    groups = panels(runs)
    fig, axes = _axes(len(groups))
    for ax, ((problem, dim, factor), rows) in zip(axes, groups):
        ref = f_ref.loc[(problem, dim)]
        data, names = [], []
        for (algorithm, level), vrows in rows.groupby(["algorithm", "level"], sort=False):
            values = vrows.loc[vrows["status"] == "ok", "final_best"].astype(float)
            data.append(_precision(values.dropna(), ref))
            names.append(level if factor else algorithm)
        ax.boxplot(data, tick_labels=names, showfliers=True)
        ax.set(yscale="log", ylabel="final f - f_ref", title=_title(problem, dim, factor))
        ax.tick_params(axis="x", labelrotation=45, labelsize=7)
        ax.grid(True, axis="y", alpha=0.3)
    return _png(fig)


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
    for v in variants:
        times = np.array([t / d for p, d, f, vv, t in table if vv == v])
        axes[0].step(grid, ecdf(times, grid), where="post", label=v)
    axes[0].set(title=f"all problems ({len(targets)} targets each)", xlabel="evaluations / dimension")
    for ax, (p, d) in zip(axes[1:], blocks):
        rows = [(vv, t) for pp, dd, f, vv, t in table if (pp, dd) == (p, d)]
        top = np.nanmax(runs.loc[(runs["problem"] == p) & (runs["dimension"] == d), "evaluations"].astype(float))
        grid = evaluation_grid(top if np.isfinite(top) else 1, 200)
        for v in variants:
            times = np.array([t for vv, t in rows if vv == v])
            ax.step(grid, ecdf(times, grid), where="post", label=v)
        ax.set(title=_title(p, d), xlabel="evaluations")
    for ax in axes:
        ax.set(xscale="log", ylim=(-0.02, 1.02), ylabel="share of (run, target) pairs solved")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7)
    return _png(fig)


def factor_effects(runs: pd.DataFrame, f_ref: pd.Series) -> bytes:
    """Fig. 6 analog (a): final value against each factor's levels (median, quartiles, runs)."""
    rows = runs[runs["factor"] != ""]
    groups = list(rows.groupby(["problem", "dimension", "factor"], sort=False))
    fig, axes = _axes(len(groups))
    for ax, ((problem, dim, factor), frows) in zip(axes, groups):
        levels = list(dict.fromkeys(frows["level"]))
        ref = f_ref.loc[(problem, dim)]
        data = [_precision(frows.loc[(frows["level"] == lv) & (frows["status"] == "ok"), "final_best"].dropna(), ref)
                for lv in levels]
        ax.boxplot(data, tick_labels=levels, showfliers=False)
        med = [np.median(d) if len(d) else np.nan for d in data]
        ax.plot(range(1, len(levels) + 1), med, "o-", lw=1.5)
        ax.set(yscale="log", xlabel=factor, ylabel="final f - f_ref", title=_title(problem, dim, factor))
        ax.grid(True, axis="y", alpha=0.3)
    return _png(fig)


def factor_generations(runs: pd.DataFrame, history: History, f_ref: pd.Series) -> bytes:
    """Fig. 6 analog (b): median best-so-far by generation for each level of each factor."""
    rows = runs[(runs["factor"] != "") & (runs["status"] == "ok")]
    groups = list(rows.groupby(["problem", "dimension", "factor"], sort=False))
    fig, axes = _axes(len(groups))
    for ax, ((problem, dim, factor), frows) in zip(axes, groups):
        ref = f_ref.loc[(problem, dim)]
        for level, lrows in frows.groupby("level", sort=False):
            frames = [history(k) for k in lrows["key"]]
            n = max((len(f) for f in frames), default=0)
            curves = np.full((len(frames), n), np.nan)
            for i, f in enumerate(frames):
                curves[i, : len(f)] = f["best"].to_numpy(dtype=float)
            med, q1, q3 = band(_precision(curves, ref))
            line, = ax.plot(np.arange(n), med, lw=1.6, label=f"{level}")
            ax.fill_between(np.arange(n), q1, q3, color=line.get_color(), alpha=0.12, lw=0)
        ax.set(yscale="log", xlabel="generation", ylabel="best so far, f - f_ref", title=_title(problem, dim, factor))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, title=factor, title_fontsize=7)
    return _png(fig)
