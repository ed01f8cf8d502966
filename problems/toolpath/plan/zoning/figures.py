"""The zone map with each zone's passes (analogs of Djebali Fig. 17-18 and Herraz Fig. 6)."""

from __future__ import annotations

import numpy as np

from .samples import SurfaceSamples

__all__ = ["border_segments", "pass_segments", "zone_map_figure", "zone_map_png"]


def pass_segments(samples: SurfaceSamples, cell_zone: np.ndarray, zone: int, passes) -> list:
    """XY polylines of a zone's passes: the zone's samples next to each plane, by t.

    A pass is broken where the zone is interrupted along it (a gap of 3 sample spacings).
    """
    sel = cell_zone == zone
    x, y = samples.x[sel], samples.y[sel]
    fx, fy = np.cos(passes.alpha), np.sin(passes.alpha)
    off, t = -fy * x + fx * y, fx * x + fy * y
    lines = []
    for s_k in passes.s:
        near = np.abs(off - s_k) <= 0.5 * samples.spacing
        if near.sum() < 2:
            continue
        tt = np.sort(t[near])
        breaks = np.flatnonzero(np.diff(tt) > 3 * samples.spacing)
        for a, b in zip(np.r_[0, breaks + 1], np.r_[breaks + 1, len(tt)]):
            if b - a >= 2:
                t0, t1 = tt[a], tt[b - 1]
                lines.append([(-fy * s_k + fx * t0, fx * s_k + fy * t0),
                              (-fy * s_k + fx * t1, fx * s_k + fy * t1)])
    return lines


def border_segments(labels: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(b, 2, 2) XY segments of the zone borders: the mesh cell edges shared by two cells of
    different zones. ``corners: (n + 1, m + 1, 3)`` the surface at the cells' corners."""
    xy = corners[..., :2]
    i, j = np.nonzero(labels[1:, :] != labels[:-1, :])  # cells (i, j) | (i + 1, j): edge u = i + 1
    across_u = np.stack([xy[i + 1, j], xy[i + 1, j + 1]], axis=1)
    i, j = np.nonzero(labels[:, 1:] != labels[:, :-1])  # cells (i, j) | (i, j + 1): edge v = j + 1
    across_v = np.stack([xy[i, j + 1], xy[i + 1, j + 1]], axis=1)
    return np.concatenate([across_u, across_v])


def zone_map_figure(surface, plan, samples: SurfaceSamples, title: str = ""):
    """The zones in plan view (XY) coloured by zone (:func:`evoplan.figure_style.zone_colors`),
    with their passes and the zone borders, in the shared figure style."""
    from evoplan.figure_style import figure, zone_colors  # sets the Agg backend before pyplot loads

    from matplotlib.collections import LineCollection
    from matplotlib.colors import ListedColormap

    labels = plan.labels
    n, m = labels.shape
    gu, gv = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, m + 1), indexing="ij")
    corners = surface.points(gu.ravel(), gv.ravel()).reshape(n + 1, m + 1, 3)
    cell_zone = labels.ravel()[samples.cell(n, m)]
    fig, (ax,) = figure(1, width=7.5, height=8)
    ax.grid(False)
    colors = zone_colors(len(plan.zones))
    ax.pcolormesh(corners[..., 0], corners[..., 1], labels, cmap=ListedColormap(colors), alpha=0.45,
                  vmin=-0.5, vmax=len(colors) - 0.5, shading="flat")
    ax.add_collection(LineCollection(border_segments(labels, corners), colors="k", linewidths=1.2))
    for z in plan.zones:
        segs = pass_segments(samples, cell_zone, z.zone, z.passes)
        ax.add_collection(LineCollection(segs, colors=[colors[z.zone % len(colors)]], linewidths=0.7))
        inside = labels == z.zone
        cx = corners[:-1, :-1, 0][inside].mean()
        cy = corners[:-1, :-1, 1][inside].mean()
        ax.annotate(f"{z.zone}: {round(z.direction_deg) % 180:.0f}°\n{z.length:.0f} mm", (cx, cy),
                    ha="center", va="center", fontsize=7,
                    bbox=dict(boxstyle="round", fc="white", alpha=0.7, lw=0))
    ax.set_aspect("equal")
    ax.set_xlabel("X (mm)")
    ax.set_ylabel("Y (mm)")
    ax.set_title(title or f"{plan.method}: {len(plan.zones)} zones, "
                          f"total {plan.total_length:.0f} mm (Eq. 4)")
    return fig


def zone_map_png(surface, plan, samples: SurfaceSamples, title: str = "") -> bytes:
    """:func:`zone_map_figure` as PNG bytes (:func:`evoplan.figure_style.png`)."""
    from evoplan.figure_style import png

    return png(zone_map_figure(surface, plan, samples, title))
