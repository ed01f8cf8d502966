"""Figures of a run (matplotlib, no display needed)."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402


def convergence_png(history: pd.DataFrame, title: str) -> bytes:
    """Best-so-far and population mean against evaluations, as PNG bytes.

    The y axis is logarithmic when every plotted value is positive (distance to a zero optimum).
    """
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=120)
    ax.plot(history["evaluations"], history["best"], lw=2, label="best so far")
    ax.plot(history["evaluations"], history["mean"], lw=1, alpha=0.7, label="population mean")
    values = history[["best", "mean"]].to_numpy()
    finite = values[np.isfinite(values)]
    if finite.size and (finite > 0).all():
        ax.set_yscale("log")
    ax.set_xlabel("evaluations")
    ax.set_ylabel("objective (minimized)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    top = ax.secondary_xaxis("top")
    top.set_xlabel("generation")
    gens, evals = history["generation"].to_numpy(), history["evaluations"].to_numpy()
    if len(gens) > 1:
        top.set_functions((lambda e: np.interp(e, evals, gens), lambda g: np.interp(g, gens, evals)))
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    return buf.getvalue()
