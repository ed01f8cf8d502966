"""Figures of a simulated cut: the deviation map (a Geomagic-style colour map of what is
left and what is gouged, the analog of Fountas' Fig. 8) and the deviation histogram.

Both use a symmetric diverging scale in mm (blue: gouge, below the design surface; red:
material left), mark the tolerance band +-``tolerance``, and show the cells no pose
reached (uncut, stock left) in grey. Zone borders of a zoned plan are drawn in black.
Both are drawn in the shared style (:mod:`evoplan.figure_style`: its figure, resolution,
palette and PNG output); ``*_figure`` returns the matplotlib figure, ``*_png`` its PNG bytes.
"""

from __future__ import annotations

import numpy as np

from .design import DesignGrid

__all__ = ["deviation_map_figure", "deviation_map_png", "deviation_hist_figure", "deviation_hist_png"]


def _scale(values: np.ndarray, tolerance: float) -> float:
    finite = np.abs(values[np.isfinite(values)])
    top = float(np.quantile(finite, 0.999)) if finite.size else tolerance
    return max(top, 2.0 * tolerance, 1e-3)


def deviation_map_figure(grid: DesignGrid, residual: np.ndarray, *, tolerance: float,
                         allowance: float, labels: np.ndarray | None = None, title: str = ""):
    """The deviation map (see the module docstring)."""
    from evoplan.figure_style import figure  # sets the Agg backend before pyplot loads

    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    res = np.where(grid.inside, residual, np.nan)
    uncut = grid.inside & ~(res < allowance)
    shown = np.where(uncut, np.nan, res)
    vmax = _scale(shown, tolerance)
    extent = (grid.x0 - grid.h / 2, grid.x0 + (grid.shape[1] - 0.5) * grid.h,
              grid.y0 - grid.h / 2, grid.y0 + (grid.shape[0] - 0.5) * grid.h)
    fig, (ax,) = figure(1, width=8.0, height=6.5)
    ax.grid(False)
    im = ax.imshow(shown, origin="lower", extent=extent, cmap="RdBu_r", vmin=-vmax, vmax=vmax,
                   interpolation="nearest")
    ax.imshow(np.where(uncut, 1.0, np.nan), origin="lower", extent=extent,
              cmap=ListedColormap(["#9e9e9e"]), interpolation="nearest")
    xs, ys = grid.xs, grid.ys
    if np.isfinite(shown).any():
        ax.contour(xs, ys, np.nan_to_num(shown, nan=0.0), levels=[-tolerance, tolerance],
                   colors=["#0b3d91", "#7f0000"], linewidths=0.4)
    if labels is not None and labels.max() > 0:
        border = np.zeros(labels.shape, bool)
        border[:, 1:] |= labels[:, 1:] != labels[:, :-1]
        border[1:, :] |= labels[1:, :] != labels[:-1, :]
        border &= grid.inside
        ax.imshow(np.where(border, 1.0, np.nan), origin="lower", extent=extent,
                  cmap=ListedColormap(["black"]), interpolation="nearest")
    cb = fig.colorbar(im, ax=ax, shrink=0.85)
    cb.set_label("deviation along the normal (mm): + material left, - gouge")
    for v in (-tolerance, tolerance):
        cb.ax.axhline(v, color="black", lw=0.8)
    handles = [Patch(color="#9e9e9e", label=f"uncut (stock >= {allowance:g} mm)"),
               Patch(facecolor="none", edgecolor="#7f0000",
                     label=f"tolerance band +-{tolerance:g} mm (contours)")]
    if labels is not None and labels.max() > 0:
        handles.append(Patch(color="black", label="zone borders"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(0.0, -0.08), ncol=3,
              fontsize=8, frameon=False)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_aspect("equal")
    ax.set_title(title or "simulated cut: deviation from the design surface", fontsize=10)
    return fig


def deviation_map_png(grid: DesignGrid, residual: np.ndarray, *, tolerance: float,
                      allowance: float, labels: np.ndarray | None = None, title: str = "") -> bytes:
    """:func:`deviation_map_figure` as PNG bytes."""
    from evoplan.figure_style import png

    return png(deviation_map_figure(grid, residual, tolerance=tolerance, allowance=allowance,
                                    labels=labels, title=title))


def deviation_hist_figure(grid: DesignGrid, residual: np.ndarray, *, tolerance: float,
                          allowance: float, title: str = ""):
    """Area-weighted histogram of the deviation; uncut cells counted apart (in the title)."""
    from evoplan.figure_style import PALETTE, figure

    area = grid.cell_area()
    keep = grid.inside & (residual < allowance)
    uncut = float(area[grid.inside & ~(residual < allowance)].sum() / max(area.sum(), 1e-300))
    vals, w = residual[keep], area[keep]
    vmax = _scale(vals, tolerance)
    fig, (ax,) = figure(1, width=7.0, height=4.0)
    ax.hist(np.clip(vals, -vmax, vmax), bins=120, range=(-vmax, vmax),
            weights=100.0 * w / max(area.sum(), 1e-300), color=PALETTE[4])
    for v in (-tolerance, tolerance):
        ax.axvline(v, color=PALETTE[5], lw=1.0, ls="--")
    ax.axvline(0.0, color="black", lw=0.6)
    ax.set_xlabel(f"deviation along the normal (mm), clipped to +-{vmax:.3g}")
    ax.set_ylabel("share of the part's area (%)")
    ax.set_title(title or f"deviation histogram (dashed: +-{tolerance:g} mm; uncut "
                 f"{100 * uncut:.2f} % of the area, not shown)", fontsize=10)
    return fig


def deviation_hist_png(grid: DesignGrid, residual: np.ndarray, *, tolerance: float,
                       allowance: float, title: str = "") -> bytes:
    """:func:`deviation_hist_figure` as PNG bytes."""
    from evoplan.figure_style import png

    return png(deviation_hist_figure(grid, residual, tolerance=tolerance, allowance=allowance, title=title))
