"""Contour-parallel z-level roughing (the commercial baseline Abbas compares against).

At each flat level z (``layers.z_levels``) the flat end mill's axis may go wherever the floor
F <= z (``layers.floor_field`` already holds the tool radius and the allowance, and holds for
the whole cell around each cell centre); that region is the slice. A commercial contour
roughing takes the slice's boundary from the surface itself, a smooth curve, not a staircase
of grid cells; here it is the level set of the floor interpolated between the cell centres
(``slice_region``: marching squares, contourpy's filled contours), taken on the floor raised
to its 3 x 3 neighbourhood maximum so that the smooth slice lies inside the union of the
cells where F <= z (``cell_region``): wherever the interpolated, raised floor is <= z, one
corner of that grid square has all its neighbours at F <= z, so the whole square is covered
by safe cells. The slice is then at most about a cell and a half inside the staircase; a
pocket of cells the raised floor misses altogether (the deepest level's few cells) keeps its
cells.

Its boundary is the first contour; the next ones are the slice offset inward by the
step-over, again and again, until nothing is left (shapely's ``buffer`` with a negative
distance, round joins: every point of offset k lies k step-overs from the slice boundary;
Clipper2 through pyclipr would do the same offsets; shapely is chosen because the slice also
needs unions and containment tests, which it has in one library). Contours are cut from the
outside in, each ring closed; the next ring is reached by a straight cutting move when that
move stays inside the slice, else by a retract, a rapid and a plunge (``zigzag._Builder``).
"""

from __future__ import annotations

import contourpy
import numpy as np
from scipy import ndimage
from shapely.geometry import LineString, MultiPolygon, Polygon, box
from shapely.ops import unary_union

from ..export.toolpath import Tool, Toolpath
from .layers import Grid
from .zigzag import _Builder, _runs


def cell_region(grid: Grid, floor: np.ndarray, z: float, only: np.ndarray | None = None):
    """The union of the cells whose floor F <= z (a shapely geometry): where the tool may go
    (``only``: of these cells (ny, nx) bool)."""
    ok = floor <= z + 1e-9
    if only is not None:
        ok &= only
    h = 0.5 * grid.cell
    boxes = [box(grid.xs[a] - h, grid.ys[r] - h, grid.xs[e - 1] + h, grid.ys[r] + h)
             for r in range(len(grid.ys)) for a, e in _runs(ok[r])]
    return unary_union(boxes).simplify(1e-9) if boxes else Polygon()


def raised_floor(floor: np.ndarray) -> np.ndarray:
    """The floor raised to the maximum over each cell's 3 x 3 neighbourhood (module docstring)."""
    return ndimage.maximum_filter(floor, size=3, mode="nearest")


def slice_region(grid: Grid, floor: np.ndarray, z: float, raised: np.ndarray | None = None):
    """The smooth slice at level z (module docstring): the filled level set {G <= z} of the
    raised floor G (``raised_floor``; pass it to reuse it between levels), linearly
    interpolated between the cell centres, as shapely polygons with their holes."""
    g = raised_floor(floor) if raised is None else raised
    polys = []
    if len(grid.xs) >= 2 and len(grid.ys) >= 2 and g.min() <= z:
        gen = contourpy.contour_generator(grid.xs, grid.ys, g, fill_type=contourpy.FillType.OuterOffset)
        points, offsets = gen.filled(float(g.min()) - 1.0, float(z))
        for pts, off in zip(points, offsets):
            rings = [pts[a:b] for a, b in zip(off[:-1], off[1:])]
            poly = Polygon(rings[0], rings[1:])
            polys.append(poly if poly.is_valid else poly.buffer(0))
    # a pocket of cells too small for the raised floor (no cell of it has G <= z: the smooth
    # slice misses it, and only it) keeps its cells, as a contour roughing would cut it
    labels, n = ndimage.label(floor <= z + 1e-9)
    if n:
        hit = np.zeros(n + 1, bool)
        hit[labels[g <= z]] = True
        missed = ~hit[labels] & (labels > 0)
        if missed.any():
            polys.append(cell_region(grid, floor, z, missed))
    return unary_union(polys) if polys else Polygon()


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
    raised = raised_floor(floor)
    for j, z in enumerate(levels):
        region = slice_region(grid, floor, z, raised)
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
