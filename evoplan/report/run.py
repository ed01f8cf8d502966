"""A run's report: convergence with hover, the best decisions with units, the toolpath in 3D."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ConfigError
from .folder import read_csv, read_json
from .page import Section, note, table

#: units of the toolpath problem's decisions (problems/toolpath/genes.py)
DECISION_UNITS = {"tool": "index in the tool list", "stepover": "% of D", "lead": "deg",
                  "tilt": "deg", "step": "mm"}
#: paths longer than this are drawn decimated, each dropped point within DISPLAY_TOLERANCE
DECIMATE_ABOVE = 20_000
DISPLAY_TOLERANCE = 0.01  # mm
#: plotly's default qualitative colours, one per section of the path (cycled)
COLOURS = ("#636EFA", "#EF553B", "#00CC96", "#AB63FA", "#FFA15A", "#19D3F3", "#FF6692",
           "#B6E880", "#FF97FF", "#FECB52")


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
    if log:  # labels at 1, 2 and 5 of each decade (plotly's default crowds 1..9 together)
        fig.update_yaxes(dtick="D2")
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
        rows.append([name, value, DECISION_UNITS.get(name, ""), domain])
    rows.append(["objective", best.get("objective"), "", "minimized"])
    facts = [f"{k} {best[k]}" for k in ("problem", "algorithm", "seed", "generations",
                                        "evaluations", "stop_reason") if k in best]
    return table(["decision", "value", "unit", "domain"], rows) + note(", ".join(facts))


def toolpath(path: Path) -> list:
    """The APT toolpath in 3D, one colour per section (zone/pass), rapids dashed, equal scales."""
    import plotly.graph_objects as go

    from ..problems.toolpath.export.apt_read import AptError, read_apt

    try:
        apt = read_apt(path)
    except AptError as e:
        raise ConfigError(f"{path}: {e}") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ConfigError(f"{path}: unreadable ({e})") from None
    tip, rapid, section = apt.tip, np.asarray(apt.rapid, bool), np.asarray(apt.section)
    drawn = ""
    if len(tip) > DECIMATE_ABOVE:
        keep = decimate(tip, rapid, section, DISPLAY_TOLERANCE)
        worst = deviation(tip, keep)
        if worst <= DISPLAY_TOLERANCE:
            tip, rapid, section = tip[keep], rapid[keep], section[keep]
            drawn = (f" Drawn with {int(keep.sum())} of its points: the points left out lie at most "
                     f"{worst:.4f} mm from the drawn line (display tolerance {DISPLAY_TOLERANCE:g} mm).")
    fig = go.Figure()
    hover = "x %{x:.3f}<br>y %{y:.3f}<br>z %{z:.3f}<extra>%{fullData.name}</extra>"
    # cutting moves: point i joins i-1 by a feed move; a new trace per section
    for s in np.unique(section):
        if s < 0:
            continue
        idx = np.flatnonzero(section == s)
        # break the line where the move into a point is a rapid (drawn separately)
        xyz = _polyline(tip, idx, ~rapid)
        fig.add_trace(go.Scatter3d(x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2], mode="lines",
                                   line=dict(width=4, color=COLOURS[int(s) % len(COLOURS)]),
                                   name=apt.sections[int(s)].lower(), hovertemplate=hover,
                                   legendgroup="cut"))
    moves = np.flatnonzero(rapid[1:]) + 1
    if moves.size:
        segs = np.full((3 * moves.size, 3), np.nan)
        segs[0::3], segs[1::3] = tip[moves - 1], tip[moves]
        fig.add_trace(go.Scatter3d(x=segs[:, 0], y=segs[:, 1], z=segs[:, 2], mode="lines",
                                   line=dict(width=2, color="#555", dash="dash"),
                                   name="rapids", hovertemplate=hover))
    fig.update_layout(scene=dict(aspectmode="data", xaxis_title="x (mm)", yaxis_title="y (mm)",
                                 zaxis_title="z (mm)", camera=dict(eye=dict(x=1.5, y=-1.6, z=1.1))),
                      height=720,
                      margin=dict(l=0, r=0, t=30, b=0))
    tool = f"tool D{apt.diameter:g} r{apt.corner_radius:g} mm"
    text = (f"{len(apt)} points in {len(apt.sections)} sections, {int(rapid.sum())} rapid moves, "
            f"{tool}; one colour per zone/pass section (click the legend to hide one), rapids dashed, "
            f"equal axis scales.{drawn}")
    return [note(text), fig]


def deviation(tip: np.ndarray, keep: np.ndarray) -> float:
    """Largest distance of a point to the segment of kept points that brackets it (an upper
    bound of its distance to the drawn line)."""
    k = np.flatnonzero(keep)
    if len(k) < 2:
        return 0.0
    seg = np.clip(np.searchsorted(k, np.arange(len(tip)), side="right") - 1, 0, len(k) - 2)
    a, ab = tip[k[seg]], tip[k[seg + 1]] - tip[k[seg]]
    t = np.clip(np.einsum("ij,ij->i", tip - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
    return float(np.linalg.norm(a + t[:, None] * ab - tip, axis=1).max())


def decimate(tip: np.ndarray, rapid: np.ndarray, section: np.ndarray, tolerance: float,
             passes: int = 6) -> np.ndarray:
    """Which points to draw so that every point left out lies within ``tolerance`` of the line.

    Each pass looks at every other kept point whose neighbours are in its section and reached
    by feed moves, and drops it when it lies within ``tolerance / passes`` of the segment
    joining its kept neighbours. A dropped point's distance to the final line is at most the
    sum of the passes' tolerances in the usual case; :func:`deviation` measures it, and the
    report draws every point when the measure exceeds the tolerance.
    """
    keep = np.ones(len(tip), bool)
    step = tolerance / passes
    for _ in range(passes):
        k = np.flatnonzero(keep)
        j = np.arange(1, len(k) - 1, 2)
        if j.size == 0:
            break
        a, p, b = k[j - 1], k[j], k[j + 1]
        ok = (section[a] == section[p]) & (section[p] == section[b]) & ~rapid[p] & ~rapid[b]
        ab = tip[b] - tip[a]
        t = np.clip(np.einsum("ij,ij->i", tip[p] - tip[a], ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
        dist = np.linalg.norm(tip[a] + t[:, None] * ab - tip[p], axis=1)
        drop = p[ok & (dist < step)]
        if drop.size == 0:
            break
        keep[drop] = False
    return keep


def _polyline(tip: np.ndarray, idx: np.ndarray, fed: np.ndarray) -> np.ndarray:
    """Points ``idx`` joined by feed moves, with a NaN gap before each point reached by a rapid
    and between non-consecutive indices."""
    gap = np.zeros(idx.size, bool)
    gap[1:] = (np.diff(idx) != 1) | ~fed[idx[1:]]
    n = idx.size + int(gap.sum())
    out = np.full((n, 3), np.nan)
    pos = np.arange(idx.size) + np.cumsum(gap)
    out[pos] = tip[idx]
    return out
