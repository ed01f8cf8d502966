"""The deviation map of an ``evoplan simulate`` folder on the part (3D) and in plan, on a
symmetric scale with the tolerance band marked, from ``deviation.npz`` (the map as data)."""

from __future__ import annotations

from pathlib import Path

import numpy as np


__all__ = ["coarsen", "deviation_figures", "read_npz"]

MAX_CELLS = 250  # cells per side drawn, at most


def read_npz(path: Path) -> dict:
    """The arrays of ``path`` (no pickles); one line naming the file otherwise."""
    from ..errors import ConfigError

    try:
        with np.load(path, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except (OSError, ValueError) as e:
        raise ConfigError(f"{path}: unreadable ({e})") from None


def coarsen(values: np.ndarray, k: int) -> np.ndarray:
    """Blocks of k x k cells -> the value of largest magnitude in each (NaN ignored): a gouge or
    a ridge of one cell stays visible at the display resolution."""
    ny, nx = values.shape
    py, px = (-ny) % k, (-nx) % k
    v = np.pad(values, ((0, py), (0, px)), constant_values=np.nan)
    b = v.reshape(v.shape[0] // k, k, v.shape[1] // k, k).transpose(0, 2, 1, 3).reshape(v.shape[0] // k, v.shape[1] // k, -1)
    mag = np.where(np.isnan(b), -1.0, np.abs(b))
    at = mag.argmax(axis=2)
    return np.take_along_axis(b, at[..., None], axis=2)[..., 0]


def _scale(shown: np.ndarray, tolerance: float) -> float:
    finite = np.abs(shown[np.isfinite(shown)])
    top = float(np.quantile(finite, 0.999)) if finite.size else tolerance
    return max(top, 2.0 * tolerance, 1e-3)


def _colorscale(vmax: float, tol: float) -> list:
    """RdBu reversed (blue gouge, red material left) with the +-tol band in pale green."""
    t = 0.5 * tol / vmax
    return [[0.0, "#08306b"], [max(0.5 - t - 1e-6, 0.0), "#6baed6"], [0.5 - t, "#c7e9c0"], [0.5 + t, "#c7e9c0"],
            [min(0.5 + t + 1e-6, 1.0), "#fc9272"], [1.0, "#67000d"]]


def deviation_figures(d: dict):
    """(3D figure, plan figure, caption) of a deviation map's data (``deviation.npz``)."""
    import plotly.graph_objects as go

    res = d["residual"].astype(float)
    inside = d["inside"].astype(bool)
    allowance, tol = float(d["allowance"]), float(d["tolerance"])
    shown = np.where(inside & (res < allowance), res, np.nan)
    uncut = inside & ~(res < allowance)
    h = float(d["h"])
    k = max(1, int(np.ceil(max(shown.shape) / MAX_CELLS)))
    s = coarsen(shown, k)
    z = coarsen(np.where(inside, d["z"].astype(float), np.nan), k)
    un = coarsen(np.where(uncut, 1.0, np.nan), k)
    xs = float(d["x0"]) + h * (k * np.arange(s.shape[1]) + (k - 1) / 2)
    ys = float(d["y0"]) + h * (k * np.arange(s.shape[0]) + (k - 1) / 2)
    vmax = _scale(shown, tol)
    cs = _colorscale(vmax, tol)
    bar = dict(title=dict(text="deviation (mm)<br>+ left, − gouge", side="top"), x=1.0, xanchor="right",
               tickvals=[-vmax, -tol, tol, vmax], ticktext=[f"{-vmax:.3g}", f"−{tol:g} (tol.)", f"+{tol:g} (tol.)",
                                                            f"{vmax:.3g}"])
    text = np.where(np.isfinite(s), np.char.mod("%.4f mm", np.nan_to_num(s)), "uncut / off the part")
    f3 = go.Figure([go.Surface(x=xs, y=ys, z=z, surfacecolor=np.nan_to_num(s, nan=0.0), cmin=-vmax, cmax=vmax,
                               colorscale=cs, colorbar=bar, name="deviation", text=text,
                               hovertemplate="x %{x:.2f} mm<br>y %{y:.2f} mm<br>%{text}<extra></extra>")])
    if np.isfinite(un).any():
        f3.add_trace(go.Surface(x=xs, y=ys, z=np.where(np.isfinite(un), z, np.nan), showscale=False,
                                colorscale=[[0, "#9e9e9e"], [1, "#9e9e9e"]], name="uncut", hoverinfo="skip",
                                showlegend=True))
    from .paths import LEGEND_BELOW, scene

    f3.update_layout(scene=scene(), height=640, meta="deviation3d", margin=dict(l=0, r=0, t=40, b=0),
                     title="deviation on the part (3D)", legend=LEGEND_BELOW)
    f2 = go.Figure([go.Heatmap(x=xs, y=ys, z=s, zmin=-vmax, zmax=vmax, colorscale=cs, colorbar=bar,
                               name="deviation", hovertemplate="x %{x:.2f} mm<br>y %{y:.2f} mm<br>"
                                                               "%{z:.4f} mm<extra></extra>")])
    if np.isfinite(un).any():
        f2.add_trace(go.Heatmap(x=xs, y=ys, z=un, colorscale=[[0, "#9e9e9e"], [1, "#9e9e9e"]], showscale=False,
                                name=f"uncut (stock ≥ {allowance:g} mm)", hoverinfo="skip", showlegend=True))
    f2.update_layout(height=620, meta="deviation_plan", title="deviation in plan (XY)",
                     xaxis=dict(title="X (mm)", constrain="domain"),
                     yaxis=dict(title="Y (mm)", scaleanchor="x", scaleratio=1),
                     legend=dict(orientation="h", x=0, y=-0.12), margin=dict(l=70, r=20, t=50, b=60))
    cap = (f"Symmetric scale ±{vmax:.3g} mm (the 99.9th percentile of |deviation|, at least twice the "
           f"tolerance); the tolerance band ±{tol:g} mm is pale green; grey: uncut (stock ≥ {allowance:g} mm). "
           f"Grid {h:g} mm shown in blocks of {k}×{k} cells, each drawn with its largest |deviation|.")
    return f3, f2, cap


