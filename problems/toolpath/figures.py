"""The CC pattern of a toolpath drawn on its surface (the analog of Fountas' Fig. 2)."""

from __future__ import annotations

import numpy as np


def cc_pattern_png(surface, points: np.ndarray, pass_index: np.ndarray, title: str = "",
                   color: np.ndarray | None = None, color_label: str = "",
                   categories: int | None = None) -> bytes:
    """:func:`cc_pattern_figure` as PNG bytes."""
    from evoplan.figure_style import png

    return png(cc_pattern_figure(surface, points, pass_index, title, color, color_label, categories))


def cc_pattern_figure(surface, points: np.ndarray, pass_index: np.ndarray, title: str = "",
                      color: np.ndarray | None = None, color_label: str = "",
                      categories: int | None = None):
    """The surface (3D wireframe, X, Y and Z on one scale) with the CC points, and a plan view (XY).

    ``points: (m, 3)`` CC points in machining order, ``pass_index: (m,)``; ``color: (m,)``
    an optional per-point value (e.g. the chord error) for the plan view; with
    ``categories = n`` it holds labels 0 .. n - 1 (e.g. zones), drawn in n distinct colours
    (the zone map's).
    """
    from evoplan.figure_style import PALETTE  # sets the Agg backend before pyplot loads

    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    g = np.linspace(0.0, 1.0, 41)
    U, V = np.meshgrid(g, g)
    S = surface.points(U.ravel(), V.ravel()).reshape(41, 41, 3)
    fig = plt.figure(figsize=(11, 4.8), dpi=110)
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.plot_wireframe(S[..., 0], S[..., 1], S[..., 2], color="0.75", linewidth=0.4)
    starts = np.flatnonzero(np.r_[True, pass_index[1:] != pass_index[:-1], True])
    for a, b in zip(starts[:-1], starts[1:]):
        ax.plot(points[a:b, 0], points[a:b, 1], points[a:b, 2], lw=0.8, color=PALETTE[4])
    ax.scatter(points[:, 0], points[:, 1], points[:, 2], s=3, color=PALETTE[5], depthshade=False)
    ax.set_xlabel("X (mm)"), ax.set_ylabel("Y (mm)"), ax.set_zlabel("Z (mm)")
    span = np.ptp(np.concatenate([S.reshape(-1, 3), points]), axis=0)
    ax.set_box_aspect(np.maximum(span, 1e-3 * span.max()))  # one mm is one mm on every axis
    ax.zaxis.set_major_locator(MaxNLocator(3))  # a flat box has room for few Z labels
    ax.set_title(f"{len(points)} CC points, {len(starts) - 1} passes")
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.contour(S[..., 0], S[..., 1], S[..., 2], levels=12, colors="0.8", linewidths=0.5)
    ax2.plot(points[:, 0], points[:, 1], lw=0.5, color="0.5")
    if color is None:  # one colour: no colour map (matplotlib warns when given one unused)
        scale = {"color": PALETTE[5]}
    elif not categories:
        scale = {"c": color, "cmap": "viridis"}
    else:
        scale = {"c": color, "cmap": plt.get_cmap("tab20", categories), "vmin": -0.5,
                 "vmax": categories - 0.5}
    sc = ax2.scatter(points[:, 0], points[:, 1], s=5, **scale)
    if color is not None:
        bar = fig.colorbar(sc, ax=ax2, label=color_label)
        if categories:
            bar.set_ticks(range(categories))
    ax2.use_sticky_edges = False  # the contour's limits would put the edge passes on the frame
    ax2.margins(0.03)
    ax2.set_aspect("equal")
    ax2.set_xlabel("X (mm)"), ax2.set_ylabel("Y (mm)")
    ax2.set_title("plan view")
    fig.suptitle(title)
    return fig
