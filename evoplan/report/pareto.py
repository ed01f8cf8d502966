"""The Pareto front of a multi-objective run (``pareto.csv``): every point's decisions and
criteria with units on hover, Eq. 9's choice (``weighted_choice``) marked."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .units import GENE_UNITS, criterion_unit, labelled

__all__ = ["pareto_figure"]


def pareto_figure(front: pd.DataFrame):
    """The non-dominated points on the first two objectives; every decision and criterion of a
    point on hover, with units; Eq. 9's choice (``weighted_choice``) marked."""
    import plotly.graph_objects as go

    objs = [c for c in front.columns if c.startswith("F_")]
    if len(objs) < 2:
        return None
    fx, fy = objs[:2]
    shown = [c for c in front.columns if c != "weighted_choice"]
    text = ["<br>".join(f"{labelled(c, GENE_UNITS.get(c) or criterion_unit(c))}: "
                        f"{row[c]:.6g}" if isinstance(row[c], (int, float, np.floating)) else f"{c}: {row[c]}"
                        for c in shown) for _, row in front.iterrows()]
    chosen = front["weighted_choice"].astype(bool).to_numpy() if "weighted_choice" in front else \
        np.zeros(len(front), bool)
    order = np.argsort(front[fx].to_numpy())
    fig = go.Figure([
        go.Scatter(x=front[fx].to_numpy()[order], y=front[fy].to_numpy()[order], mode="lines+markers",
                   name="non-dominated points", text=np.array(text)[order], hovertemplate="%{text}<extra></extra>",
                   marker=dict(size=8, color="#1f77b4"), line=dict(color="#90caf9", dash="dot")),
    ])
    if chosen.any():
        fig.add_trace(go.Scatter(x=front[fx][chosen], y=front[fy][chosen], mode="markers",
                                 name="Eq. 9's choice (lowest weighted sum)", text=np.array(text)[chosen],
                                 hovertemplate="%{text}<extra></extra>",
                                 marker=dict(size=16, symbol="star", color="#d62728",
                                             line=dict(color="black", width=1))))
    fig.update_layout(height=480, meta="pareto", title="Pareto front (hover: decisions and criteria)",
                      xaxis=dict(title=labelled(fx, "normalized")), yaxis=dict(title=labelled(fy, "normalized")),
                      legend=dict(x=1.0, xanchor="right", y=1.0), margin=dict(l=70, r=20, t=50, b=50))
    return fig
