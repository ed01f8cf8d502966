"""Contour-parallel z-level roughing (the commercial baseline Abbas compares against).

At each flat level z (``layers.z_levels``) the flat end mill's axis may go wherever the floor
F <= z (``layers.floor_field`` already holds the tool radius and the allowance); that region
is the slice. Its boundary is the first contour; the next ones are the slice offset inward by
the step-over, again and again, until nothing is left (shapely's ``buffer`` with a negative
distance, round joins: every point of offset k lies k step-overs from the slice boundary;
Clipper2 through pyclipr would do the same offsets; shapely is
chosen because the slice also needs the union of the grid cells and containment tests, which
it has in one library). Contours are cut from the outside in, each ring closed; the next
ring is reached by a straight cutting move when that move stays inside the slice, else by a
retract, a rapid and a plunge (``zigzag._Builder``).
"""

from __future__ import annotations

import numpy as np
from shapely.geometry import LineString, MultiPolygon, Polygon, box
from shapely.ops import unary_union

from ..export.toolpath import Tool, Toolpath
from .layers import Grid
from .zigzag import _Builder, _runs


def slice_region(grid: Grid, floor: np.ndarray, z: float):
    """The slice at level z: the union of the cells whose floor F <= z (a shapely geometry)."""
    ok = floor <= z + 1e-9
    h = 0.5 * grid.cell
    boxes = [box(grid.xs[a] - h, grid.ys[r] - h, grid.xs[e - 1] + h, grid.ys[r] + h)
             for r in range(len(grid.ys)) for a, e in _runs(ok[r])]
    return unary_union(boxes).simplify(1e-9) if boxes else Polygon()


def _polygons(g) -> list[Polygon]:
    if g.is_empty:
        return []
    if isinstance(g, Polygon):
        return [g]
    if isinstance(g, MultiPolygon):
        return list(g.geoms)
    return [p for p in getattr(g, "geoms", []) if isinstance(p, Polygon)]


def offset_rings(region, stepover: float, max_rings: int = 10000) -> list[list[np.ndarray]]:
    """Per offset k the closed rings (each (m, 2)) of the slice offset inward by d_k: d_0 = 0
    (the slice itself), d_k = k x stepover while that leaves something; then one more ring at
    half a step-over past the last one, if anything is left there (the core between the last
    ring and the middle of the slice, which a full step would skip)."""
    out, distances = [], []
    d, half = 0.0, False
    while len(out) < max_rings:
        g = region if d == 0 else region.buffer(-d, join_style="round", quad_segs=16)
        polys = _polygons(g)
        if not polys:
            if half or not out:
                break
            d, half = d - 0.5 * stepover, True
            continue
        rings = []
        for p in polys:
            rings.append(np.asarray(p.exterior.coords))
            rings += [np.asarray(i.coords) for i in p.interiors]
        out.append(rings)
        distances.append(d)
        if half:
            break
        d += stepover
    return out


def contour_path(grid: Grid, floor: np.ndarray, levels: np.ndarray, tool: Tool, stepover: float, *,
                 z_top: float, safe_z: float, feed: float, plunge_feed: float, tolerance: float = 0.01,
                 comments=()) -> Toolpath:
    """Contour-parallel rings at each level (module docstring); level j as section j."""
    b = _Builder(safe_z)
    for j, z in enumerate(levels):
        region = slice_region(grid, floor, z)
        if region.is_empty:
            continue
        inside_region = region.buffer(1e-6)
        last = None
        for rings in offset_rings(region, stepover):
            for ring in rings:
                pts = np.column_stack([ring, np.full(len(ring), z)])
                if last is not None and inside_region.contains(LineString([last[:2], pts[0, :2]])):
                    b.cut(np.vstack([last[None], pts[:1]])[1:], j, tolerance)
                else:
                    if last is not None:
                        b.retract()
                    b.enter(pts[0], j, z_top if j == 0 else levels[j - 1])
                b.cut(pts[1:], j, tolerance)
                last = pts[-1]
        if last is not None:
            b.retract()
    return b.build("roughing (contour-parallel z-level)", tool, feed, plunge_feed, comments)
