"""Stock Z-map: a flat end mill cutting a block, dexel by dexel (one height per grid cell).

Every move of a toolpath is sampled at most half a cell apart in XY (a plunge at its end only);
at each sample the cells whose centres lie within the tool radius of the axis are lowered to
the tool's bottom. Per sample the kernel records the depth of cut (the most material above
the bottom inside the footprint, before the cut) and the volume removed. From these:

- ``max_depth``: the deepest cut of the whole path (must stay <= D_cut);
- per section (layer): the volume removed, the deepest cut, the cutting length and the
  air-cutting length (feed moves whose samples remove nothing deeper than ``air_eps``);
- ``rapid_volume``: material a rapid move would hit (must be 0: a rapid into stock is a crash).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..export.toolpath import Toolpath
from .layers import Grid


@numba.njit(cache=True)
def _cut(h, x0, y0, cell, radius, px, py, pz, depth, removed):  # pragma: no cover - compiled
    ny, nx = h.shape
    n = int(math.ceil(radius / cell)) + 1
    r2 = radius * radius * (1.0 + 1e-9)  # a dexel on the rim counts the same from every sample
    for s in range(len(px)):
        ci = int(math.floor((px[s] - x0) / cell + 0.5))
        ri = int(math.floor((py[s] - y0) / cell + 0.5))
        dmax = 0.0
        vol = 0.0
        for r in range(max(ri - n, 0), min(ri + n + 1, ny)):
            dy = y0 + r * cell - py[s]
            for c in range(max(ci - n, 0), min(ci + n + 1, nx)):
                dx = x0 + c * cell - px[s]
                if dx * dx + dy * dy <= r2:
                    d = h[r, c] - pz[s]
                    if d > 0.0:
                        vol += d
                        h[r, c] = pz[s]
                        if d > dmax:
                            dmax = d
        depth[s] = dmax
        removed[s] = vol * cell * cell


class StockZMap:
    """Block stock over ``grid`` with its top at ``z_top``; ``cut`` machines a toolpath."""

    def __init__(self, grid: Grid, z_top: float):
        self.grid = grid
        self.h = np.full((len(grid.ys), len(grid.xs)), float(z_top))

    def _samples(self, tip: np.ndarray):
        """Sample points (k, 3), the index of the point each one moves to, sub-segment lengths."""
        seg = np.diff(tip, axis=0)
        length = np.linalg.norm(seg, axis=1)
        flat = np.linalg.norm(seg[:, :2], axis=1)  # samples by XY length: the same XY spots each layer
        n = np.maximum(1, np.ceil(flat / (0.5 * self.grid.cell) - 1e-9)).astype(int)
        move = np.repeat(np.arange(len(seg)), n)
        k = np.arange(len(move)) - np.repeat(np.cumsum(n) - n, n) + 1
        t = (k / np.repeat(n, n))[:, None]
        pts = tip[move] + t * seg[move]
        return pts, move + 1, (length / n)[move]

    def _run(self, h: np.ndarray, pts: np.ndarray, radius: float):
        depth, removed = np.zeros(len(pts)), np.zeros(len(pts))
        g = self.grid
        _cut(h, g.xs[0], g.ys[0], g.cell, radius, np.ascontiguousarray(pts[:, 0]),
             np.ascontiguousarray(pts[:, 1]), np.ascontiguousarray(pts[:, 2]), depth, removed)
        return depth, removed

    def probe(self, tip: np.ndarray, radius: float) -> float:
        """Deepest cut the polyline ``tip`` (k, 3) would take from the stock as it is now
        (a dry run: the stock is not changed)."""
        pts = self._samples(np.asarray(tip, float))[0]
        r, c = self.grid.index(pts[:, 0], pts[:, 1])
        n = int(np.ceil(radius / self.grid.cell)) + 1
        r0, c0 = max(r.min() - n, 0), max(c.min() - n, 0)
        win = self.h[r0:r.max() + n + 1, c0:c.max() + n + 1].copy()
        shift = np.array([self.grid.xs[c0] - self.grid.xs[0], self.grid.ys[r0] - self.grid.ys[0], 0.0])
        return float(self._run(win, pts - shift, radius)[0].max(initial=0.0))

    def stamp(self, tip: np.ndarray, radius: float) -> None:
        """Cut the polyline ``tip`` (k, 3) into the stock (no statistics)."""
        self._run(self.h, self._samples(np.asarray(tip, float))[0], radius)

    def cut(self, tp: Toolpath, air_eps: float = 1e-3) -> dict:
        """Machine ``tp`` (a flat end mill: its tool radius, vertical axis); statistics."""
        if tp.multi_axis:
            raise ValueError("the Z-map simulates 3-axis (vertical axis) toolpaths only")
        pts, point, ds = self._samples(tp.tip)
        depth, removed = self._run(self.h, pts, 0.5 * tp.tool.diameter)
        rapid = tp.rapid[point]
        feed = ~rapid
        section = tp.section[point]
        layers = []
        for k in np.unique(section[feed & (section >= 0)]):
            m = feed & (section == k)
            layers.append({"section": int(k), "removed_mm3": float(removed[m].sum()),
                           "max_depth": float(depth[m].max()), "cutting_length": float(ds[m].sum()),
                           "air_length": float(ds[m & (depth < air_eps)].sum())})
        return {"max_depth": float(depth[feed].max(initial=0.0)), "removed_mm3": float(removed[feed].sum()),
                "air_length": float(ds[feed & (depth < air_eps)].sum()), "rapid_volume": float(removed[rapid].sum()),
                "layers": layers}

    def clearance_over(self, z_surface: np.ndarray, part: np.ndarray | None = None) -> tuple[float, float]:
        """(min, max) of stock height minus surface height over the cells the surface covers
        (``part``: only those cells, e.g. the ones on a trimmed face's footprint)."""
        inside = np.isfinite(z_surface) & (True if part is None else part)
        left = self.h[inside] - z_surface[inside]
        return float(left.min()), float(left.max())
