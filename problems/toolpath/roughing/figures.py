"""Figure of the roughing layers (the analog of Abbas' Figs. 5-7): a 3D view of the surface
and the layers, and the section at the middle of the part in Y."""

from __future__ import annotations

import numpy as np


def layers_png(stock, floor: np.ndarray, layers: np.ndarray, method: str, title: str = "") -> bytes:
    """:func:`layers_figure` as PNG bytes."""
    from evoplan.figure_style import png

    return png(layers_figure(stock, floor, layers, method, title))


def layers_figure(stock, floor: np.ndarray, layers: np.ndarray, method: str, title: str = ""):
    """Left, the surface and every layer (wireframes); right, the section at mid Y with the
    stock top, the layers (morphing: curves, z-level: the cut extents at each level) and the
    allowance floor F, its legend outside the data (right of the section)."""
    from evoplan.figure_style import PALETTE, legend_outside  # sets the Agg backend first

    import matplotlib.pyplot as plt

    g = stock.grid
    fig = plt.figure(figsize=(12, 5), dpi=110)
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    X, Y = np.meshgrid(g.xs, g.ys)
    step = max(1, len(g.xs) // 30)
    zs = np.where(np.isfinite(stock.z_surface), stock.z_surface, np.nan)
    ax3.plot_surface(X[::step, ::step], Y[::step, ::step], zs[::step, ::step], cmap="viridis", alpha=0.8)
    stack = layers if layers.ndim == 3 else np.where(floor[None] <= layers[:, None, None], layers[:, None, None], np.nan)
    for k, h in enumerate(stack):
        ax3.plot_wireframe(X[::step * 2, ::step * 2], Y[::step * 2, ::step * 2], h[::step * 2, ::step * 2],
                           color=plt.cm.autumn(k / max(1, len(stack) - 1)), linewidth=0.4)
    ax3.set_xlabel("X (mm)")
    ax3.set_ylabel("Y (mm)")
    ax3.set_zlabel("Z (mm)")
    ax = fig.add_subplot(1, 2, 2)
    row = len(g.ys) // 2
    ax.axhline(stock.z_top, color="k", linewidth=1, label="stock top")
    for k, h in enumerate(stack):
        ax.plot(g.xs, h[row], color=plt.cm.autumn(k / max(1, len(stack) - 1)), linewidth=1,
                label="layers" if k == 0 else None)
    ax.plot(g.xs, floor[row], ls="--", color=PALETTE[4], linewidth=1, label="allowance floor F")
    ax.plot(g.xs, zs[row], color=PALETTE[2], linewidth=2, label="surface")
    ax.set_xlabel(f"X (mm), section at Y = {g.ys[row]:.1f} mm")
    ax.set_ylabel("Z (mm)")
    legend_outside(ax, fontsize=8)
    fig.suptitle(title or f"{method} roughing: {len(stack)} layers")
    return fig
