"""A run's report: convergence with hover, the best decisions with units, the toolpath in 3D."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

from ..errors import ConfigError
from ..units import GENE_UNITS
from .folder import read_csv, read_json
from .page import Section, note, table
from .units import is_number

#: units of the toolpath problem's decisions (problems/toolpath/genes.py)
DECISION_UNITS = {**GENE_UNITS, "tool": "index in the tool list"}


def sections(folder: Path) -> list[Section]:
    out = [Section("Convergence", [convergence(folder / "history.csv")])]
    if (folder / "best.json").is_file():
        out.append(Section("Best solution", [best_table(folder / "best.json")]))
    if (folder / "toolpath.apt").is_file():
        out.append(Section("Toolpath (toolpath.apt)", toolpath(folder / "toolpath.apt")))
    if (folder / "pareto.csv").is_file():
        from .pareto import pareto_figure

        fig = pareto_figure(read_csv(folder / "pareto.csv"))
        if fig is not None:
            out.append(Section("Pareto front (pareto.csv)", [fig, note(
                "Objectives normalized with the bounds fixed at construction; hover a point for its decisions "
                "and criteria with units; the star is the point of lowest Eq. 9 weighted sum.")]))
    return out


def convergence(path: Path):
    """Best so far over generations, over the population band (best to worst of each
    generation) and its mean; hover gives generation, evaluations and value."""
    import plotly.graph_objects as go

    h = read_csv(path, ("generation", "best", "mean", "worst"))
    gen = h["generation"].to_numpy()
    best_so_far = np.minimum.accumulate(h["best"].to_numpy(dtype=float))
    evals = h["evaluations"].to_numpy() if "evaluations" in h else np.full(len(h), np.nan)
    hover = "generation %{x}<br>evaluations %{customdata}<br>%{y:.6g}"
    fig = go.Figure()
    fig.add_trace(go.Scatter(x=gen, y=h["worst"], mode="lines", line=dict(width=0.5, color="#9ecae1"),
                             name="worst of generation", customdata=evals, hovertemplate=hover))
    fig.add_trace(go.Scatter(x=gen, y=h["best"], mode="lines", line=dict(width=0.5, color="#9ecae1"),
                             fill="tonexty", fillcolor="rgba(158,202,225,0.35)",
                             name="population band (best to worst of generation)",
                             customdata=evals, hovertemplate=hover))
    fig.add_trace(go.Scatter(x=gen, y=h["mean"], mode="lines", line=dict(dash="dash", color="#3182bd"),
                             name="population mean", customdata=evals, hovertemplate=hover))
    fig.add_trace(go.Scatter(x=gen, y=best_so_far, mode="lines+markers", marker=dict(size=4),
                             line=dict(width=2.5, color="#D55E00"), name="best so far",
                             customdata=evals, hovertemplate=hover))
    values = h[["best", "worst"]].to_numpy(dtype=float)
    values = values[np.isfinite(values)]
    log = values.size and values.min() > 0 and values.max() / values.min() > 100
    fig.update_xaxes(tickformat="d", dtick=1 if len(gen) <= 12 else None)
    if log:  # plotly's default crowds 1..9 of every decade together
        decades = np.log10(values.max() / values.min())
        # up to 3 decades: labels at 1, 2 and 5 of each; beyond: one label every k decades (<= 8 labels)
        fig.update_yaxes(dtick="D2" if decades <= 3 else int(np.ceil(decades / 8)), exponentformat="power")
    fig.update_layout(xaxis_title="generation", yaxis_title="objective (minimized)",
                      yaxis_type="log" if log else "linear", hovermode="x unified",
                      height=460, margin=dict(l=60, r=20, t=30, b=50),
                      legend=dict(orientation="h", y=-0.18))
    return fig


def best_table(path: Path) -> str:
    """The best decisions (with units where known) and the objective, as an HTML table."""
    best = read_json(path)
    variables = best.get("variables")
    if not isinstance(variables, dict):
        return note(f"{path.name}: the run has no best solution")
    space = {g.get("name"): g for g in best.get("space", []) if isinstance(g, dict)}
    rows = []
    for name, value in variables.items():
        gene = space.get(name, {})
        if "low" in gene and "high" in gene:
            domain = f"[{gene['low']:g}, {gene['high']:g}]"
        elif "choices" in gene:
            domain = "{" + ", ".join(str(c) for c in gene["choices"]) + "}"
        else:
            domain = ""
        rows.append([name, value, DECISION_UNITS.get(name, "") if is_number(value) else "", domain])
    rows.append(["objective", best.get("objective"), "", "minimized"])
    facts = [f"{k} {best[k]}" for k in ("problem", "algorithm", "seed", "generations",
                                        "evaluations", "stop_reason") if k in best]
    return table(["decision", "value", "unit", "domain"], rows) + note(", ".join(facts))


def toolpath(path: Path) -> list:
    """The APT toolpath in 3D (:func:`.paths.toolpath_figure`: one hue per zone, a shade per
    pass, links and rapids dashed, equal scales, cuts decimated by Ramer-Douglas-Peucker within
    the stated tolerance), over the part and with the CC points and the criteria of
    ``toolpath.npz`` when the run wrote one."""
    from ..problems.toolpath.export.apt_read import AptError
    from .paths import read_moves, surface_trace, toolpath_figure

    try:
        moves = read_moves(path, "finish")
    except AptError as e:
        raise ConfigError(f"{path}: {e}") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ConfigError(f"{path}: unreadable ({e})") from None
    data = plan_data(path.parent / "toolpath.npz")
    part = surface_trace(data["surface"], name="part (toolpath.npz)") if data else None
    fig, caption = toolpath_figure([moves], part=part, cc=data["cc"] if data else None, name="toolpath3d")
    rapids = int((moves.kind[1:] == 2).sum())  # point 0 is reached from anywhere: not a move
    text = (f"{len(moves.tip)} points, {rapids} rapid move{'s' if rapids != 1 else ''}, "
            f"tool D{moves.diameter:g} mm; {caption}")
    out = [note(text), fig]
    if data and len(data["criteria_names"]):
        from .units import criterion_unit

        rows = [[n, f"{v:.6g}", criterion_unit(n)] for n, v in zip(data["criteria_names"], data["criteria_values"])]
        out.append(table(["criterion (toolpath.npz)", "value", "unit"], rows))
    return out


def plan_data(path: Path) -> dict | None:
    """``toolpath.npz`` (the part sampled on a (u, v) grid, the CC points, the criteria) as
    arrays, read without pickles; None when absent, a one-line error naming it when broken."""
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in ("surface", "cc", "criteria_names", "criteria_values")}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as e:
        raise ConfigError(f"{path}: unreadable ({' '.join(str(e).split())[:200]})") from None
    if data["surface"].ndim != 3 or data["surface"].shape[-1] != 3 or data["cc"].ndim != 2:
        raise ConfigError(f"{path}: surface must be (n, m, 3) and cc (k, 3) points")
    return data
