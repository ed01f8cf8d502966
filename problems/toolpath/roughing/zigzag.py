"""Zig-zag roughing paths of a flat end mill over the layers of ``layers.py``.

Raster lines run along X, spaced in Y by at most the step-over, the first and last on the
stock's edges (so the tool sweeps the whole block). Along a line the tool's axis passes over
every cell centre; its bottom (the CL tip) is the layer's height there. Both methods start a
layer with a rapid to ``safe_z`` above its first point, a rapid down to 1 mm above the
material left there by the previous layer, and a plunge at the plunge feed; they end it with
a rapid retract to ``safe_z``.

- Morphing: every line of a layer is cut whole; consecutive lines are linked along the
  stock's edge column at the layer's heights (cutting moves).
- Z-level: a line of level z is cut only where the floor F <= z (runs); the next run is
  reached by a cutting move at z when the straight link stays where F <= z and takes no
  more than D_cut from the stock the levels above left (probed on a Z-map: a link may cross
  material no raster line of the level above reached), else by a retract to ``safe_z``, a
  rapid, and a plunge.

Points along straight stretches are thinned (``toolpath.drop_collinear``, within
``tolerance``) so that NC size reflects the path's shape, not the grid.
"""

from __future__ import annotations

import math

import numpy as np

from ..export.toolpath import Tool, Toolpath, drop_collinear
from .layers import Grid


def raster_rows(grid: Grid, stepover: float) -> np.ndarray:
    """Grid rows of the raster lines: equally spaced from the first to the last row, gaps
    <= ``stepover``."""
    ny = len(grid.ys)
    span = (ny - 1) * grid.cell
    n = int(math.ceil(span / stepover - 1e-9)) + 1 if span > 0 else 1
    return np.unique(np.round(np.linspace(0, ny - 1, n)).astype(int))


class _Builder:
    def __init__(self, safe_z: float, gap: float = 1.0):
        self.safe_z, self.gap = safe_z, gap
        self.pts, self.rapid, self.plunge, self.section = [], [], [], []

    def _add(self, p, rapid, plunge, section):
        p = np.atleast_2d(p)
        self.pts.append(p)
        self.rapid.append(np.full(len(p), rapid))
        self.plunge.append(np.full(len(p), plunge))
        self.section.append(np.full(len(p), section))

    def enter(self, p, section, material):
        """Rapid up to safe_z, over p, down to ``gap`` above the material there, plunge to p."""
        if self.pts:
            last = self.pts[-1][-1]
            if last[2] < self.safe_z:
                self._add([last[0], last[1], self.safe_z], True, False, -1)
        self._add([p[0], p[1], self.safe_z], True, False, -1)
        self._add([p[0], p[1], min(material + self.gap, self.safe_z)], True, False, -1)
        self._add(p, False, True, section)

    def cut(self, p, section, tolerance):
        p = np.atleast_2d(p)
        self._add(p[drop_collinear(p, tolerance)] if len(p) > 2 else p, False, False, section)

    def retract(self):
        last = self.pts[-1][-1]
        self._add([last[0], last[1], self.safe_z], True, False, -1)

    def build(self, name, tool, feed, plunge_feed, comments) -> Toolpath:
        tip = np.vstack(self.pts)
        axis = np.tile([0.0, 0.0, 1.0], (len(tip), 1))
        return Toolpath(name, tool, tip, axis, np.concatenate(self.rapid), np.concatenate(self.plunge),
                        np.concatenate(self.section), feed, plunge_feed, section_label="LAYER",
                        comments=list(comments))


def _line(grid, row, heights, reverse):
    cols = np.arange(len(grid.xs))[::-1] if reverse else np.arange(len(grid.xs))
    return np.column_stack([grid.xs[cols], np.full(len(cols), grid.ys[row]), heights[cols]]), cols


def morph_path(grid: Grid, layers: np.ndarray, tool: Tool, stepover: float, *, z_top: float, safe_z: float,
               feed: float, plunge_feed: float, tolerance: float = 0.01, comments=()) -> Toolpath:
    """Zig-zag over each morphing layer (N, ny, nx) in turn, layer k as section k."""
    rows = raster_rows(grid, stepover)
    b = _Builder(safe_z)
    for k, h in enumerate(layers):
        pts = []
        for n, row in enumerate(rows):
            line, cols = _line(grid, row, h[row], reverse=n % 2 == 1)
            pts.append(line)
            if n + 1 < len(rows):  # link along the edge column to the next line
                between = np.arange(row + 1, rows[n + 1])
                c = cols[-1]
                pts.append(np.column_stack([np.full(len(between), grid.xs[c]), grid.ys[between], h[between, c]]))
        pts = np.vstack(pts)
        b.enter(pts[0], k, z_top if k == 0 else grid.local_max(layers[k - 1], rows[0], 0, 0.5 * tool.diameter + grid.cell))
        b.cut(pts[1:], k, tolerance)
        b.retract()
    return b.build("roughing (morphing layers)", tool, feed, plunge_feed, comments)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) index pairs of the True runs of a 1-D mask."""
    d = np.diff(np.r_[0, mask.astype(np.int8), 0])
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


def zlevel_path(grid: Grid, floor: np.ndarray, levels: np.ndarray, tool: Tool, stepover: float, *,
                z_top: float, safe_z: float, feed: float, plunge_feed: float, tolerance: float = 0.01,
                d_cut: float | None = None, comments=()) -> Toolpath:
    """Zig-zag at each flat level (N,), only where floor <= level; level j as section j.
    A direct link must also take no more than ``d_cut`` from the stock left by the levels
    above (probed on a Z-map), else the tool retracts."""
    from .zmap import StockZMap

    rows = raster_rows(grid, stepover)
    b = _Builder(safe_z)
    stock = StockZMap(grid, z_top)
    limit = d_cut if d_cut is not None else np.inf
    radius = 0.5 * tool.diameter
    for j, z in enumerate(levels):
        start = sum(len(p) for p in b.pts)
        ok = floor <= z + 1e-9
        inside = False  # the tool is down at this level
        for n, row in enumerate(rows):
            reverse = n % 2 == 1
            order = np.arange(len(grid.xs))[::-1] if reverse else np.arange(len(grid.xs))
            for a, e in _runs(ok[row, order]):
                cols = order[a:e]
                run = np.column_stack([grid.xs[cols], np.full(len(cols), grid.ys[row]), np.full(len(cols), z)])
                link = _link(grid, b.pts[-1][-1], run[0], z) if inside else None
                if inside and _link_clear(grid, ok, link) and \
                        stock.probe(np.vstack([b.pts[-1][-1:], link]), radius) <= limit + 1e-9:
                    b.cut(link, j, tolerance)
                else:
                    b.enter(run[0], j, z_top if j == 0 else levels[j - 1])
                if len(run) > 1:
                    b.cut(run[1:], j, tolerance)
                inside = True
        if inside:
            b.retract()
            stock.stamp(np.vstack(b.pts)[start:], radius)
    return b.build("roughing (z-level)", tool, feed, plunge_feed, comments)


def _link(grid, p, q, z):
    n = max(2, int(math.ceil(np.hypot(*(q[:2] - p[:2])) / grid.cell)) + 1)
    t = np.linspace(0, 1, n)[1:, None]
    out = p + t * (q - p)
    out[:, 2] = z
    return out


def _link_clear(grid, ok, link) -> bool:
    r, c = grid.index(*link[:, :2].T)
    return bool(ok[r, c].all())
