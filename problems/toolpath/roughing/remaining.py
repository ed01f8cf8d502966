"""Morphing layers cut only where material remains above them (the stock Z-map tells where).

Abbas' layers (``layers.morph_layers``) cover the whole block, and a layer's zig-zag over
the block also passes where the layers above, or the tool's flat bottom sweeping down a
slope, have already taken the stock below it. Here the stock is a Z-map (``zmap.StockZMap``)
cut by every layer in turn; before layer k the highest stock under the tool's disk,
``M = max over the disk of h``, is compared with the layer: the tool at (x, y) removes
something only where ``M(x, y) > H_k(x, y) + min_chip``. Along each raster line of the layer
(the same lines as ``zigzag.morph_path``, zig-zag order) only those runs are cut, at the
layer's heights. From the end of one run to the start of the next the tool either stays
down and follows the layer along the straight XY link (through air or a thin layer of stock:
the stock above H_k is at most the previous layer's step plus ``min_chip``, so never deeper
than D_cut), or retracts to ``safe_z``, rapids over and plunges, whichever takes less time at
the feed, the rapid rate and the plunge feed (``rapid``). A layer with no material left is
skipped.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from ..export.toolpath import Tool, Toolpath
from .layers import Grid
from .zigzag import _Builder, _runs, raster_rows
from .zmap import StockZMap


def material_above(stock: StockZMap, layer: np.ndarray, radius: float, min_chip: float) -> tuple[np.ndarray, np.ndarray]:
    """(mask (ny, nx) where the tool at the layer's height would remove more than ``min_chip``,
    M the highest stock under the tool's disk)."""
    top = ndimage.maximum_filter(stock.h, footprint=stock.grid.disk(radius), mode="nearest")
    return top > layer + min_chip, top


def _link_points(grid: Grid, layer: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Points from after ``p`` to ``q`` along the straight XY link, at the layer's heights
    (sampled at most a cell apart; the end is ``q`` itself)."""
    n = max(1, int(math.ceil(np.hypot(*(q[:2] - p[:2])) / grid.cell)))
    t = np.linspace(0.0, 1.0, n + 1)[1:, None]
    out = p + t * (q - p)
    r, c = grid.index(out[:-1, 0], out[:-1, 1])
    out[:-1, 2] = layer[r, c]
    out[-1] = q
    return out


def morph_remaining_path(grid: Grid, layers: np.ndarray, tool: Tool, stepover: float, *, z_top: float,
                         safe_z: float, feed: float, plunge_feed: float, rapid: float = 10000.0,
                         tolerance: float = 0.01, min_chip: float = 0.01, comments=()) -> Toolpath:
    """Zig-zag over each morphing layer (N, ny, nx) where material remains (module
    docstring), layer k as section k."""
    rows = raster_rows(grid, stepover)
    radius = 0.5 * tool.diameter
    stock = StockZMap(grid, z_top)
    b = _Builder(safe_z)
    for k, h in enumerate(layers):
        start = sum(len(p) for p in b.pts)
        mask, top = material_above(stock, h, radius, min_chip)
        down = False
        for n, row in enumerate(rows):
            order = np.arange(len(grid.xs))[::-1] if n % 2 else np.arange(len(grid.xs))
            for a, e in _runs(mask[row, order]):
                cols = order[a:e]
                run = np.column_stack([grid.xs[cols], np.full(len(cols), grid.ys[row]), h[row, cols]])
                if down:
                    here = b.pts[-1][-1]
                    link = _link_points(grid, h, here, run[0])
                    stay = np.linalg.norm(np.diff(np.vstack([here, link]), axis=0), axis=1).sum() / feed
                    drop = top[row, cols[0]] + b.gap - run[0, 2]
                    leave = ((safe_z - here[2]) + np.hypot(*(run[0, :2] - here[:2])) + (safe_z - run[0, 2] - drop)) \
                        / rapid + drop / plunge_feed
                    if stay <= leave:
                        b.cut(link, k, tolerance)
                    else:
                        b.retract()
                        b.enter(run[0], k, top[row, cols[0]])
                else:
                    b.enter(run[0], k, top[row, cols[0]])
                    down = True
                if len(run) > 1:
                    b.cut(run[1:], k, tolerance)
        if down:
            b.retract()
            stock.stamp(np.vstack(b.pts)[start:], radius)
    if not b.pts:
        raise ValueError("roughing: no material above any morphing layer (the stock is already the floor)")
    return b.build("roughing (morphing layers, remaining material)", tool, feed, plunge_feed, comments)
