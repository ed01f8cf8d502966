"""Figures of a run (matplotlib, no display needed), in the style of :mod:`evoplan.figure_style`."""

from __future__ import annotations

import numpy as np
import pandas as pd
import matplotlib.pyplot as plt
from matplotlib.font_manager import FontProperties
from matplotlib.ticker import MaxNLocator

from .figure_style import PALETTE, figure, label, legend_outside, plain_numbers, png


def convergence_figure(history: pd.DataFrame, title: str):
    """Best-so-far and population mean against evaluations; a top axis of generations.

    The top axis is a twin of the evaluation axis with the same limits: the tick of generation
    ``g`` sits at the evaluation count at which generation ``g`` ended (its ``history.csv`` row).
    The y axis is logarithmic when every plotted value is positive. It names no unit: a
    weighted-sum objective has none.
    """
    fig, (ax,) = figure(1, width=7.0, height=4.2)
    ev = history["evaluations"].to_numpy(dtype=float)
    ax.plot(ev, history["best"], lw=2, color=PALETTE[4], label="best so far")
    ax.plot(ev, history["mean"], lw=1, color=PALETTE[0], alpha=0.8, label="population mean")
    values = history[["best", "mean"]].to_numpy(dtype=float)
    finite = values[np.isfinite(values)]
    if finite.size and (finite > 0).all():
        ax.set_yscale("log")
        plain_numbers(ax, "y")
    ax.set_xlabel("evaluations")
    ax.set_ylabel("objective (minimized)")
    ax.set_title(title)
    legend_outside(ax)
    generation_axis(ax, history)
    return fig


def generation_axis(ax, history: pd.DataFrame):
    """A top axis whose ticks mark where generations ended, at their evaluation counts.

    Generations late in a run often cost few evaluations (the cache answers most of them), so
    their ticks crowd together; a tick is kept only if its label clears its right-hand
    neighbour's (:func:`thin_ticks`), and the run's last generation is always labelled."""
    ax.set_xlim(ax.get_xlim())  # frozen: both axes share these limits from now on
    top = ax.twiny()
    top.set_xlim(ax.get_xlim())
    gens = history["generation"].to_numpy(dtype=int)
    ev = history["evaluations"].to_numpy(dtype=float)
    if len(gens):
        wanted = MaxNLocator(nbins=8, integer=True).tick_values(gens.min(), gens.max())
        at = np.isin(gens, np.rint(wanted).astype(int)) | (gens == gens.max())
        at &= np.r_[ev[1:] != ev[:-1], True]  # generations that cost nothing (cache): label the last
        labels = [str(g) for g in gens[at]]
        keep = thin_ticks(ax, ev[at], labels)
        top.set_xticks(ev[at][keep], labels=[t for t, k in zip(labels, keep) if k])
    top.set_xlabel("generation")
    return top


def thin_ticks(ax, positions: np.ndarray, labels: list[str], pad_chars: float = 1.5) -> np.ndarray:
    """Which ticks to keep so that no two labels overlap, walking from the right (the last is
    kept). Label widths are estimated from the tick font size (0.6 em a character) against the
    axes' current width, which only grows when the figure is laid out."""
    size = plt.rcParams["xtick.labelsize"]
    points = size if isinstance(size, (int, float)) else FontProperties(size=size).get_size_in_points()
    width_in = ax.get_position().width * ax.figure.get_figwidth()
    lo, hi = ax.get_xlim()
    per_char = 0.6 * points / 72 / width_in * (hi - lo)  # one character, in data units
    keep = np.zeros(len(positions), dtype=bool)
    last = None
    for i in range(len(positions) - 1, -1, -1):
        if last is None or positions[last] - positions[i] >= per_char * ((len(labels[i]) + len(labels[last])) / 2 + pad_chars):
            keep[i] = True
            last = i
    return keep


def convergence_png(history: pd.DataFrame, title: str) -> bytes:
    """:func:`convergence_figure` as PNG bytes."""
    return png(convergence_figure(history, title))


def pareto_png(front: pd.DataFrame, names: list[str], weights: dict[str, float], title: str) -> bytes:
    """The non-dominated points of a two-objective run, with the Eq. 9 choice marked.

    Axes show the raw criteria with their units when ``front`` has them (the toolpath
    problem's ``machining_error`` in mm, ``machining_time`` in min), else the objective values
    the problem returns. With more than two objectives the first two are drawn.
    """
    fig, (ax,) = figure(1, width=6.2, height=4.4)
    cols = [n if n in front else f"F_{n}" for n in names[:2]]
    front = front.sort_values(cols[0])
    x, y = front[cols[0]].to_numpy(float), front[cols[1]].to_numpy(float)
    ax.plot(x, y, ls="-", lw=0.8, color="0.6", zorder=1)
    ax.plot(x, y, ls="none", marker="o", ms=5, color=PALETTE[4], label=f"non-dominated ({len(front)})", zorder=2)
    chosen = front["weighted_choice"].to_numpy(bool)
    w = ", ".join(f"{weights[n]:g} {n.replace('_', ' ')}" for n in names)
    ax.plot(x[chosen], y[chosen], ls="none", marker="*", ms=15, color=PALETTE[5], zorder=3,
            label=f"lowest Eq. 9 weighted sum\n({w}, normalized)")
    for axis, col in zip("xy", cols):
        name = col.removeprefix("F_")
        text = label(name) if not col.startswith("F_") else f"{name.replace('_', ' ')} (objective value)"
        (ax.set_xlabel if axis == "x" else ax.set_ylabel)(text)
        plain_numbers(ax, axis)
    ax.set_title(title)
    legend_outside(ax)
    return png(fig)
